// render.mjs: the test page's script. window.vdbgiRun(task) loads task.scene
// and task.gi with web/ (WebGL2 or WebGPU) and does one of:
//   probe:  render the probe-colour view (per fragment) and the world
//           positions into float targets; return both for covered pixels;
//   shot:   draw the scene lit, GI off or on, into the canvas;
//   frames: time task.frames frames with GI off, per vertex, per fragment;
//   load:   only load (task.worker: loadGi's option), and report the error a bad
//           file gives, or with task.digest a hash of the textures' bytes; with
//           task.animate, a game's frames run meanwhile (8 ms of work each) and
//           `fps` says how many it drew a second;
//   boundsSetup, boundsLoad, boundsDraw: tests/web/check_bounds.mjs's steps;
//   split: GiRuntime.lightScene() against the recipe by hand (tests/web/check_split.mjs);
//   occlude: a 10 m floor lit only by a flat lightmap or by task.gi, with and
//           without task.occluders: the world positions and both frames;
//   grid:   task.scene lit only by task.gi, through our runtime per fragment and
//           through three's own light probe grid filled from it (makeProbeGrid);
//           with task.frames, the median frame of each and of neither instead.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { GiRuntime, loadGi, DebugView } from '/web/vdbgi.js';

// The benchmarks load our own big worlds (the town's L2 textures pass loadGi's default
// budget); only the bounds tasks keep the defaults.
const OWN_WORLDS = 2 ** 31;

async function makeRenderer(backend, canvas, width, height) {
  if (backend === 'webgpu') {
    const { WebGPURenderer } = await import('three/webgpu');
    const r = new WebGPURenderer({ canvas, antialias: false, forceWebGL: false });
    await r.init();
    if (!r.backend.isWebGPUBackend) throw new Error('no WebGPU adapter: the renderer fell back to WebGL');
    r.setSize(width, height, false);
    return r;
  }
  const r = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
  r.setSize(width, height, false);
  return r;
}

// A WebGL renderer's dispose() keeps its context until the page collects it, and
// Chromium loses the oldest past 16 with a warning: a bench's many loads on one
// page reach that, so each task gives its context back.
function release(renderer) {
  renderer.dispose();
  if (renderer.isWebGLRenderer) renderer.forceContextLoss();
}

// The demo world's camera and the bake's lights (gi-bake's defaults: sun
// towards 0.4,0.8,0.3, ambient 0.15; three's Lambert divides by pi).
function stage(scene, width, height) {
  const camera = new THREE.PerspectiveCamera(50, width / height, 0.1, 500);
  camera.position.set(26, 17, 30);
  camera.lookAt(0, 1, 0);
  const sun = new THREE.DirectionalLight(0xffffff, Math.PI);
  sun.position.set(0.4, 0.8, 0.3).multiplyScalar(50);
  const ambient = new THREE.AmbientLight(0xffffff, 0.15 * Math.PI);
  scene.add(sun, ambient);
  return { camera, lights: [sun, ambient] };
}

// A canvas keeps the first kind of context it gave: each run gets a new one.
function freshCanvas() {
  const old = document.getElementById('c');
  const canvas = Object.assign(document.createElement('canvas'), { id: 'c' });
  old.replaceWith(canvas);
  return canvas;
}

async function setup(task) {
  const canvas = freshCanvas();
  const { width = 256, height = 256, backend = 'webgl' } = task;
  const renderer = await makeRenderer(backend, canvas, width, height);
  const gltf = await new GLTFLoader().loadAsync(task.scene);
  const scene = gltf.scene;
  const { camera, lights } = stage(scene, width, height);
  const webgpu = backend === 'webgpu' ? await import('/web/vdbgi-webgpu.js') : null;
  const gi = webgpu ? new webgpu.GiRuntime() : new GiRuntime();
  const t0 = performance.now();
  const volume = await loadGi(task.gi, { renderer: backend === 'webgl' ? renderer : null, maxBytes: OWN_WORLDS });
  const loadMs = performance.now() - t0;
  gi.setVolume(volume);
  const meshes = [];
  scene.traverse((o) => o.isMesh && meshes.push(o));
  // Each material in two variants, per vertex and per fragment, swapped by mode().
  const variants = new Map();
  for (const m of meshes) {
    if (variants.has(m.material)) continue;
    const make = (perFragment) => gi.apply(m.material.clone(), { perFragment });
    variants.set(m.material, { vertex: make(false), fragment: make(true) });
  }
  const originals = meshes.map((m) => m.material);
  const mode = (which) => meshes.forEach((m, i) => { m.material = variants.get(originals[i])[which]; });
  return { renderer, scene, camera, lights, gi, volume, loadMs, mode, width, height, backend };
}

async function readFloat(ctx, view = DebugView.OFF) {
  const { renderer, scene, camera, gi, width, height, backend } = ctx;
  const rt = new (backend === 'webgpu' ? (await import('three/webgpu')).RenderTarget : THREE.WebGLRenderTarget)(
    width, height, { type: THREE.FloatType, format: THREE.RGBAFormat, minFilter: THREE.NearestFilter,
      magFilter: THREE.NearestFilter, depthBuffer: true });
  gi.debug = view;
  renderer.setClearColor(0x000000, 0);
  renderer.setRenderTarget(rt);
  renderer.clear();
  renderer.render(scene, camera);
  renderer.setRenderTarget(null);
  const px = backend === 'webgpu' ? await renderer.readRenderTargetPixelsAsync(rt, 0, 0, width, height)
                                  : (() => {
                                    const a = new Float32Array(width * height * 4);
                                    renderer.readRenderTargetPixels(rt, 0, 0, width, height, a);
                                    return a;
                                  })();
  rt.dispose();
  gi.debug = DebugView.OFF;
  return px;
}

async function probe(task) {
  const ctx = await setup(task);
  ctx.mode('fragment');
  const pos = await readFloat(ctx, DebugView.POSITION);
  const normal = await readFloat(ctx, DebugView.NORMAL);
  const irr = await readFloat(ctx, DebugView.PROBE);
  const level = await readFloat(ctx, DebugView.LEVEL);
  const bricks = await readFloat(ctx, DebugView.BRICKS);
  // Lit by GI alone (the lights kept at zero: a node material with no light
  // at all would show its albedo), with the physical knobs and with task.knobs.
  for (const l of ctx.lights) l.intensity = 0;
  const physical = await readFloat(ctx);
  ctx.gi.setKnobs('world', task.knobs ?? { intensity: 1, self: 1, bleed: 0 });
  const styled = await readFloat(ctx);
  // Half metal: a standard material reflects the bounce with albedo x (1 - metalness).
  ctx.gi.setKnobs('world', { intensity: 1, self: 1, bleed: 0 });
  const materials = new Set();
  ctx.scene.traverse((o) => o.isMesh && materials.add(o.material));
  for (const m of materials) m.metalness = 0.5;
  const halfMetal = await readFloat(ctx);
  const covered = [];
  for (let i = 0; i < ctx.width * ctx.height; i++) if (pos[4 * i + 3] === 1) covered.push(i);
  // The brick-boundary view darkens only the lines between bricks: lit pixels it paints black.
  let lit = 0, blackened = 0;
  for (const i of covered) {
    if (irr[4 * i] + irr[4 * i + 1] + irr[4 * i + 2] <= 0) continue;
    lit++;
    blackened += bricks[4 * i] + bricks[4 * i + 1] + bricks[4 * i + 2] <= 0;
  }
  const want = Math.min(task.points ?? 400, covered.length);
  const points = [];
  // The world position a pixel reports must project back onto that pixel's
  // centre: a wrong position (a missing model matrix) would fool the
  // comparison with the C sampler, which reads the same position.
  let offPixel = 0;
  const v = new THREE.Vector3();
  for (let k = 0; k < want; k++) {
    const i = covered[Math.floor((k + 0.5) * covered.length / want)];
    v.set(pos[4 * i], pos[4 * i + 1], pos[4 * i + 2]).project(ctx.camera);
    const x = (v.x + 1) / 2 * ctx.width;
    const y = (ctx.backend === 'webgpu' ? 1 - v.y : v.y + 1) / 2 * ctx.height; // readback rows
    offPixel = Math.max(offPixel, Math.hypot(x - (i % ctx.width + 0.5), y - (Math.floor(i / ctx.width) + 0.5)));
    points.push({ pixel: i, pos: Array.from(pos.subarray(4 * i, 4 * i + 3)),
      normal: Array.from(normal.subarray(4 * i, 4 * i + 3)),
      irr: Array.from(irr.subarray(4 * i, 4 * i + 3)), level: Array.from(level.subarray(4 * i, 4 * i + 3)),
      physical: Array.from(physical.subarray(4 * i, 4 * i + 3)), styled: Array.from(styled.subarray(4 * i, 4 * i + 3)),
      halfMetal: Array.from(halfMetal.subarray(4 * i, 4 * i + 3)) });
  }
  return { covered: covered.length, pixels: ctx.width * ctx.height, points, offPixel, header: headerOf(ctx.volume),
    bricksView: { lit, blackened } };
}

function headerOf(volume) {
  const h = volume.info;
  return { layout: h.layout, encoding: h.encoding, bricks: h.bricks, vramBytes: volume.vramBytes,
    timings: volume.timings };
}

async function shot(task) {
  const ctx = await setup(task);
  ctx.renderer.outputColorSpace = THREE.SRGBColorSpace;
  ctx.scene.background = new THREE.Color(0.55, 0.7, 0.9);
  ctx.mode(task.perFragment ? 'fragment' : 'vertex');
  ctx.gi.enabled = task.gi_on !== false;
  ctx.renderer.render(ctx.scene, ctx.camera);
  if (ctx.backend === 'webgpu') await ctx.renderer.backend.device?.queue.onSubmittedWorkDone();
  return { header: headerOf(ctx.volume) };
}

// Frame time of each mode, drawn into an 8-bit target; the GPU finishes
// every frame before the next (one pixel read back).
async function frames(task) {
  const ctx = await setup(task);
  const RT = ctx.backend === 'webgpu' ? (await import('three/webgpu')).RenderTarget : THREE.WebGLRenderTarget;
  const rt = new RT(ctx.width, ctx.height, { depthBuffer: true });
  const one = new Uint8Array(4);
  ctx.renderer.setRenderTarget(rt);
  const finish = ctx.backend === 'webgpu' ? () => ctx.renderer.readRenderTargetPixelsAsync(rt, 0, 0, 1, 1)
                                          : () => ctx.renderer.readRenderTargetPixels(rt, 0, 0, 1, 1, one);
  const time = async (setMode) => {
    setMode();
    for (let i = 0; i < 3; i++) ctx.renderer.render(ctx.scene, ctx.camera);
    await finish();
    const t = performance.now();
    for (let i = 0; i < task.frames; i++) {
      ctx.renderer.render(ctx.scene, ctx.camera);
      await finish();
    }
    return (performance.now() - t) / task.frames;
  };
  const out = {};
  // With task.occluders, as many spheres of 0.8 m over the middle of the world, added for
  // the last two modes (every lit fragment tests them all).
  const occlude = () => {
    for (let i = 0; i < task.occluders; i++) {
      const o = new THREE.Object3D();
      o.position.set(-8 + 16 * ((i % 4) + 0.5) / 4, 1.2, -8 + 16 * (Math.floor(i / 4) % 4 + 0.5) / 4);
      o.updateMatrixWorld();
      ctx.gi.addOccluder(o, { capsules: [{ a: [0, 0, 0], radius: 0.8 }] });
    }
  };
  // The second round is kept: the first also compiles and warms caches.
  for (let round = 0; round < 2; round++) {
    out.off = await time(() => { ctx.mode('vertex'); ctx.gi.enabled = false; });
    out.vertex = await time(() => { ctx.mode('vertex'); ctx.gi.enabled = true; });
    out.fragment = await time(() => { ctx.mode('fragment'); ctx.gi.enabled = true; });
  }
  if (task.occluders) {
    occlude(); // the same programs: only uniforms change, so one round
    out.vertexOccluded = await time(() => { ctx.mode('vertex'); ctx.gi.enabled = true; });
    out.fragmentOccluded = await time(() => { ctx.mode('fragment'); ctx.gi.enabled = true; });
  }
  ctx.renderer.setRenderTarget(null);
  rt.dispose();
  return out;
}

// FNV-1a over the bytes the textures upload, with each one's size: equal digests, equal textures.
function texturesDigest(textures) {
  let h = 0x811c9dc5;
  for (const t of textures) {
    const d = t.image.data, b = new Uint8Array(d.buffer, d.byteOffset, d.byteLength);
    for (let i = 0; i < b.length; i++) h = Math.imul(h ^ b[i], 0x01000193);
    h = Math.imul(h ^ b.length, 0x01000193);
  }
  return `${textures.length} textures, FNV-1a ${(h >>> 0).toString(16).padStart(8, '0')}`;
}

async function load(task) {
  const canvas = freshCanvas();
  const renderer = await makeRenderer('webgl', canvas, 64, 64);
  // The page's long tasks (50 ms or more) while loadGi runs: the longest is what a game stutters by.
  const tasks = [];
  const observer = new PerformanceObserver((list) => tasks.push(...list.getEntries().map((e) => e.duration)));
  observer.observe({ type: 'longtask' });
  try {
    const t0 = performance.now();
    let frames = 0, animating = !!task.animate;
    const frame = () => {
      if (!animating) return;
      frames++;
      for (const t = performance.now(); performance.now() - t < 8;); // the game's own work
      requestAnimationFrame(frame);
    };
    if (animating) requestAnimationFrame(frame);
    const v = await loadGi(task.gi, { renderer, maxBytes: OWN_WORLDS, worker: task.worker ?? 'auto' });
    const wall = performance.now() - t0;
    animating = false;
    await new Promise((resolve) => setTimeout(resolve, 0));
    for (const e of observer.takeRecords()) tasks.push(e.duration);
    const digest = task.digest ? texturesDigest([v.columns, v.atlas, ...(v.sh ?? [])]) : undefined;
    v.dispose();
    return { ok: true, timings: v.timings, vramBytes: v.vramBytes, fileBytes: v.fileBytes, wall,
      longestTask: Math.max(0, ...tasks), longTasks: tasks.length, digest,
      fps: task.animate ? 1000 * frames / wall : undefined };
  } catch (e) {
    return { ok: false, error: e.message };
  } finally {
    observer.disconnect();
    release(renderer);
  }
}

// The floor seen from straight above, orthographic, 128 x 128 pixels over 8 x 8 m,
// lit by the indirect light alone: a flat lightmap (volume: false) or the volume
// (per fragment). The occluders are hidden meshes: a sphere, or an object with
// capsules. Frames without and with them, and the positions, as floats.
async function occlude(task) {
  const canvas = freshCanvas();
  const { backend = 'webgl', width = 128, height = 128 } = task;
  const renderer = await makeRenderer(backend, canvas, width, height);
  const webgpu = backend === 'webgpu' ? await import('/web/vdbgi-webgpu.js') : null;
  const gi = webgpu ? new webgpu.GiRuntime() : new GiRuntime();
  const lightmap = !task.gi;
  if (!lightmap) gi.setVolume(await loadGi(task.gi, { renderer: backend === 'webgl' ? renderer : null, maxBytes: OWN_WORLDS }));
  const scene = new THREE.Scene();
  const floor = new THREE.Mesh(new THREE.PlaneGeometry(10, 10).rotateX(-Math.PI / 2),
    new THREE.MeshLambertMaterial({ color: 0xffffff }));
  if (lightmap) {
    const map = new THREE.DataTexture(new Float32Array([1, 1, 1, 1]), 1, 1, THREE.RGBAFormat, THREE.FloatType);
    map.channel = 0;
    map.needsUpdate = true;
    floor.material.lightMap = map;
  }
  floor.material = gi.apply(floor.material, { volume: !lightmap, perFragment: true });
  scene.add(floor);
  const camera = new THREE.OrthographicCamera(-4, 4, 4, -4, 0.1, 50);
  camera.position.set(0, 20, 0);
  camera.up.set(0, 0, -1);
  camera.lookAt(0, 0, 0);
  const ctx = { renderer, scene, camera, gi, width, height, backend };
  const pos = await readFloat(ctx, DebugView.POSITION);
  const before = await readFloat(ctx);
  for (const o of task.occluders) {
    const holder = o.sphere
      ? new THREE.Mesh(new THREE.SphereGeometry(o.sphere.radius, 48, 24), new THREE.MeshBasicMaterial())
      : new THREE.Object3D();
    if (o.sphere) holder.position.set(...o.sphere.center);
    holder.visible = false;
    scene.add(holder);
    holder.updateMatrixWorld(true);
    gi.addOccluder(holder, o.capsules ? { capsules: o.capsules } : {});
  }
  const after = await readFloat(ctx);
  let refused = null;
  try {
    for (let i = 0; i < 17; i++) gi.addOccluder(new THREE.Object3D(), { capsules: [{ a: [0, 0, 0], radius: 1 }] });
  } catch (e) {
    refused = e.message;
  }
  release(renderer);
  const pick = (a) => Array.from({ length: width * height }, (_, i) => a[4 * i]);
  return { pos: Array.from(pos), before: pick(before), after: pick(after), refused };
}

// A player's view, as tests/truth/frame_vs_cycles.sh compares it with Cycles: the
// statics of task.scene as diffuse (Lambert) surfaces lit by their gi-lightmap maps
// (task.lightmap: a .glb from gi-lightmap) or by the volume (per vertex or per
// fragment), task.spheres (the moving objects, not in the bake) lit by the volume
// per fragment and, with task.occluders, taking baked light away; task.lamps as
// three's point lights (candela) with shadows, task.sky as the background. Linear
// radiance and world positions (w 0 where no surface) as floats, rows from the bottom.
async function frame(task) {
  const canvas = freshCanvas();
  const { width, height } = task.camera;
  const renderer = await makeRenderer('webgl', canvas, width, height);
  renderer.outputColorSpace = THREE.LinearSRGBColorSpace;
  renderer.toneMapping = THREE.NoToneMapping;
  renderer.shadowMap.enabled = true;
  renderer.shadowMap.type = THREE.PCFShadowMap;
  const gi = new GiRuntime();
  const figures = {};
  if (task.gi) {
    const t0 = performance.now();
    gi.setVolume(await loadGi(task.gi, { renderer, maxBytes: OWN_WORLDS }));
    figures.loadMs = performance.now() - t0;
  }
  const gltf = await new GLTFLoader().loadAsync(task.lightmap ?? task.scene);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(...task.sky);
  const jobs = [];
  gltf.scene.traverse((o) => {
    if (!o.isMesh) return;
    const lm = o.material.userData.vdbgi_lightmap;
    const m = new THREE.MeshLambertMaterial({ color: o.material.color, map: o.material.map,
      vertexColors: o.material.vertexColors, side: o.material.side });
    o.material = m;
    o.castShadow = o.receiveShadow = true;
    if (task.lightmap && lm)
      jobs.push(gltf.parser.getDependency('texture', lm.texture).then((t) => {
        t.colorSpace = THREE.SRGBColorSpace; // the PNG holds sRGB-encoded E / scale
        t.channel = lm.texCoord;
        m.lightMap = t;
        m.lightMapIntensity = lm.scale;
      }));
  });
  await Promise.all(jobs);
  // The task's lamps (below, with shadow maps) are the scene's lights: a glTF's own
  // (KHR_lights_punctual, which make_scenes.py --room writes) would light it twice.
  const gltfLights = [];
  gltf.scene.traverse((o) => { if (o.isLight) gltfLights.push(o); });
  for (const l of gltfLights) l.removeFromParent();
  // perFragment 'auto': as light() chooses (per fragment where a mesh's triangles are large).
  if (task.perFragment === 'auto' && !task.lightmap) gi.light(gltf.scene);
  else gltf.scene.traverse((o) => {
    if (o.isMesh) o.material = gi.apply(o.material, { volume: !task.lightmap, perFragment: !!task.perFragment });
  });
  scene.add(gltf.scene);
  for (const s of task.spheres ?? []) {
    const ball = new THREE.Mesh(new THREE.SphereGeometry(s.radius, 96, 48),
      gi.apply(new THREE.MeshLambertMaterial({ color: new THREE.Color(...s.albedo) }), { set: 'character', perFragment: true }));
    ball.position.set(...s.center);
    ball.castShadow = ball.receiveShadow = true;
    scene.add(ball);
    ball.updateMatrixWorld();
    if (task.occluders) gi.addOccluder(ball);
  }
  for (const l of task.lamps) {
    const lamp = new THREE.PointLight(new THREE.Color(...l.color), l.intensity, 0, 2);
    lamp.position.set(...l.position);
    lamp.castShadow = true;
    lamp.shadow.mapSize.set(2048, 2048);
    lamp.shadow.camera.near = 0.05;
    lamp.shadow.bias = -0.0005;
    scene.add(lamp);
  }
  // The bakers' sun (its colour is E / pi, so three's irradiance is pi times it), with a
  // shadow map over the bundled world's 48 m.
  if (task.sun) {
    const sun = new THREE.DirectionalLight(new THREE.Color(...task.sun.color), Math.PI);
    sun.position.set(...task.sun.direction).normalize().multiplyScalar(60);
    sun.castShadow = true;
    sun.shadow.mapSize.set(4096, 4096);
    Object.assign(sun.shadow.camera, { left: -36, right: 36, top: 36, bottom: -36, near: 1, far: 150 });
    sun.shadow.bias = -0.0005;
    scene.add(sun);
  }
  // Three's own light probe grid over task.grid.box at task.grid.spacing: baked in the
  // page with task.grid.bounces extra passes (the moving spheres hidden: they are not
  // in a bake), or with task.grid.fromVolume filled from task.gi (makeProbeGrid).
  if (task.grid) {
    const { LightProbeGridWebGL } = await import('three/addons/lighting/LightProbeGridWebGL.js');
    const { min, max } = task.grid.box, s = task.grid.spacing;
    const res = min.map((v, k) => Math.max(1, Math.round((max[k] - v) / s)));
    let grid;
    const t0 = performance.now();
    if (task.grid.fromVolume) {
      const { makeProbeGrid } = await import('/web/gi-probe-grid.js');
      grid = makeProbeGrid(gi.volume, LightProbeGridWebGL, { box: task.grid.box, spacing: s });
    } else {
      grid = new LightProbeGridWebGL(...max.map((v, k) => v - min[k]), ...res);
      grid.position.set(...min.map((v, k) => (v + max[k]) / 2));
      scene.add(grid);
      const balls = scene.children.filter((o) => o.isMesh);
      balls.forEach((b) => { b.visible = false; });
      scene.updateMatrixWorld(true);
      grid.bake(renderer, scene, { bounces: task.grid.bounces ?? 0, cubemapSize: task.grid.cubemapSize ?? 8 });
      balls.forEach((b) => { b.visible = true; });
      renderer.getContext().finish();
    }
    figures.gridMs = performance.now() - t0;
    gi.enabled = false; // the grid's light alone (the debug views still read positions)
    figures.gridProbes = grid.resolution.x * grid.resolution.y * grid.resolution.z;
    if (!grid.parent) scene.add(grid);
  }
  const c = task.camera;
  const camera = new THREE.PerspectiveCamera(c.fov, width / height, 0.01, 100);
  camera.position.set(...c.position);
  camera.lookAt(...c.target);
  const ctx = { renderer, scene, camera, gi, width, height, backend: 'webgl' };
  const radiance = await readFloat(ctx);
  const pos = await readFloat(ctx, DebugView.POSITION);
  release(renderer);
  return { radiance: Array.from(radiance), pos: Array.from(pos), ...figures };
}

// Bounds (tests/web/check_bounds.mjs), in three steps the test measures apart:
// boundsSetup makes the renderer (the browser's own cost); boundsLoad loads
// task.gi with loadGi's defaults, as a game given that URL would (the error, or
// nothing); boundsDraw lights a floor with what loaded, task.floor (x0, z0, x1,
// z1, y) or the box's at its middle height, and reads the frame's mean light.
const bench = {};
async function boundsSetup(task) {
  bench.backend = task.backend ?? 'webgl';
  bench.renderer = await makeRenderer(bench.backend, freshCanvas(), 32, 32);
  bench.webgpu = bench.backend === 'webgpu' ? await import('/web/vdbgi-webgpu.js') : null;
  return {};
}

async function boundsLoad(task) {
  const t0 = performance.now();
  try {
    bench.volume = await loadGi(task.gi, { renderer: bench.webgpu ? null : bench.renderer });
    return { ok: true, ms: performance.now() - t0 };
  } catch (e) {
    return { ok: false, ms: performance.now() - t0, error: e.message };
  }
}

async function boundsDraw(task) {
  const { renderer, webgpu, volume } = bench;
  const t0 = performance.now();
  const gi = webgpu ? new webgpu.GiRuntime() : new GiRuntime();
  gi.setVolume(volume);
  const { boxMin: lo, boxMax: hi } = volume.info;
  const [x0, z0, x1, z1, y] = task.floor ?? [lo[0], lo[2], hi[0], hi[2], (lo[1] + hi[1]) / 2];
  const scene = new THREE.Scene();
  const floor = new THREE.Mesh(new THREE.PlaneGeometry(x1 - x0, z1 - z0).rotateX(-Math.PI / 2),
    gi.apply(new THREE.MeshLambertMaterial({ color: 0xffffff }), { perFragment: true }));
  floor.position.set((x0 + x1) / 2, y, (z0 + z1) / 2);
  scene.add(floor);
  const w = (x1 - x0) / 2, d = (z1 - z0) / 2;
  const camera = new THREE.OrthographicCamera(-w, w, d, -d, 0.1, 1e4);
  camera.position.set((x0 + x1) / 2, y + 1, (z0 + z1) / 2);
  camera.lookAt((x0 + x1) / 2, y, (z0 + z1) / 2);
  const px = await readFloat({ renderer, scene, camera, gi, width: 32, height: 32, backend: bench.backend });
  volume.dispose();
  release(renderer);
  // The mean light in 8-bit steps.
  return { ms: performance.now() - t0, light: (255 * px.reduce((a, v, i) => (i % 4 === 3 ? a : a + v), 0)) / (32 * 32 * 3) };
}

// split: task.scene (a gi-lightmap .glb) lit by task.gi the split way, with a sphere at
// task.hero as the moving object: by GiRuntime.lightScene(), and by the recipe
// docs/lightmap.md writes out (the maps by hand, then apply()); and unlit by either
// (the sun and ambient alone). The three frames as floats, and lightScene()'s counts.
async function split(task) {
  const { backend = 'webgl', width = 160, height = 120 } = task;
  const renderer = await makeRenderer(backend, freshCanvas(), width, height);
  const webgpu = backend === 'webgpu' ? await import('/web/vdbgi-webgpu.js') : null;
  const frame = async (light) => {
    const gi = webgpu ? new webgpu.GiRuntime() : new GiRuntime();
    gi.setVolume(await loadGi(task.gi, { renderer: webgpu ? null : renderer, maxBytes: OWN_WORLDS }));
    const gltf = await new GLTFLoader().loadAsync(task.scene);
    const { camera } = stage(gltf.scene, width, height);
    const hero = new THREE.Mesh(new THREE.SphereGeometry(1, 32, 16), new THREE.MeshStandardMaterial({ color: 0xcccccc }));
    hero.position.set(...task.hero);
    gltf.scene.add(hero);
    gltf.scene.updateMatrixWorld();
    const counts = await light(gi, gltf, hero);
    const px = await readFloat({ renderer, scene: gltf.scene, camera, gi, width, height, backend });
    gi.dispose();
    return { px: Array.from(px), counts };
  };
  const byCall = await frame((gi, gltf, hero) => gi.lightScene(gltf, { moving: [hero] }));
  const byHand = await frame(async (gi, gltf, hero) => {
    for (const mesh of gltf.scene.getObjectsByProperty('isMesh', true)) {
      if (mesh === hero) continue;
      const lm = mesh.material.userData.vdbgi_lightmap;
      if (!lm) {
        mesh.material = gi.apply(mesh.material);
        continue;
      }
      const map = await gltf.parser.getDependency('texture', lm.texture);
      map.colorSpace = THREE.SRGBColorSpace;
      map.channel = 1;
      mesh.material.lightMap = map;
      mesh.material.lightMapIntensity = lm.scale;
      mesh.material = gi.apply(mesh.material, { volume: false });
    }
    hero.material = gi.apply(hero.material, { set: 'character', perFragment: true });
    gi.addOccluder(hero);
  });
  const unlit = await frame(async (gi) => { gi.enabled = false; });
  release(renderer);
  return { byCall: byCall.px, counts: byCall.counts, byHand: byHand.px, unlit: unlit.px };
}

// No light but the bounce, so that the two frames differ only in how they read it:
// our runtime per fragment (GiRuntime.apply) and three's grid with the scene's
// materials untouched. Both frames and the grid's figures.
async function grid(task) {
  const { backend = 'webgl', width = 192, height = 144, camera: cam } = task;
  const renderer = await makeRenderer(backend, freshCanvas(), width, height);
  const webgpu = backend === 'webgpu' ? await import('/web/vdbgi-webgpu.js') : null;
  const { makeProbeGrid } = await import('/web/gi-probe-grid.js');
  const Grid = backend === 'webgpu' ? (await import('three/addons/lighting/LightProbeGrid.js')).LightProbeGrid
                                    : (await import('three/addons/lighting/LightProbeGridWebGL.js')).LightProbeGridWebGL;
  const camera = new THREE.PerspectiveCamera(cam.fov, width / height, 0.05, 100);
  camera.position.set(...cam.position);
  camera.lookAt(...cam.target);
  const volume = await loadGi(task.gi, { renderer: webgpu ? null : renderer, maxBytes: OWN_WORLDS });
  const draw = async (light) => {
    const gi = webgpu ? new webgpu.GiRuntime() : new GiRuntime();
    gi.setVolume(volume);
    const scene = (await new GLTFLoader().loadAsync(task.scene)).scene;
    const figures = await light(gi, scene);
    scene.updateMatrixWorld();
    const px = await readFloat({ renderer, scene, camera, gi, width, height, backend });
    // With task.frames: that many frames into the canvas, each waited for by reading
    // one pixel back; the median milliseconds, after a first frame that compiles.
    const ms = [];
    for (let i = 0; i <= (task.frames ?? 0); i++) {
      const t0 = performance.now();
      renderer.render(scene, camera);
      if (webgpu) await renderer.backend.device.queue.onSubmittedWorkDone();
      else renderer.getContext().readPixels(0, 0, 1, 1, renderer.getContext().RGBA, renderer.getContext().UNSIGNED_BYTE, new Uint8Array(4));
      if (i) ms.push(performance.now() - t0);
    }
    ms.sort((a, b) => a - b);
    return { px: task.frames ? [] : Array.from(px), frameMs: ms.length ? ms[ms.length >> 1] : null, ...figures };
  };
  const ours = await draw((gi, scene) => {
    scene.traverse((o) => { if (o.isMesh) o.material = gi.apply(o.material, { perFragment: true }); });
  });
  const none = task.frames ? await draw(() => ({})) : null;
  const three = await draw((gi, scene) => {
    const t0 = performance.now();
    const g = makeProbeGrid(volume, Grid);
    const fillMs = performance.now() - t0;
    scene.add(g);
    const { data } = g.texture.image;
    return { fillMs, gridBytes: data.byteLength, resolution: g.resolution.toArray(), volumeBytes: volume.vramBytes,
      spacing: volume.info.spacing };
  });
  release(renderer);
  return { ours: ours.px, three: three.px, fillMs: three.fillMs, gridBytes: three.gridBytes,
    resolution: three.resolution, volumeBytes: three.volumeBytes, spacing: three.spacing,
    frameMs: { none: none?.frameMs, ours: ours.frameMs, three: three.frameMs } };
}

// The WGSL three made for a plain standard material on a quad, and with the volume
// per fragment: how many texture reads each fragment shader holds. (Read from the
// renderer's program cache, three 0.187's private _pipelines: a test's view only.)
async function reads(task) {
  const renderer = await makeRenderer('webgpu', freshCanvas(), 16, 16);
  const { GiRuntime: GpuRuntime } = await import('/web/vdbgi-webgpu.js');
  const gi = new GpuRuntime();
  gi.setVolume(await loadGi(task.gi, { maxBytes: OWN_WORLDS }));
  const camera = new THREE.PerspectiveCamera(50, 1, 0.1, 10);
  camera.position.set(0, 0, 2);
  const count = async (material) => {
    const scene = new THREE.Scene();
    scene.add(new THREE.Mesh(new THREE.PlaneGeometry(1, 1), material));
    const before = new Set(renderer._pipelines.programs.fragment.values());
    renderer.render(scene, camera);
    const made = [...renderer._pipelines.programs.fragment.values()].filter((p) => !before.has(p));
    return made.map((p) => (p.code.match(/\btexture(Sample|Load)[A-Za-z]*\s*\(/g) ?? []).length);
  };
  const plain = await count(new THREE.MeshStandardMaterial());
  const lit = await count(gi.apply(new THREE.MeshStandardMaterial(), { perFragment: true }));
  release(renderer);
  return { plain, lit };
}

// Where three's WebGL probe grid stops: its bake renders into a 9 x N float target
// (LightProbeGridWebGL's _ensureBatchTarget), N its probe count. Make that target for
// each task.probes as the bake would and report WebGL's error, beside the largest
// texture side.
async function gridLimit(task) {
  const renderer = await makeRenderer('webgl', freshCanvas(), 16, 16);
  const gl = renderer.getContext();
  const out = { maxTextureSize: renderer.capabilities.maxTextureSize, errors: [] };
  for (const n of task.probes) {
    const rt = new THREE.WebGLRenderTarget(9, n, { type: THREE.FloatType, minFilter: THREE.NearestFilter,
      magFilter: THREE.NearestFilter, generateMipmaps: false, depthBuffer: false });
    while (gl.getError() !== gl.NO_ERROR);
    renderer.initRenderTarget(rt);
    out.errors.push(gl.getError());
    rt.dispose();
  }
  release(renderer);
  return out;
}

window.vdbgiRun = async (task) => {
  const run = { probe, shot, frames, load, occlude, frame, boundsSetup, boundsLoad, boundsDraw, split, grid, reads,
    gridLimit }[task.kind];
  if (!run) throw new Error(`unknown task ${task.kind}`);
  return run(task);
};
window.vdbgiReady = true;
