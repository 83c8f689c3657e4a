// viewer.js: the vdbgi viewer page (viewer.html). A scene lit by the bake's
// default lights (gi-bake: sun towards 0.4,0.8,0.3, ambient 0.15) plus the
// probe volume as indirect diffuse, with seed 000's knobs as sliders. A scene
// from gi-lightmap shows its lightmaps (material.lightMap on TEXCOORD_1) on its
// static surfaces, which then take no light from the volume: the volume lights
// what moves (the character), as engines do.
// window.vdbgiViewer exposes its state to the browser tests.
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import GUI from 'three/addons/libs/lil-gui.module.min.js';
import { GiRuntime, loadGi, LAYOUT_COMPACT, ENCODING_RGB9E5 } from './vdbgi.js';
import { LayerCompositor } from './lightmap-layers.js';

const params = new URLSearchParams(location.search);
const backend = params.get('backend') === 'webgpu' ? 'webgpu' : 'webgl';
const canvas = document.getElementById('view');
const errorBox = document.getElementById('error');
const figures = document.getElementById('figures');

const state = { status: 'starting', error: null, frames: 0, scene: null, gi: null, figures: null, lightmaps: 0,
  layers: [] };
window.vdbgiViewer = state;

let renderer, webgpu = null;
if (backend === 'webgpu') {
  const { WebGPURenderer } = await import('three/webgpu');
  webgpu = await import('./vdbgi-webgpu.js');
  renderer = new WebGPURenderer({ canvas, antialias: params.get('aa') !== '0' });
  await renderer.init();
} else {
  renderer = new THREE.WebGLRenderer({ canvas, antialias: params.get('aa') !== '0', preserveDrawingBuffer: true });
}
renderer.setPixelRatio(Math.min(window.devicePixelRatio, 2));
// tone=0: no tone mapping (the tests', since Neutral's desaturation can lower a channel as light is added).
renderer.toneMapping = params.get('tone') === '0' ? THREE.NoToneMapping : THREE.NeutralToneMapping;
renderer.shadowMap.enabled = params.get('shadows') !== '0';
// PCF in both: three 0.187 dropped PCFSoftShadowMap (with a warning) for WebGL2 too.
renderer.shadowMap.type = THREE.PCFShadowMap;

const scene = new THREE.Scene();
scene.background = new THREE.Color(0.55, 0.7, 0.9);
const camera = new THREE.PerspectiveCamera(50, 1, 0.05, 2000);
camera.position.set(26, 17, 30);
const controls = new OrbitControls(camera, canvas);
controls.target.set(0, 1, 0);
controls.enableDamping = true;
// The viewer's own sun and fill (sun=, ambient= in the URL; 0 shows a scene by its own lights and GI).
const num = (name, fallback) => (params.get(name) !== null && Number.isFinite(Number(params.get(name))) ? Number(params.get(name)) : fallback);
const sun = new THREE.DirectionalLight(0xffffff, num('sun', Math.PI));
const ambient = new THREE.AmbientLight(0xffffff, num('ambient', 0.15 * Math.PI));
scene.add(sun, sun.target, ambient);
sun.castShadow = true;
sun.shadow.mapSize.set(2048, 2048);
sun.shadow.bias = -0.0005;
let reach = 50; // half the scene's diagonal: the shadow camera covers it
const setSun = () => {
  sun.target.position.copy(controls.target);
  sun.position.copy(controls.target).addScaledVector(new THREE.Vector3(0.4, 0.8, 0.3).normalize(), 2 * reach);
  Object.assign(sun.shadow.camera, { left: -reach, right: reach, top: reach, bottom: -reach, near: 0.1, far: 4 * reach });
  sun.shadow.camera.updateProjectionMatrix();
};
setSun();

const gi = webgpu ? new webgpu.GiRuntime() : new GiRuntime();
const settings = { gi: true, perVertex: params.get('vertex') !== '0', debug: 'off', sun: Math.PI, ambient: 0.15,
  lightmap: params.get('lightmap') !== '0' };
let root = null; // the scene's root object
let character = null;
const meshes = []; // { mesh, original, vertex, fragment }

function showError(message) {
  state.error = message;
  errorBox.textContent = message;
  errorBox.style.display = message ? 'block' : 'none';
}

// Every material gets a per-vertex and a per-fragment variant; the toggle swaps them.
// A lightmapped one keeps its map instead of the volume's light (both would count the bounce twice).
function prepare(mesh, set) {
  const lit = !!mesh.material.lightMap;
  const make = (perFragment) => {
    if (lit) return webgpu ? webgpu.toNodeMaterial(mesh.material) : mesh.material.clone();
    return gi.apply(mesh.material.clone(), { set, perFragment });
  };
  const vertex = make(false);
  meshes.push({ mesh, vertex, fragment: lit ? vertex : make(true), scale: lit ? mesh.material.lightMapIntensity : 0 });
}

// gi-lightmap's maps: the material's extras name the texture, on TEXCOORD_1, and E's scale (docs/lightmap.md).
// With per-light layers (--layers), each atlas's map is their weighted sum instead, drawn by the
// compositor (WebGL2 or WebGPU), so the panel can dim or switch each light (layers=0: the baked sum).
let compositor = null;
async function attachLightmaps(gltf) {
  const materials = new Set();
  const jobs = [];
  // Before the jobs: a compositor made after an await in each would be made several times.
  const gpu = webgpu && { webgpu: await import('three/webgpu'), tsl: await import('three/tsl') };
  const texture = async (i) => {
    const t = await gltf.parser.getDependency('texture', i);
    t.colorSpace = THREE.SRGBColorSpace; // the PNGs hold sRGB-encoded E / scale
    return t;
  };
  gltf.scene.traverse((o) => {
    const lm = o.isMesh && o.material.userData.vdbgi_lightmap;
    if (!lm) return;
    jobs.push((async () => {
      const map = await texture(lm.texture);
      map.channel = lm.texCoord;
      o.material.lightMap = map;
      o.material.lightMapIntensity = lm.scale;
      if (lm.layers?.length && params.get('layers') !== '0') {
        const layers = await Promise.all(lm.layers.map(async (l) => ({ name: l.name, scale: l.scale, map: await texture(l.texture) })));
        compositor ??= new LayerCompositor(renderer, gpu);
        o.material.lightMap = compositor.target(gltf.parser.json.textures[lm.texture].source, layers);
        o.material.lightMapIntensity = 1;
      }
      materials.add(o.material);
    })());
  });
  await Promise.all(jobs);
  return materials.size;
}

// One slider a light, 0..2, when the scene's lightmaps have layers.
let layerFolder = null;
function showLayers() {
  layerFolder?.destroy();
  layerFolder = null;
  state.layers = compositor ? compositor.names() : [];
  if (!state.layers.length) return;
  layerFolder = gui.addFolder('light layers');
  const w = Object.fromEntries(state.layers.map((n) => [n, 1]));
  for (const name of state.layers) layerFolder.add(w, name, 0, 2, 0.01).onChange((v) => compositor.setWeight(name, v));
}

function applyLightmaps() {
  for (const m of meshes)
    if (m.scale) for (const mat of [m.vertex, m.fragment]) mat.lightMapIntensity = settings.lightmap ? m.scale : 0;
}

function applyMode() {
  for (const m of meshes) m.mesh.material = settings.perVertex && m.mesh !== character ? m.vertex : m.fragment;
}

// A stand-in character (the knobs' second set): a capsule on the ground, lit per fragment.
function addCharacter(box) {
  const c = new THREE.Mesh(new THREE.CapsuleGeometry(0.35, 1.1, 8, 16),
    new THREE.MeshStandardMaterial({ color: 0xd8d0c8, roughness: 0.8 }));
  const centre = box.getCenter(new THREE.Vector3());
  c.position.set(centre.x, box.min.y + 0.9, centre.z);
  c.name = 'character';
  c.castShadow = c.receiveShadow = true;
  return c;
}

// Loads finish in any order: only the latest of each kind is shown.
let sceneToken = 0, volumeToken = 0;

// The GPU side of the scene shown before: geometries, textures, both material variants.
function disposeScene() {
  const textures = new Set();
  for (const m of meshes) {
    m.mesh.geometry.dispose();
    for (const mat of [m.vertex, m.fragment]) {
      for (const v of Object.values(mat)) if (v && v.isTexture) textures.add(v);
      mat.dispose();
    }
  }
  textures.forEach((t) => t.dispose());
  meshes.length = 0;
}

async function loadScene(source, name) {
  const token = ++sceneToken;
  const loader = new GLTFLoader();
  const gltf = typeof source === 'string' ? await loader.loadAsync(source)
                                          : await loader.parseAsync(source, '');
  const previous = compositor;
  compositor = null; // this scene's layers only
  const lightmaps = await attachLightmaps(gltf);
  if (token !== sceneToken) {
    compositor?.dispose();
    compositor = previous;
    return; // a later load won
  }
  previous?.dispose();
  if (root) scene.remove(root);
  if (character) scene.remove(character);
  disposeScene();
  root = gltf.scene;
  scene.add(root);
  // The scene's own glTF lights (KHR_lights_punctual) light it directly unless lights=0.
  const sceneLights = [];
  root.traverse((o) => { if (o.isLight) sceneLights.push(o); });
  if (params.get('lights') === '0') sceneLights.forEach((l) => { l.visible = false; });
  root.traverse((o) => {
    if (!o.isMesh) return;
    o.castShadow = o.receiveShadow = true;
    prepare(o, 'world');
  });
  const box = new THREE.Box3().setFromObject(root);
  reach = box.getSize(new THREE.Vector3()).length() / 2;
  character = addCharacter(box);
  scene.add(character);
  prepare(character, 'character');
  applyMode();
  applyLightmaps();
  state.lightmaps = lightmaps;
  showLayers();
  // Frame the scene, unless the URL says where to look from (cam=x,y,z&at=x,y,z).
  const size = box.getSize(new THREE.Vector3()).length();
  const vec = (name) => params.get(name) && new THREE.Vector3(...params.get(name).split(',').map(Number));
  controls.target.copy(vec('at') || box.getCenter(new THREE.Vector3()));
  if (vec('cam')) camera.position.copy(vec('cam'));
  else camera.position.copy(controls.target).add(new THREE.Vector3(0.45, 0.35, 0.55).multiplyScalar(size * 0.8));
  camera.far = size * 10;
  camera.updateProjectionMatrix();
  setSun();
  state.scene = name;
}

// While a volume loads nothing is drawn: a frame (with shadows, on a CPU renderer
// above all) would take the time the unpacking needs.
let loading = 0;

async function loadVolume(source, name) {
  const token = ++volumeToken;
  const t0 = performance.now();
  loading++;
  try {
    // A person chose this file and watches it load: a budget of 1 GiB, not a game's 32 MiB.
    const volume = await loadGi(source, { renderer: backend === 'webgl' ? renderer : null, maxBytes: 1 << 30 });
    if (token !== volumeToken) { // a later load won
      volume.dispose();
      return;
    }
    gi.setVolume(volume);
    // The first frame with the volume, its shaders compiled: what a user waits for.
    // (compileAsync in WebGL2 warns where KHR_parallel_shader_compile is missing, as on SwiftShader.)
    if (backend === 'webgpu') await renderer.compileAsync(scene, camera);
    else renderer.compile(scene, camera);
    renderer.render(scene, camera);
    volume.timings.firstFrame = performance.now() - t0;
    state.gi = name;
    showFigures(volume, name);
    showError('');
  } catch (e) {
    if (token !== volumeToken) return;
    // A bad file never half-replaces the volume shown: the scene keeps rendering without it.
    gi.setVolume(null);
    state.gi = null;
    showFigures(null, name);
    // loadGi names a URL itself; a dropped file's bytes get its name here.
    throw typeof source === 'string' ? e : new Error(`${name}: ${e.message}`);
  } finally {
    loading--;
  }
}

function showFigures(volume, name) {
  if (!volume) {
    state.figures = null;
    figures.textContent = `${state.scene ?? 'no scene'} — no GI volume` +
      (state.lightmaps ? `, lightmaps on ${state.lightmaps} materials` : '');
    return;
  }
  const h = volume.info, t = volume.timings;
  const mb = (b) => `${(b / 1e6).toFixed(2)} MB`;
  const ms = (v) => (v == null ? '–' : `${v.toFixed(1)} ms`);
  state.figures = { bricks: h.bricks, vramBytes: volume.vramBytes, fileBytes: volume.fileBytes, timings: t };
  figures.textContent = [
    `${name}: ${h.layout === LAYOUT_COMPACT ? 'compact' : 'seed'} layout, ${h.encoding === ENCODING_RGB9E5 ? 'RGB9E5' : 'RGBM'}, ` +
      `${h.spacing.toPrecision(3)} m spacing, ${backend === 'webgpu' ? 'WebGPU' : 'WebGL2'}`,
    `bricks L0..L3  ${h.bricks.join(' / ')}`,
    `VRAM           ${mb(volume.vramBytes)} (${h.indDims.join('×')} cells as ${volume.columns.image.width}×${volume.columns.image.height} columns, atlas ${h.atlasDims.join('×')})`,
    `file           ${mb(volume.fileBytes)}` +
      (h.storedPoints ? ` (version ${h.version}: ${h.storedPoints} probe values, each once)` : ` (version ${h.version}: the textures)`),
    `load           fetch ${ms(t.fetch)}, gunzip ${ms(t.gunzip)}, ` +
      `${h.storedPoints ? 'check and rebuild' : 'check'} ${ms(t.parse)}, textures ${ms(t.build)}, upload ${ms(t.upload)}`,
    `first lit frame ${ms(t.firstFrame)} after the load began (shaders compiled)`,
  ].join('\n');
}

async function run(task) {
  try {
    await task();
  } catch (e) {
    showError(e.message);
    console.error(e);
  }
}

// Panel: GI on/off, per vertex or per fragment, the two knob sets, the debug views, the lights.
const gui = new GUI({ title: 'vdbgi' });
gui.add(settings, 'gi').name('GI on').onChange((v) => { gi.enabled = v; });
gui.add(settings, 'perVertex').name('per vertex').onChange(applyMode);
gui.add(settings, 'lightmap').name('lightmaps').onChange(applyLightmaps);
gui.add(settings, 'debug', { off: 'off', 'probe colour': 'probe', 'brick level': 'level', 'brick boundaries': 'bricks' })
  .name('view').onChange((v) => { gi.debug = v; });
for (const set of ['world', 'character']) {
  const knobs = gi.getKnobs(set);
  const f = gui.addFolder(set);
  f.add(knobs, 'intensity', 0, 4, 0.01).onChange(() => gi.setKnobs(set, knobs));
  f.add(knobs, 'self', 0, 1, 0.01).onChange(() => gi.setKnobs(set, knobs));
  f.add(knobs, 'bleed', 0, 1, 0.01).onChange(() => gi.setKnobs(set, knobs));
}
if (params.get('gui') === '0') gui.hide();
const lights = gui.addFolder('lights');
lights.add(sun, 'intensity', 0, 10, 0.01).name('sun');
lights.add(ambient, 'intensity', 0, 3, 0.01).name('ambient');
lights.close();

// Drag and drop: a scene file, a .gi.gz, or both.
addEventListener('dragover', (e) => { e.preventDefault(); document.body.classList.add('dragging'); });
addEventListener('dragleave', () => document.body.classList.remove('dragging'));
addEventListener('drop', (e) => {
  e.preventDefault();
  document.body.classList.remove('dragging');
  const files = [...e.dataTransfer.files];
  const sceneFile = files.find((f) => /\.(glb|gltf)$/i.test(f.name));
  const giFile = files.find((f) => !/\.(glb|gltf)$/i.test(f.name));
  run(async () => {
    if (sceneFile) await loadScene(await sceneFile.arrayBuffer(), sceneFile.name);
    if (giFile) await loadVolume(await giFile.arrayBuffer(), giFile.name);
  });
});

function resize() {
  const w = canvas.clientWidth, h = canvas.clientHeight;
  if (canvas.width !== Math.floor(w * renderer.getPixelRatio()) || canvas.height !== Math.floor(h * renderer.getPixelRatio())) {
    renderer.setSize(w, h, false);
    camera.aspect = w / h;
    camera.updateProjectionMatrix();
  }
}

renderer.setAnimationLoop(() => {
  if (loading) return;
  resize();
  controls.update();
  renderer.render(scene, camera);
  state.frames++;
});

await run(async () => {
  if (params.get('scene')) await loadScene(params.get('scene'), params.get('scene').split('/').pop());
});
await run(async () => {
  if (params.get('gi')) await loadVolume(params.get('gi'), params.get('gi').split('/').pop());
});
if (!params.get('gi')) showFigures(null);
// What the panel does, for scripts and the browser tests.
state.api = {
  setGi: (on) => { settings.gi = on; gi.enabled = on; gui.controllersRecursive().forEach((c) => c.updateDisplay()); },
  setPerVertex: (on) => { settings.perVertex = on; applyMode(); },
  setLightmap: (on) => { settings.lightmap = on; applyLightmaps(); },
  setLayer: (name, weight) => compositor?.setWeight(name, weight),
  setDebug: (view) => { gi.debug = view; },
  // Draw a frame and copy it in the same task (a WebGPU canvas is blank once presented).
  snapshot: () => {
    renderer.render(scene, camera);
    const c = Object.assign(document.createElement('canvas'), { width: canvas.width, height: canvas.height });
    c.getContext('2d').drawImage(canvas, 0, 0);
    return c;
  },
  frame: () => new Promise((ok) => { const n = state.frames; const wait = () => (state.frames > n + 1 ? ok() : requestAnimationFrame(wait)); wait(); }),
};
state.status = 'ready';
