// bench.mjs: the worker's per-load decode in JS (web/gi-format.js parseGi + web/gi-gpu.js
// prepareTextures, as web/gi-worker.js runs them once the inflated .gi is whole) against the
// WASM build of lib/ (gi_read + gi_prepare, giwasm.c). One process per mode, so that run 1 is cold.
//   node bench.mjs js   FILE.gi          timings of the JS path
//   node bench.mjs wasm FILE.gi W.wasm   timings of the WASM path
//   node bench.mjs both FILE.gi W.wasm   warm JS and WASM runs alternating in one process
//   node bench.mjs check FILE.gi W.wasm [NATIVE_PREFIX]  byte comparison of the outputs
import { readFileSync } from 'node:fs';
import { performance } from 'node:perf_hooks';
import { parseGi } from '../../web/gi-format.js';
import { prepareTextures } from '../../web/gi-gpu.js';
import { crc32 } from '../../web/gi-stream.js';

const [mode, file, wasmFile, nativePrefix] = process.argv.slice(2);
const bytes = new Uint8Array(readFileSync(file));
const now = () => performance.now();
const WARM = 3, RUNS = 10;

function stats(times) {
  const s = [...times].sort((a, b) => a - b);
  return { best: s[0], median: (s[(s.length - 1) >> 1] + s[s.length >> 1]) / 2 };
}
const fmt = (x) => x.toFixed(2);

function jsOnce() {
  const buf = bytes.slice(); // the worker's reader hands parseGi a fresh buffer each load (not timed)
  const t0 = now();
  const gi = prepareTextures(parseGi(buf));
  return { ms: now() - t0, gi };
}

async function loadWasm() {
  const t0 = now();
  const binary = readFileSync(wasmFile);
  const tRead = now();
  const module = await WebAssembly.compile(binary);
  const tCompile = now();
  let memory;
  const instance = await WebAssembly.instantiate(module, {
    env: { emscripten_notify_memory_growth: () => {} },
  });
  const tInst = now();
  const x = instance.exports;
  x._initialize?.();
  memory = x.memory;
  return { x, memory, compileMs: tCompile - tRead, instantiateMs: tInst - tCompile };
}

function wasmOnce(w, { copyOut = true } = {}) {
  const { x, memory } = w;
  const t0 = now();
  const p = x.gi_alloc(bytes.length);
  new Uint8Array(memory.buffer, p, bytes.length).set(bytes);
  const t1 = now();
  const r = x.gi_read(p, bytes.length);
  x.gi_dealloc(p); // the reader keeps its own copy of the body
  if (r !== 0) throw new Error(`gi_read ${r}: ${cstr(w, x.gi_error())}`);
  const t2 = now();
  if (x.gi_prepare() !== 0) throw new Error(`gi_prepare: ${cstr(w, x.gi_error())}`);
  const t3 = now();
  let out = null;
  if (copyOut) out = copyOutputs(w);
  const t4 = now();
  return { ms: t4 - t0, copyIn: t1 - t0, read: t2 - t1, prepare: t3 - t2, copyOut: t4 - t3, out };
}

// The GPU-ready arrays out of the WASM heap, as a worker would transfer them: own ArrayBuffers.
function copyOutputs({ x, memory }) {
  const heap = memory.buffer;
  const take = (p, n) => new Uint8Array(heap, p, n).slice();
  const atlasSize = x.gi_atlas_size();
  const out = {
    atlas: take(x.gi_atlas(), atlasSize),
    columns: { data: take(x.gi_columns(), x.gi_columns_size()), width: x.gi_columns_dim(0), height: x.gi_columns_dim(1) },
  };
  if (x.gi_sh(0)) out.sh = Array.from({ length: 6 }, (_, i) => take(x.gi_sh(i), atlasSize));
  return out;
}

function cstr({ memory }, p) {
  const h = new Uint8Array(memory.buffer);
  let e = p;
  while (h[e]) e++;
  return new TextDecoder().decode(h.subarray(p, e));
}

function same(a, b) {
  if (a.length !== b.length) return false;
  for (let i = 0; i < a.length; i++) if (a[i] !== b[i]) return false;
  return true;
}

if (mode === 'js') {
  const times = [];
  for (let i = 0; i < 1 + WARM + RUNS; i++) times.push(jsOnce().ms);
  const { best, median } = stats(times.slice(1 + WARM));
  // What the worker's reader adds per load for a gzip'd file besides the inflate: a CRC-32 of
  // the inflated bytes in JS (gi-stream.js take()). Reported, not in the figures above.
  const c0 = now(); crc32(bytes); const crcCold = now() - c0;
  const ct = []; for (let i = 0; i < 5; i++) { const c = now(); crc32(bytes); ct.push(now() - c); }
  console.log(JSON.stringify({ mode, file, cold: fmt(times[0]), best: fmt(best), median: fmt(median), crc32Cold: fmt(crcCold), crc32Best: fmt(stats(ct).best) }));
} else if (mode === 'wasm') {
  const w = await loadWasm();
  const runs = [];
  for (let i = 0; i < 1 + WARM + RUNS; i++) runs.push(wasmOnce(w));
  const timed = runs.slice(1 + WARM);
  const all = stats(timed.map((r) => r.ms));
  const part = (k) => fmt(stats(timed.map((r) => r[k])).median);
  const c = runs[0];
  console.log(JSON.stringify({
    mode, file, wasm: wasmFile, compile: fmt(w.compileMs), instantiate: fmt(w.instantiateMs),
    cold: fmt(c.ms), coldParts: { copyIn: fmt(c.copyIn), read: fmt(c.read), prepare: fmt(c.prepare), copyOut: fmt(c.copyOut) },
    best: fmt(all.best), median: fmt(all.median),
    medianParts: { copyIn: part('copyIn'), read: part('read'), prepare: part('prepare'), copyOut: part('copyOut') },
    heapMiB: w.memory.buffer.byteLength / 2 ** 20,
  }));
} else if (mode === 'both') {
  // Warm figures in one process, JS and WASM runs alternating (so that load from other
  // processes on the machine hits both alike): WARM each, then RUNS rounds.
  const w = await loadWasm();
  for (let i = 0; i < WARM; i++) { jsOnce(); wasmOnce(w); }
  const js = [], wa = [];
  for (let i = 0; i < RUNS; i++) { js.push(jsOnce().ms); wa.push(wasmOnce(w)); }
  const j = stats(js), a = stats(wa.map((r) => r.ms)), part = (k) => fmt(stats(wa.map((r) => r[k])).median);
  console.log(JSON.stringify({ mode, file, wasm: wasmFile, jsBest: fmt(j.best), jsMedian: fmt(j.median), wasmBest: fmt(a.best), wasmMedian: fmt(a.median),
    wasmMedianParts: { copyIn: part('copyIn'), read: part('read'), prepare: part('prepare'), copyOut: part('copyOut') } }));
} else if (mode === 'check') {
  const { gi } = jsOnce();
  // The indirection before prepareTextures drops it, for one more comparison.
  const raw = parseGi(bytes.slice());
  const w = await loadWasm();
  const r = wasmOnce(w);
  const ind = new Uint8Array(w.memory.buffer, w.x.gi_indirection(), w.x.gi_indirection_size()).slice();
  const res = {
    file,
    atlasBytes: gi.atlas.length,
    atlas: same(gi.atlas, r.out.atlas),
    indirection3D: same(raw.indirection, ind),
    columns: same(gi.columns.data, r.out.columns.data) && gi.columns.width === r.out.columns.width && gi.columns.height === r.out.columns.height,
    columnsDims: `${gi.columns.width}x${gi.columns.height}`,
    sh: gi.sh ? gi.sh.map((s, i) => same(s, r.out.sh[i])) : 'none (scalar)',
  };
  if (nativePrefix) {
    const n = (what) => new Uint8Array(readFileSync(`${nativePrefix}.${what}`));
    res.nativeAtlas = same(n('atlas'), gi.atlas);
    res.nativeColumns = same(n('columns'), gi.columns.data);
    if (gi.sh) res.nativeSh = gi.sh.map((s, i) => same(n(`sh${i}`), s));
  }
  console.log(JSON.stringify(res));
} else {
  console.error('usage: node bench.mjs js|wasm|check FILE.gi [W.wasm] [NATIVE_PREFIX]');
  process.exit(2);
}
