// vdbgi.js: the runtime half of vdbgi for three.js (WebGL2).
//
//   const gi = new GiRuntime();
//   gi.setVolume(await loadGi('world.gi.gz', { renderer }));
//   mesh.material = gi.apply(mesh.material);        // world set, per vertex
//   hero.material = gi.apply(hero.material, { set: 'character', perFragment: true });
//   gi.debug = 'level';                             // or DebugView.LEVEL
//   gi.addOccluder(hero);                           // takes baked light away near it
//   // every frame, after moving things: gi.updateOccluders();
//
// vdbgi-webgpu.js exports a GiRuntime with the same names and options for
// WebGPURenderer (TSL); everything else here it re-exports.
//
// loadGi() reads a .gi.gz (docs/format.md) into its two textures; a
// GiRuntime owns the uniforms every patched material shares, so swapping
// volumes, turning GI off, changing a knob or a debug view touches no material.
// The lookup is seed 000's volumeIrradiance(); docs/web.md says what each
// knob does. vdbgi-webgpu.js is the same for WebGPURenderer, in TSL.
import * as THREE from 'three';
import { now, yieldToPage } from './gi-stream.js';
import {
  decodeGi, giReader, parseGiSliced, layoutGeometry, MAX_BYTES, ENCODING_RGB9E5, LAYOUT_SEED, LAYOUT_COMPACT, SH2_RANGE,
  SH_BYTES_LUMA2,
} from './gi-format.js';
import { prepareTextures, readTextures } from './gi-gpu.js';

export { ENCODING_RGBM, ENCODING_RGB9E5, LAYOUT_SEED, LAYOUT_COMPACT, MAX_BYTES } from './gi-format.js';

// Debug views: what a material with GI shows instead of its lit colour. The
// runtime's `debug` takes one of these or its name in lower case ('level').
export const DebugView = Object.freeze({ OFF: 0, PROBE: 1, LEVEL: 2, BRICKS: 3, POSITION: 4, NORMAL: 5 });

function debugViewId(view) {
  if (typeof view === 'string' && Object.hasOwn(DebugView, view.toUpperCase())) return DebugView[view.toUpperCase()];
  if (Object.values(DebugView).includes(view)) return view;
  throw new Error(`unknown debug view ${JSON.stringify(view)} (${Object.keys(DebugView).map((k) => k.toLowerCase()).join(', ')})`);
}
// DebugView.LEVEL's colours, linear RGB: no brick, then levels 0..3 (the
// C library's levels.png uses the same, docs/converter.md has the legend).
export const LEVEL_COLOURS = Object.freeze([[0.25, 0.25, 0.25], [0.1, 0.35, 1.0], [0.1, 0.85, 0.25], [1.0, 0.85, 0.1], [1.0, 0.2, 0.1]]);
const glslVec3 = (c) => `vec3(${c.map((v) => v.toFixed(2)).join(', ')})`;


// updateOccluders()'s temporaries, made once: it runs every frame.
const occluderScratch = { p: new THREE.Vector3(), q: new THREE.Vector3(), sphere: new THREE.Sphere(), box: new THREE.Box3() };

// Most occluder shapes (spheres and capsules, all objects together) a runtime
// takes: each costs every lit fragment a few dozen operations (docs/web.md).
export const MAX_OCCLUDERS = 16;
// (Distance / radius)^2 past which an occluder is skipped: it covers under (1/22)^2, 0.2 %.
export const OCCLUDER_REACH2 = 484;

// The oldest three.js each back end draws with (tests/cli/web_three_range.sh draws with
// both): web/package.json's peer range starts at the first. The WebGPU runtime needs
// three/tsl as 0.175 has it; before that the import itself fails, before any check runs.
export const THREE_OLDEST = Object.freeze({ webgl: 165, webgpu: 175 });

// Throw, in one line, if three's REVISION (a string, '187') is older than `backend` needs.
export function checkThree(backend, revision) {
  const oldest = THREE_OLDEST[backend];
  if (!(Number.parseInt(revision, 10) >= oldest))
    throw new Error(`vdbgi: three r${revision} is older than r${oldest}, the oldest its ` +
      `${backend === 'webgpu' ? 'WebGPU runtime (vdbgi/webgpu)' : 'WebGL2 runtime'} draws with: npm install three@^0.187`);
}

// How long a response may give no byte before loadGi gives up on it, by default.
export const LOAD_TIMEOUT_MS = 30000;

// Fetch (a URL) or take (an ArrayBuffer or typed array) a .gi.gz, check it and
// make its textures. With `renderer`, the textures are uploaded before this
// returns, so `timings.upload` is real. Throws, and makes nothing, on a bad file;
// for a URL every message begins with it. A URL's body is checked as it arrives
// (gi-stream.js): a file that is not a volume is refused from its first bytes,
// and reading stops at the first byte past what its header declares.
// `maxBytes` (MAX_BYTES, 32 MiB, by default) refuses from its header a volume
// that would unpack to more. `timeout` (ms, 0 for none) gives up on a response
// that sends nothing for that long; `onProgress({ loaded, total })` hears each
// chunk (total from Content-Length, or null); `signal` aborts as for fetch()
// (its own error, unwrapped). A URL's file is unpacked and rebuilt in a module
// worker (gi-worker.js, beside this file) where one can start, else on the page,
// which it gives back every SLICE_MS: `worker` 'auto' (the worker where this
// file is not inside a bundler's output, which has no gi-worker.js beside it),
// false (the page), or the URL of gi-worker.js as the app serves it.
// timings.decoder says which ran, and timings.reader which rebuilt a packed
// file's textures: 'wasm' (lib/'s C reader, gi-wasm.js: the worker's, where
// WebAssembly runs) or 'js' (gi-packed.js: the page's, which it can slice).
export async function loadGi(source, { renderer = null, signal, timeout = LOAD_TIMEOUT_MS, onProgress, maxBytes = MAX_BYTES,
  worker = 'auto' } = {}) {
  const url = typeof source === 'string' || source instanceof URL ? String(source) : null;
  try {
    return await load(source, url, { renderer, signal, timeout, onProgress, maxBytes, worker });
  } catch (e) {
    if (signal?.aborted && e === signal.reason) throw e;
    if (!url || e.message.startsWith(`${url}: `)) throw e;
    throw new Error(`${url}: ${e.message}`, { cause: e });
  }
}

async function load(source, url, { renderer, signal, timeout, onProgress, maxBytes, worker }) {
  const timings = {};
  let t = now();
  let header, fileBytes;
  if (url) {
    const gi = await fetchGi(url, { signal, timeout, onProgress, maxBytes, worker });
    if (signal?.aborted) throw signal.reason;
    timings.fetch = now() - t - gi.parseMs;
    timings.gunzip = gi.inflateMs;
    timings.parse = gi.parseMs;
    timings.decoder = gi.decoder;
    timings.reader = gi.reader ?? 'js';
    header = gi.header;
    fileBytes = gi.loaded;
  } else {
    let bytes;
    if (source instanceof ArrayBuffer) bytes = new Uint8Array(source);
    else if (ArrayBuffer.isView(source)) bytes = new Uint8Array(source.buffer, source.byteOffset, source.byteLength);
    else throw new Error('loadGi: expected a URL, an ArrayBuffer or a typed array');
    timings.fetch = 0;
    header = await decodeGi(bytes, timings, { maxBytes });
    if (signal?.aborted) throw signal.reason;
    timings.decoder = 'page';
    timings.reader = 'js';
    fileBytes = bytes.length;
  }
  t = now();
  const volume = new GiVolume(header, fileBytes);
  timings.build = now() - t;
  t = now();
  if (renderer) {
    // A texture a task: an L2 volume's seven would be one long one.
    for (const texture of [volume.columns, volume.atlas, ...(volume.sh ?? [])]) {
      renderer.initTexture(texture);
      await yieldToPage();
      if (signal?.aborted) {
        volume.dispose();
        throw signal.reason;
      }
    }
    const gl = renderer.getContext?.();
    if (gl && gl.finish) gl.finish();
  }
  timings.upload = renderer ? now() - t : null;
  volume.timings = timings;
  return volume;
}

// The .gi at url, read chunk by chunk into a decoder (unpacked as it comes,
// refused at the first byte it cannot be, then parsed and made ready for the
// GPU), given up on after `timeout` ms without a byte (the wait for the answer
// included). Network failures say what happened where.
async function fetchGi(url, { signal, timeout, onProgress, maxBytes, worker }) {
  if (signal?.aborted) throw signal.reason;
  const decoding = startDecoder(worker, maxBytes);
  let gi = null;
  const stop = new AbortController();
  let timer = null, timedOut = false;
  const arm = () => {
    clearTimeout(timer);
    if (timeout > 0) timer = setTimeout(() => { timedOut = true; stop.abort(); }, timeout);
  };
  const abort = () => stop.abort();
  signal?.addEventListener('abort', abort);
  let loaded = 0, reader = null;
  // What went wrong while doing `doing`: the caller's abort as it is, else what happened.
  const failed = (e, doing) => {
    if (signal?.aborted) return signal.reason;
    if (timedOut) return new Error(`${doing}: nothing for ${timeout / 1000} s (loadGi's timeout option)`);
    return new Error(`${doing}: ${e.message}`, { cause: e });
  };
  try {
    arm();
    let response;
    try {
      response = await fetch(url, { signal: stop.signal });
    } catch (e) {
      throw failed(e, 'no answer');
    }
    if (!response.ok) throw new Error(`HTTP ${response.status}`);
    const total = Number(response.headers.get('content-length')) || null;
    gi = await decoding;
    reader = response.body.getReader();
    for (;;) {
      arm();
      let part;
      try {
        part = await reader.read();
      } catch (e) {
        throw failed(e, `the body stopped after ${loaded} bytes`);
      }
      if (part.done) break;
      loaded += part.value.length;
      onProgress?.({ loaded, total });
      // The timeout is for the server's silence, not the page's own work on a chunk.
      clearTimeout(timer);
      await gi.push(part.value);
      if (signal?.aborted) throw signal.reason;
    }
    reader = null;
    return { ...(await gi.end()), loaded, decoder: gi.kind };
  } catch (e) {
    // Nothing more is read: a refused file, a bomb, an abort.
    (gi ?? (await decoding)).cancel(e);
    reader?.cancel(e).catch(() => {});
    stop.abort();
    throw e;
  } finally {
    clearTimeout(timer);
    signal?.removeEventListener('abort', abort);
  }
}

// Where loadGi's worker lives when nothing says otherwise: beside this file, when
// this file is itself and not part of a bundler's output (which has no gi-worker.js
// beside it: a worker that failed to load would leave a 404 in the console).
const WORKER_BESIDE = /\/vdbgi\.js$/.test(new URL(import.meta.url).pathname)
  ? new URL('./gi-worker.js', import.meta.url) : null;
// How long a worker may take to start before the page decodes instead.
const WORKER_START_MS = 5000;

// A decoder: push(chunk) each chunk, end() for { header, inflateMs, parseMs }
// (the header ready for GiVolume), cancel(reason) to stop. This one decodes on
// the page, giving it back every SLICE_MS.
function pageDecoder(maxBytes) {
  const gi = giReader({ maxBytes });
  return {
    kind: 'page',
    push: (chunk) => gi.push(chunk),
    cancel: (reason) => gi.cancel(reason),
    end: () => readTextures(gi, parseGiSliced),
  };
}

// The decoder `worker` asks for ('auto', false, or gi-worker.js's URL): one in a
// module worker once it says it is ready, else (no Worker, a policy that forbids
// one, a script that did not load or start within WORKER_START_MS) the page's.
function startDecoder(worker, maxBytes) {
  const url = worker === 'auto' ? WORKER_BESIDE : worker || null;
  if (!url || typeof Worker === 'undefined') return Promise.resolve(pageDecoder(maxBytes));
  let w;
  try {
    w = new Worker(url, { type: 'module' });
  } catch {
    return Promise.resolve(pageDecoder(maxBytes));
  }
  const pending = new Map();
  let next = 0, failure = null;
  const call = (op, message = {}, transfer = []) => new Promise((resolve, reject) => {
    if (failure) return reject(failure);
    pending.set(next, { resolve, reject });
    w.postMessage({ id: next++, op, ...message }, transfer);
  });
  const decoder = {
    kind: 'worker',
    // The chunk's buffer goes over; one that holds more than the chunk is copied first.
    push: (chunk) => {
      const own = chunk.byteOffset === 0 && chunk.byteLength === chunk.buffer.byteLength ? chunk : chunk.slice();
      return call('push', { chunk: own }, [own.buffer]);
    },
    cancel: () => w.terminate(),
    async end() {
      try {
        return await call('end');
      } finally {
        w.terminate();
      }
    },
  };
  return new Promise((resolve) => {
    const fallBack = () => {
      clearTimeout(timer);
      w.terminate();
      resolve(pageDecoder(maxBytes));
    };
    const timer = setTimeout(fallBack, WORKER_START_MS);
    w.onerror = (e) => {
      e.preventDefault();
      // Before it started: the page decodes. After: what was asked of it fails.
      failure = new Error(`the decoding worker stopped (${e.message || 'no message'})`);
      for (const p of pending.values()) p.reject(failure);
      pending.clear();
      fallBack();
    };
    w.onmessage = ({ data }) => {
      if (data.ready) {
        clearTimeout(timer);
        call('start', { maxBytes }).then(() => resolve(decoder), fallBack);
        return;
      }
      const p = pending.get(data.id);
      pending.delete(data.id);
      if (data.error !== undefined) p?.reject(new Error(data.error));
      else p?.resolve(data);
    };
  });
}

// One world's textures and figures. Make it with loadGi(). `info` holds the
// file's header fields (docs/format.md: version, layout, encoding, rgbmRange,
// indDims, atlasDims, boxMin, boxMax, spacing, maxLevel, bricks,
// storedPoints); `columns` and `atlas` are the two textures the GPU gets.
export class GiVolume {
  constructor(header, fileBytes) {
    // The indirection as columns, the terms as unorm bytes (gi-gpu.js), unless the worker made them.
    const { columns, atlas: atlasBytes, sh: shArrays, ...info } = header.columns ? header : prepareTextures(header);
    this.info = Object.freeze(info);
    this.fileBytes = fileBytes;
    const [ax, ay, az] = header.atlasDims;
    const ind = new THREE.DataTexture(columns.data, columns.width, columns.height);
    ind.format = THREE.RGBAFormat;
    ind.type = THREE.UnsignedByteType;
    ind.minFilter = ind.magFilter = THREE.NearestFilter;
    let atlas;
    if (header.encoding === ENCODING_RGB9E5) {
      // Shared-exponent floats, which WebGL2 and WebGPU both filter.
      const a = atlasBytes;
      const words = a.byteOffset % 4 === 0 ? new Uint32Array(a.buffer, a.byteOffset, a.length / 4)
                                           : new Uint32Array(a.slice().buffer);
      atlas = new THREE.Data3DTexture(words, ax, ay, az);
      atlas.format = THREE.RGBFormat;
      atlas.type = THREE.UnsignedInt5999Type;
    } else {
      atlas = new THREE.Data3DTexture(atlasBytes, ax, ay, az);
      atlas.format = THREE.RGBAFormat;
      atlas.type = THREE.UnsignedByteType;
    }
    atlas.minFilter = atlas.magFilter = THREE.LinearFilter;
    // L2 terms: signed ratios as unorm bytes q + 128 (prepareTextures), read back as
    // (255 t - 128) / 127 in the shader. Versions 6 and 7: six RGBA8 textures; 8: three
    // RGBA8 and one RG8 (docs/format.md, "Version 8").
    const texels = ax * ay * az;
    this.sh = shArrays ? shArrays.map((u) => {
      const t = new THREE.Data3DTexture(u, ax, ay, az);
      t.format = u.length === 2 * texels ? THREE.RGFormat : THREE.RGBAFormat;
      t.type = THREE.UnsignedByteType;
      t.minFilter = t.magFilter = THREE.LinearFilter;
      return t;
    }) : null;
    for (const t of [ind, atlas, ...(this.sh ?? [])]) {
      t.wrapS = t.wrapT = t.wrapR = THREE.ClampToEdgeWrapping;
      t.generateMipmaps = false;
      // Rows of an RG8 texture of odd width end on two bytes.
      t.unpackAlignment = t.format === THREE.RGFormat ? 2 : 4;
      t.colorSpace = THREE.NoColorSpace;
      t.needsUpdate = true;
    }
    this.columns = ind;
    this.atlas = atlas;
    this.boxMin = new THREE.Vector3(...header.boxMin);
    this.boxMax = new THREE.Vector3(...header.boxMax);
    // No mipmaps, 4 bytes a texel: what the GPU holds is the atlas and the columns.
    this.vramBytes = columns.data.length + atlasBytes.length + (shArrays ?? []).reduce((n, u) => n + u.length, 0);
  }

  get bricks() { return this.info.bricks; }

  dispose() {
    this.columns.dispose();
    this.atlas.dispose();
    for (const t of this.sh ?? []) t.dispose();
  }
}



// All-zero textures: with them, every lookup reads black (a 1x1x1 indirection's
// columns: one empty run, then nothing).
function emptyTexture(Texture, ...dims) {
  const t = new Texture(new Uint8Array(4 * dims.reduce((a, b) => a * b)), ...dims);
  t.minFilter = t.magFilter = THREE.NearestFilter;
  t.needsUpdate = true;
  return t;
}

// The knobs of seed 000, per receiver set: intensity, self, bleed.
// intensity scales the bounce; self = 1 keeps the part of the bounce along the
// surface's own colour (physical), 0 removes it; bleed lifts the reflecting
// albedo toward white (mix(albedo, 1, bleed)). docs/web.md has the formulas.
export const DEFAULT_KNOBS = Object.freeze({ intensity: 1, self: 1, bleed: 0 });

// What both back ends' runtimes share: the volume shown, the uniforms every
// material with GI reads, the knobs, `enabled` and `debug`. Each back end's
// GiRuntime adds apply().
export class GiRuntimeBase {
  constructor() {
    this.volume = null;
    this._retired = null;
    this._empty = { ind: emptyTexture(THREE.DataTexture, 2, 1), atlas: emptyTexture(THREE.Data3DTexture, 1, 1, 1) };
    this.uniforms = {
      giColumns: { value: this._empty.ind },
      giColumnsDims: { value: new THREE.Vector2(2, 1) },
      giAtlas: { value: this._empty.atlas },
      // L2 terms: six samplers (the empty texture where the volume has fewer), and their
      // form (giBasis 0 none, 2 every term in colour, 3 the second band in luminance).
      giSh: { value: Array(6).fill(this._empty.atlas) },
      giBasis: { value: 0 },
      giBoxMin: { value: new THREE.Vector3(0, 0, 0) },
      giBoxSize: { value: new THREE.Vector3(1, 1, 1) },
      giIndDims: { value: new THREE.Vector3(1, 1, 1) },
      giAtlasDims: { value: new THREE.Vector3(1, 1, 1) },
      // x: texels a brick side, y: border before the first probe, z: coarse probe offset.
      // The layout's number (gi-format.js), the seed apron and where a coarse probe stands.
      giLayout: { value: new THREE.Vector3(LAYOUT_SEED, 1, 0.5) },
      // RGBM's range (0 for RGB9E5, whose texels are already linear), and 1 while the light is on.
      giRgbmRange: { value: 0 },
      giOn: { value: 0 },
      giDebug: { value: DebugView.OFF },
      world: { value: new THREE.Vector3(DEFAULT_KNOBS.intensity, DEFAULT_KNOBS.self, DEFAULT_KNOBS.bleed) },
      character: { value: new THREE.Vector3(DEFAULT_KNOBS.intensity, DEFAULT_KNOBS.self, DEFAULT_KNOBS.bleed) },
      // Occluders, world space: a capsule's ends (xyz) and, in giOccA's w, its radius
      // (a sphere: both ends at its centre); the first giOccCount are in use.
      giOccA: { value: Array.from({ length: MAX_OCCLUDERS }, () => new THREE.Vector4()) },
      giOccB: { value: Array.from({ length: MAX_OCCLUDERS }, () => new THREE.Vector4()) },
      giOccCount: { value: 0 },
    };
    this._enabled = true;
    this._applied = new WeakSet();
    // The same materials, to recompile when the debug views come or go; the dead ones
    // dropped whenever the set has doubled since.
    this._appliedRefs = new Set();
    this._refsKept = 64;
    // light() and lightScene()'s materials, across calls: a material given (or made) ->
    // { original, ways: way of lighting -> the material apply() made of it }.
    this._lit = new WeakMap();
    this._occluders = new Map(); // object -> its capsules in its own space, or null: its bounding sphere
  }

  // Let object (a moving one: a character, a prop) take baked light away from
  // what is near it, the lightmap's and the volume's alike, on every material
  // apply() gave: by default as its bounding sphere; with capsules ([{ a, b,
  // radius }], ends as Vector3 or [x, y, z] in the object's own space: a
  // character is a few) as those. A receiver inside a shape (the object's own
  // surface, for its bounding sphere) is not occluded by it. Throws past
  // MAX_OCCLUDERS shapes in all. Reads the object's world matrix now and at
  // every updateOccluders().
  addOccluder(object, { capsules = null } = {}) {
    const shapes = capsules ? capsules.map((c) => {
      const v = (p) => (p?.isVector3 ? p.clone() : new THREE.Vector3(...p));
      if (!(c.radius > 0)) throw new Error(`vdbgi: an occluder's capsule needs a radius > 0 (got ${c.radius})`);
      return { a: v(c.a), b: v(c.b ?? c.a), radius: c.radius };
    }) : null;
    const had = this._occluders.get(object);
    this._occluders.set(object, shapes);
    const total = [...this._occluders.values()].reduce((n, c) => n + (c ? c.length : 1), 0);
    if (total > MAX_OCCLUDERS) {
      if (had === undefined) this._occluders.delete(object);
      else this._occluders.set(object, had);
      throw new Error(`vdbgi: ${total} occluder shapes asked, at most ${MAX_OCCLUDERS} (MAX_OCCLUDERS): ` +
        'give fewer capsules or remove an occluder');
    }
    this.updateOccluders();
    return object;
  }

  // Light every mesh under `root` with the volume. perFragment 'auto' chooses
  // per mesh: per fragment where its triangles' mean edge is longer than the
  // volume's probe spacing (its vertices then stand farther apart than the
  // probes, and light interpolated between them misses what the probes hold in
  // between: a lamp's pool on a floor of two triangles), per vertex elsewhere,
  // the cheaper lookup. true or false lights every mesh one way. The volume must
  // be set first (its spacing decides). Materials shared stay shared within a
  // way. Returns how many meshes each way: { perVertex, perFragment }.
  light(root, { set = 'world', perFragment = 'auto' } = {}) {
    if (perFragment === 'auto' && !this.volume)
      throw new Error("vdbgi: light(root) with perFragment 'auto' needs the volume first (setVolume): " +
        'its probe spacing decides');
    const use = materialUser(this);
    const counts = { perVertex: 0, perFragment: 0 };
    root.traverse((o) => {
      if (!o.isMesh || !o.material) return;
      const fragment = perFragment === 'auto' ? largeTriangles(o, this.volume.info.spacing) : !!perFragment;
      use(o, fragment ? 'fragment' : 'vertex', { set, perFragment: fragment });
      counts[fragment ? 'perFragment' : 'perVertex']++;
    });
    return counts;
  }

  // The split the README recommends, in one call, for a GLTFLoader result of a
  // gi-lightmap .glb: a mesh with a lightmap gets it (TEXCOORD_1, at its scale) and
  // takes no light from the volume, only the occluders' shadow; a mesh without one
  // is lit by the volume as light() lights it (per fragment where its triangles
  // are large); every mesh under an object of `moving` (characters, props: in the
  // scene or not) is lit by the volume per fragment with the character knobs, and
  // each of those objects becomes an occluder unless `occlude` is false.
  // Materials shared stay shared. Resolves to how many meshes each way:
  // { lightmapped, volume, moving }.
  async lightScene(gltf, { moving = [], occlude = true } = {}) {
    const movers = new Set();
    for (const object of moving) object.traverse((o) => { if (o.isMesh) movers.add(o); });
    const statics = [];
    gltf.scene.traverse((o) => { if (o.isMesh && !movers.has(o)) statics.push(o); });
    // Each lightmap texture once, all before any material changes.
    const maps = new Map();
    for (const mesh of statics) {
      const lm = mesh.material.userData?.vdbgi_lightmap;
      if (lm && !maps.has(lm.texture)) maps.set(lm.texture, gltf.parser.getDependency('texture', lm.texture));
    }
    const loaded = await Promise.all(maps.values());
    [...maps.keys()].forEach((index, i) => {
      loaded[i].colorSpace = THREE.SRGBColorSpace; // the PNGs hold sRGB-encoded E / scale
      maps.set(index, loaded[i]);
    });
    const use = materialUser(this);
    for (const mesh of movers) use(mesh, 'moving', { set: 'character', perFragment: true });
    let lightmapped = 0;
    for (const mesh of statics) {
      const lm = mesh.material.userData?.vdbgi_lightmap;
      if (!lm) {
        const fragment = !!this.volume && largeTriangles(mesh, this.volume.info.spacing);
        use(mesh, fragment ? 'fragment' : 'vertex', { perFragment: fragment });
        continue;
      }
      const map = maps.get(lm.texture);
      map.channel = lm.texCoord ?? 1;
      use(mesh, 'lightmap', { volume: false }, (material) => {
        material.lightMap = map;
        material.lightMapIntensity = lm.scale;
      });
      lightmapped++;
    }
    if (occlude) for (const object of moving) this.addOccluder(object);
    return { lightmapped, volume: statics.length - lightmapped, moving: movers.size };
  }

  removeOccluder(object) {
    this._occluders.delete(object);
    this.updateOccluders();
  }

  // Read every occluder's world matrix into the shared uniforms: once a frame,
  // after the objects moved (object.updateMatrixWorld() first if the renderer
  // has not yet).
  updateOccluders() {
    const a = this.uniforms.giOccA.value, b = this.uniforms.giOccB.value;
    const { p, q, sphere, box } = occluderScratch;
    let n = 0;
    for (const [object, capsules] of this._occluders) {
      const m = object.matrixWorld;
      if (!capsules) {
        if (object.geometry) {
          if (!object.geometry.boundingSphere) object.geometry.computeBoundingSphere();
          sphere.copy(object.geometry.boundingSphere).applyMatrix4(m);
        } else {
          box.setFromObject(object).getBoundingSphere(sphere);
        }
        a[n].set(sphere.center.x, sphere.center.y, sphere.center.z, sphere.radius);
        b[n++].set(sphere.center.x, sphere.center.y, sphere.center.z, 0);
        continue;
      }
      const scale = m.getMaxScaleOnAxis();
      for (const c of capsules) {
        p.copy(c.a).applyMatrix4(m);
        q.copy(c.b).applyMatrix4(m);
        a[n].set(p.x, p.y, p.z, c.radius * scale);
        b[n++].set(q.x, q.y, q.z, 0);
      }
    }
    this.uniforms.giOccCount.value = n;
  }

  // Whether apply() goes on with material: not when this back end does not light
  // its kind (one warning a kind; `also` names more kinds it does light), nor
  // when it has GI already.
  _admits(material, supported, also) {
    if (!supported) {
      warnOnce(`vdbgi: ${material.type} materials take no GI (MeshStandardMaterial, MeshPhysicalMaterial and ` +
        `MeshLambertMaterial${also} do); left as they are`);
      return false;
    }
    if (this._applied.has(material)) return false;
    this._applied.add(material);
    this._appliedRefs.add(new WeakRef(material));
    if (this._appliedRefs.size > 2 * this._refsKept) {
      [...this._liveMaterials()]; // the walk drops the dead
      this._refsKept = Math.max(64, this._appliedRefs.size);
    }
    return true;
  }

  // The materials apply() gave that are still alive; the dead ones' refs dropped.
  * _liveMaterials() {
    for (const ref of this._appliedRefs) {
      const m = ref.deref();
      if (m) yield m;
      else this._appliedRefs.delete(ref);
    }
  }

  // Show `volume` (or nothing, with null). The volume shown before is disposed
  // one setVolume() later, so it is out of any frame still in flight.
  setVolume(volume) {
    if (this._retired && this._retired !== volume) this._retired.dispose();
    this._retired = this.volume !== volume ? this.volume : null;
    this.volume = volume;
    const u = this.uniforms;
    if (!volume) {
      u.giColumns.value = this._empty.ind;
      u.giColumnsDims.value.set(2, 1);
      u.giIndDims.value.set(1, 1, 1);
      u.giAtlas.value = this._empty.atlas;
      u.giSh.value = Array(6).fill(this._empty.atlas);
      u.giBasis.value = 0;
      u.giRgbmRange.value = 0;
      u.giOn.value = 0;
      return;
    }
    const h = volume.info;
    const geo = layoutGeometry(h.layout);
    u.giColumns.value = volume.columns;
    u.giColumnsDims.value.set(volume.columns.image.width, volume.columns.image.height);
    u.giAtlas.value = volume.atlas;
    // Six term samplers whatever the volume holds: version 8's four, then the empty one.
    u.giSh.value = [...(volume.sh ?? []), ...Array(6).fill(this._empty.atlas)].slice(0, 6);
    u.giBasis.value = !volume.sh ? 0 : h.shBytes === SH_BYTES_LUMA2 ? 3 : 2;
    u.giBoxMin.value.copy(volume.boxMin);
    u.giBoxSize.value.subVectors(volume.boxMax, volume.boxMin);
    u.giIndDims.value.set(...h.indDims);
    u.giAtlasDims.value.set(...h.atlasDims);
    u.giLayout.value.set(h.layout, geo.pad, geo.centre);
    u.giRgbmRange.value = h.encoding === ENCODING_RGB9E5 ? 0 : h.rgbmRange;
    u.giOn.value = this._enabled ? 1 : 0;
  }

  get enabled() { return this._enabled; }
  set enabled(on) {
    this._enabled = !!on;
    this.uniforms.giOn.value = this._enabled && this.volume ? 1 : 0;
  }

  get debug() { return this.uniforms.giDebug.value; }
  set debug(view) {
    const id = debugViewId(view), was = this.uniforms.giDebug.value;
    this.uniforms.giDebug.value = id;
    if ((was === DebugView.OFF) !== (id === DebugView.OFF)) this._debugChanged();
  }

  // Both back ends build the debug views into a material only while one is shown: a
  // rasteriser that runs both sides of a branch for every fragment (SwiftShader) paid
  // the views' second lookup in every frame (docs/web.md). Showing one, or going
  // back to none, recompiles each material apply() gave (three keeps both programs).
  _debugChanged() {
    const shown = this.debug !== DebugView.OFF;
    for (const m of this._liveMaterials()) {
      this._showDebug(m, shown);
      m.needsUpdate = true;
    }
  }

  // What a back end changes in a material as the debug views come or go, beyond the
  // recompile (WebGL2: nothing; its onBeforeCompile reads the state).
  _showDebug() {}

  // set: 'world' or 'character'; knobs: any of { intensity, self, bleed }.
  setKnobs(set, knobs) {
    const v = this._set(set).value;
    if (knobs.intensity !== undefined) v.x = knobs.intensity;
    if (knobs.self !== undefined) v.y = knobs.self;
    if (knobs.bleed !== undefined) v.z = knobs.bleed;
  }

  getKnobs(set) {
    const v = this._set(set).value;
    return { intensity: v.x, self: v.y, bleed: v.z };
  }

  _set(set) {
    if (set !== 'world' && set !== 'character') throw new Error(`unknown knob set '${set}' (world or character)`);
    return this.uniforms[set];
  }

  dispose() {
    this._retired?.dispose();
    this.volume?.dispose();
    this._empty.ind.dispose();
    this._empty.atlas.dispose();
    this.volume = this._retired = null;
  }
}

// Sets mesh.material (each of an array) to what runtime.apply() made of it for a
// way of lighting it, once per (material, way), remembered by the runtime across
// calls. A material lit two ways (a mover sharing one with the world, a coarse
// and a fine mesh) gets a copy of the original for the second: apply() patches
// in place, and the first way's shader (or a lightmap set on it) would reach the
// second's meshes.
function materialUser(runtime) {
  const lit = runtime._lit;
  const one = (given, way, options, prepare) => {
    let entry = lit.get(given);
    if (!entry) lit.set(given, (entry = { original: given, ways: new Map() }));
    if (!entry.ways.has(way)) {
      const material = entry.ways.size === 0 ? entry.original : entry.original.clone();
      prepare(material);
      const made = runtime.apply(material, options);
      entry.ways.set(way, made);
      lit.set(made, entry);
    }
    return entry.ways.get(way);
  };
  return (mesh, way, options, prepare = () => {}) => {
    mesh.material = Array.isArray(mesh.material)
      ? mesh.material.map((m) => one(m, way, options, prepare))
      : one(mesh.material, way, options, prepare);
  };
}

// Whether a mesh's triangles are large against the probe spacing: their mean
// edge in world metres (the mesh's largest world scale, times an instanced
// mesh's largest instance scale; at most 4,096 triangles read, evenly spread)
// over `spacing`.
function largeTriangles(mesh, spacing) {
  const position = mesh.geometry?.attributes?.position;
  if (!position) return false;
  const index = mesh.geometry.index;
  const triangles = Math.floor((index ? index.count : position.count) / 3);
  if (triangles === 0) return false;
  const stride = Math.max(1, Math.floor(triangles / 4096));
  const v = edgeScratch;
  const at = (k) => (index ? index.getX(k) : k);
  let sum = 0, n = 0;
  for (let t = 0; t < triangles; t += stride, n++) {
    for (let e = 0; e < 3; e++) v[e].fromBufferAttribute(position, at(3 * t + e));
    sum += v[0].distanceTo(v[1]) + v[1].distanceTo(v[2]) + v[2].distanceTo(v[0]);
  }
  mesh.updateWorldMatrix(true, false);
  let scale = mesh.matrixWorld.getMaxScaleOnAxis();
  if (mesh.isInstancedMesh) {
    let most = 0;
    for (let i = 0; i < mesh.count; i++) {
      mesh.getMatrixAt(i, instanceScratch);
      most = Math.max(most, instanceScratch.getMaxScaleOnAxis());
    }
    scale *= most;
  }
  return (sum / (3 * n)) * scale > spacing;
}
const edgeScratch = [new THREE.Vector3(), new THREE.Vector3(), new THREE.Vector3()];
const instanceScratch = new THREE.Matrix4();

// Warn once per message: a traverse over a scene meets the same material many times.
const warned = new Set();
function warnOnce(message) {
  if (warned.has(message)) return;
  warned.add(message);
  console.warn(message);
}

// The WebGL2 runtime: apply() patches three's own shader text.
export class GiRuntime extends GiRuntimeBase {
  constructor() {
    checkThree('webgl', THREE.REVISION);
    super();
  }

  // Add GI to a MeshStandardMaterial, MeshPhysicalMaterial or MeshLambertMaterial,
  // in place: giIrradiance x albedo as indirect diffuse, looked up per vertex
  // (seed 000's default: the rasteriser interpolates it) or per fragment.
  // Returns the material. Any other material (unlit, toon, a ShaderMaterial)
  // is returned as it was, with one warning; a material given twice is
  // returned as it is (a clone of one with GI has none: three copies neither
  // onBeforeCompile nor this mark).
  // With volume: false the material takes no light from the volume, only the
  // occluders' shadow on what it has (a lightmapped static surface).
  apply(material, { set = 'world', perFragment = false, volume = true } = {}) {
    const knobs = this._set(set);
    if (!this._admits(material, material.isMeshStandardMaterial || material.isMeshLambertMaterial, ''))
      return material;
    const previous = material.onBeforeCompile;
    const u = this.uniforms;
    material.onBeforeCompile = (shader, renderer) => {
      previous?.call(material, shader, renderer);
      for (const name of ['giColumns', 'giColumnsDims', 'giAtlas', 'giSh', 'giBasis', 'giBoxMin', 'giBoxSize',
        'giIndDims', 'giAtlasDims', 'giLayout', 'giRgbmRange', 'giOn', 'giDebug', 'giOccA', 'giOccB', 'giOccCount'])
        shader.uniforms[name] = u[name];
      shader.uniforms.giKnobs = knobs;
      shader.vertexShader = shader.vertexShader
        .replace('#include <common>', `#include <common>\n${GLSL_LOOKUP}\n${GLSL_VERTEX_PARS}`)
        .replace('#include <worldpos_vertex>', `#include <worldpos_vertex>\n${GLSL_VERTEX}`);
      shader.fragmentShader = shader.fragmentShader
        .replace('#include <common>', `#include <common>\n${GLSL_LOOKUP}\n${GLSL_FRAGMENT_PARS}`)
        .replace('#include <lights_fragment_end>', `#include <lights_fragment_end>\n${GLSL_SHADE}`)
        .replace('#include <dithering_fragment>',
          `#include <dithering_fragment>\n${this.debug !== DebugView.OFF ? GLSL_DEBUG : ''}`);
    };
    material.defines = { ...material.defines };
    if (perFragment || !volume) delete material.defines.VDBGI_PER_VERTEX;
    else material.defines.VDBGI_PER_VERTEX = '';
    if (volume) delete material.defines.VDBGI_NO_VOLUME;
    else material.defines.VDBGI_NO_VOLUME = '';
    const key = material.customProgramCacheKey.bind(material);
    material.customProgramCacheKey = () =>
      `${key()}|vdbgi${!volume ? 'n' : perFragment ? 'f' : 'v'}${this.debug !== DebugView.OFF ? 'd' : ''}`;
    material.needsUpdate = true;
    return material;
  }
}

// Seed 000's volumeIrradiance(), both layouts: NEAREST indirection for the
// cell's slot and level, then one LINEAR read inside the brick. docs/format.md
// is the reference; tests/js/gi_loader.mjs is the same arithmetic in float32.
const GLSL_LOOKUP = /* glsl */ `
uniform highp sampler2D giColumns;
uniform highp sampler3D giAtlas;
uniform highp sampler3D giSh[6];
uniform int giBasis;
uniform vec3 giBoxMin, giBoxSize, giIndDims, giAtlasDims, giLayout;
uniform vec2 giColumnsDims;
uniform float giRgbmRange, giOn;
uniform int giDebug;
struct GiLookup { vec3 irradiance; float level; vec3 inBrick; };
// Texel i of the runtime's indirection, as bytes. i, row and column are
// integers below 2^22, exact in float32; a GPU's division may be a few ulp
// off, so a texel at a row's edge may first land a row off: step back.
vec4 vdbgiColumnsTexel(float i) {
  float w = giColumnsDims.x;
  float row = floor((i + 0.5) / w);
  float col = i - row * w;
  row += col < 0.0 ? -1.0 : (col >= w ? 1.0 : 0.0);
  return floor(texelFetch(giColumns, ivec2(int(i - row * w), int(row)), 0) * 255.0 + 0.5);
}
// n: the receiver's world normal. With L2 terms (docs/format.md, "Version 6")
// the position moves half a spacing along it, off its own surface, and the
// term textures, read where the atlas is, turn L0 into E(n) / pi. A zero
// normal (a mesh without normals, per vertex) reads L0 alone. giBasis: 0 no
// terms, 2 every term in colour (versions 6, 7), 3 terms 4-8 one ratio for
// the three channels, at bytes 9-13 (version 8).
GiLookup vdbgiLookup(vec3 pos, vec3 n) {
  float nn = dot(n, n);
  bool l2 = giBasis > 0 && nn > 0.25;
  n = l2 ? n * inversesqrt(nn) : vec3(0.0);
  pos += n * (0.5 * giBoxSize.x / (giIndDims.x * 4.0));
  vec3 p = (pos - giBoxMin) / giBoxSize * (giIndDims * 4.0) - 0.5;
  vec3 baseBrick = floor(p / 4.0);
  // The cell's texel of the indirection, read from its column's run (docs/format.md,
  // "The runtime's indirection"): 0,0,0,0 outside the run, as in the 3D texture,
  // except below it in the compact layout (the lift: the run's lowest brick at its
  // bottom plane).
  vec3 cell = clamp(baseBrick, vec3(0.0), giIndDims - 1.0);
  float column = cell.x + giIndDims.x * cell.z;
  vec4 run = vdbgiColumnsTexel(2.0 * column), at = vdbgiColumnsTexel(2.0 * column + 1.0);
  float ymin = run.r + 256.0 * run.g, count = run.b + 256.0 * run.a;
  bool compact = abs(giLayout.x - ${LAYOUT_COMPACT}.0) < 0.5;
  bool lift = compact && count > 0.0;
  baseBrick.y = lift ? max(baseBrick.y, ymin) : baseBrick.y;
  float k = lift ? max(cell.y - ymin, 0.0) : cell.y - ymin;
  float entry = 2.0 * giIndDims.x * giIndDims.z + at.r + 256.0 * at.g + 65536.0 * at.b + max(k, 0.0);
  vec4 ind = vdbgiColumnsTexel(min(entry, giColumnsDims.x * giColumnsDims.y - 1.0));
  ind = k >= 0.0 && k < count ? ind : vec4(0.0);
  // Seed: rgb the slot, a the level + 1 (0: empty). Compact: a holds the level
  // in bits 0-1 and the first texel mod 4 per axis above; rgb its texel / 4.
  float level = compact ? mod(ind.a, 4.0) : max(ind.a - 1.0, 0.0);
  float span = exp2(level);
  vec3 originCell = floor(baseBrick / span) * span * 4.0;
  vec3 q = (p - originCell + giLayout.z) / span - giLayout.z;
  q.y = compact ? max(q.y, 0.0) : q.y;
  vec3 first = compact ? ind.rgb * 4.0 + mod(floor(ind.a / vec3(4.0, 16.0, 64.0)), 4.0)
                       : ind.rgb * 6.0 + giLayout.y;
  vec3 texel = first + q;
  vec3 uvw = (texel + 0.5) / giAtlasDims;
  vec4 s = texture(giAtlas, uvw);
  GiLookup r;
  r.irradiance = giRgbmRange > 0.0 ? s.rgb * s.a * giRgbmRange : s.rgb;
  if (l2) {
    // Term byte j = 3 term + channel in texture j / 4, component j mod 4; version 8's
    // terms 4-8 (k = 3..7) at byte 6 + k, for all three channels. (GLSL ES 3.0 indexes
    // a sampler array by constants only: one line a texture.)
    float t[24];
    ${[0, 1, 2, 3, 4, 5].map((i) => `vec4 q${i} = max((texture(giSh[${i}], uvw) * 255.0 - 128.0) / 127.0, -1.0);
    t[${4 * i}] = q${i}.x; t[${4 * i + 1}] = q${i}.y; t[${4 * i + 2}] = q${i}.z; t[${4 * i + 3}] = q${i}.w;`).join('\n    ')}
    float poly[8] = float[8](n.x, n.y, n.z, n.x * n.y, n.y * n.z, 3.0 * n.z * n.z - 1.0, n.x * n.z, n.x * n.x - n.y * n.y);
    float range[8] = float[8](${SH2_RANGE.map((r) => r.toFixed(4)).join(', ')});
    float luma2 = giBasis == 3 ? 1.0 : 0.0;
    vec3 sum = vec3(1.0);
    for (int k = 0; k < 8; k++)
      sum += mix(vec3(t[3 * k], t[3 * k + 1], t[3 * k + 2]), vec3(t[6 + k]), k >= 3 ? luma2 : 0.0) * range[k] * poly[k];
    r.irradiance = max(r.irradiance * sum, 0.0);
  }
  r.level = compact ? (ind == vec4(0.0) ? -1.0 : level) : ind.a - 1.0;
  r.inBrick = (p - originCell) / (4.0 * span);
  return r;
}
`;

const GLSL_VERTEX_PARS = /* glsl */ `
varying vec3 vGiWorld;
#ifdef VDBGI_PER_VERTEX
varying vec3 vGiIrradiance;
#endif
`;

// The world normal from three's view-space one (instancing and the normal
// matrix already in it).
const GLSL_WORLD_NORMAL = (viewNormal) => `(vec4(${viewNormal}, 0.0) * viewMatrix).xyz`;

const GLSL_VERTEX = /* glsl */ `
{
  vec4 giWorld = vec4(transformed, 1.0);
  #ifdef USE_BATCHING
  giWorld = batchingMatrix * giWorld;
  #endif
  #ifdef USE_INSTANCING
  giWorld = instanceMatrix * giWorld;
  #endif
  giWorld = modelMatrix * giWorld;
  vGiWorld = giWorld.xyz;
  #ifdef VDBGI_PER_VERTEX
  vGiIrradiance = vdbgiLookup(vGiWorld, ${GLSL_WORLD_NORMAL('transformedNormal')}).irradiance;
  #endif
}
`;

const GLSL_FRAGMENT_PARS = /* glsl */ `
varying vec3 vGiWorld;
#ifdef VDBGI_PER_VERTEX
varying vec3 vGiIrradiance;
#endif
uniform vec3 giKnobs; // intensity, self, bleed
uniform vec4 giOccA[${MAX_OCCLUDERS}], giOccB[${MAX_OCCLUDERS}];
uniform int giOccCount;
// The share of the cosine-weighted hemisphere over unit normal n at p that a
// sphere (c, r) covers: cos(theta) (r / d)^2 above the horizon, and the exact
// form where the horizon cuts it (Quilez, "sphere ambient occlusion"; the
// clipped part after Lagarde and de Rousiers).
float vdbgiSphereOcclusion(vec3 p, vec3 n, vec3 c, float r) {
  vec3 d = c - p;
  float l2 = dot(d, d), dn = dot(n, d);
  // None from inside it, nor from wholly below the horizon, nor past 22 radii (where
  // it covers under 0.2 %): most fragments of a scene stop here.
  if (l2 <= r * r * 1.002 || dn <= -r || l2 >= ${OCCLUDER_REACH2}.0 * r * r) return 0.0;
  float l = sqrt(l2), nl = dn / l, h2 = l2 / (r * r), k2 = 1.0 - h2 * nl * nl;
  float res = max(nl, 0.0) / h2;
  if (k2 > 1e-4) {
    float x = clamp(-nl * sqrt((h2 - 1.0) / (1.0 - nl * nl)), -1.0, 1.0);
    res = (nl * acos(x) - sqrt(k2 * (h2 - 1.0))) / h2 + atan(sqrt(k2 / (h2 - 1.0)));
    res /= PI;
  }
  return clamp(res, 0.0, 1.0);
}
// What the occluders leave of the light arriving at p over n: each capsule as
// the sphere at its segment's point nearest p, their shares multiplied.
float vdbgiVisibility(vec3 p, vec3 n) {
  float v = 1.0;
  for (int i = 0; i < ${MAX_OCCLUDERS}; i++) {
    if (i >= giOccCount) break;
    vec3 a = giOccA[i].xyz, ab = giOccB[i].xyz - a;
    float t = dot(ab, ab) > 0.0 ? clamp(dot(p - a, ab) / dot(ab, ab), 0.0, 1.0) : 0.0;
    v *= 1.0 - vdbgiSphereOcclusion(p, n, a + t * ab, giOccA[i].w);
  }
  return v;
}
// n: the fragment's world normal (main()'s normal, turned to world space).
vec3 vdbgiIrradianceHere(vec3 n) {
  #ifdef VDBGI_PER_VERTEX
  return vGiIrradiance;
  #else
  return vdbgiLookup(vGiWorld, n).irradiance;
  #endif
}
// The seed's stylisation: self scales the part of the bounce's colour that
// lies along the surface's own colour (1 keeps it: physical); bleed lifts the
// reflecting albedo toward white.
vec3 vdbgiBounce(vec3 irradiance, vec3 albedo, vec3 knobs) {
  vec3 ownHue = albedo - dot(albedo, vec3(1.0 / 3.0));
  vec3 hue = irradiance - dot(irradiance, vec3(1.0 / 3.0));
  float len2 = dot(ownHue, ownHue);
  float along = len2 > 1e-8 ? max(dot(hue, ownHue), 0.0) / len2 : 0.0;
  vec3 e = max(irradiance - (1.0 - knobs.y) * along * ownHue, 0.0);
  return e * mix(albedo, vec3(1.0), knobs.z) * knobs.x;
}
`;

// The albedo a standard material's diffuse light sees, (1 - metalness) x its
// colour: three 0.183 on calls it diffuseContribution (diffuseColor is then the
// whole base colour); before, diffuseColor held it. Read from three's own chunk.
const STANDARD_DIFFUSE = THREE.ShaderChunk.lights_physical_pars_fragment.includes('diffuseContribution')
  ? 'diffuseContribution' : 'diffuseColor';

// The volume's bounce, then the occluders over all of the indirect diffuse
// light (a lightmap's, three's probes' and ambient's too).
const GLSL_SHADE = /* glsl */ `
#ifndef VDBGI_NO_VOLUME
#if defined( STANDARD )
reflectedLight.indirectDiffuse += giOn * vdbgiBounce(vdbgiIrradianceHere(${GLSL_WORLD_NORMAL('normal')}), material.${STANDARD_DIFFUSE}, giKnobs);
#else
reflectedLight.indirectDiffuse += giOn * vdbgiBounce(vdbgiIrradianceHere(${GLSL_WORLD_NORMAL('normal')}), material.diffuseColor, giKnobs);
#endif
#endif
if (giOccCount > 0) reflectedLight.indirectDiffuse *= vdbgiVisibility(vGiWorld, normalize(${GLSL_WORLD_NORMAL('normal')}));
`;

// Debug views replace the final colour; PROBE, POSITION and NORMAL write linear
// values, so a float render target reads back exactly what the lookup returned.
const GLSL_DEBUG = /* glsl */ `
if (giDebug != ${DebugView.OFF}) {
  GiLookup giL = vdbgiLookup(vGiWorld, ${GLSL_WORLD_NORMAL('normal')});
  vec3 giC;
  if (giDebug == ${DebugView.PROBE}) {
    giC = vdbgiIrradianceHere(${GLSL_WORLD_NORMAL('normal')});
  } else if (giDebug == ${DebugView.LEVEL}) {
    giC = giL.level < 0.0 ? ${glslVec3(LEVEL_COLOURS[0])} : giL.level < 0.5 ? ${glslVec3(LEVEL_COLOURS[1])}
        : giL.level < 1.5 ? ${glslVec3(LEVEL_COLOURS[2])} : giL.level < 2.5 ? ${glslVec3(LEVEL_COLOURS[3])}
        : ${glslVec3(LEVEL_COLOURS[4])};
  } else if (giDebug == ${DebugView.BRICKS}) {
    // A line where the surface crosses a brick's face: an axis along which the
    // position does not move across the pixel (a floor read in a face's plane, as
    // half a spacing off a floor at a round height is) crosses none.
    vec3 w = fwidth(giL.inBrick);
    vec3 d = mix(min(giL.inBrick, 1.0 - giL.inBrick) / max(w, vec3(1e-6)), vec3(1e6), lessThan(w, vec3(1e-6)));
    // Below its column's lowest brick (the lift) a position reads that brick's bottom
    // plane: no face of it lies there, so y draws no line.
    d.y = giL.inBrick.y < 0.0 ? 1e6 : d.y;
    float edge = 1.0 - clamp(min(d.x, min(d.y, d.z)) - 0.5, 0.0, 1.0);
    giC = mix(giL.irradiance, vec3(0.0), edge);
  } else if (giDebug == ${DebugView.NORMAL}) {
    giC = normalize(${GLSL_WORLD_NORMAL('normal')});
  } else {
    giC = vGiWorld;
  }
  // Positions and normals go out raw; colours through the output's colour space
  // (the identity for a linear float target).
  gl_FragColor = giDebug >= ${DebugView.POSITION} ? vec4(giC, 1.0) : linearToOutputTexel(vec4(giC, 1.0));
}
`;
