// gi-wasm.js: the rebuild of a packed .gi (versions 5 to 8) by lib/'s C reader
// built to WebAssembly (wasm/gi-reader.c), which the decoding worker runs in
// place of gi-packed.js's: the same bytes in less time (docs/web.md, "The
// WebAssembly reader"). `make` builds it into gi-reader-wasm.js, its
// binary as base64 (a module beside this one, so that wherever the worker's
// scripts are served or bundled it is too, with no .wasm MIME type to set).
// Where that module is missing or WebAssembly cannot run, the caller keeps
// gi-packed.js's rebuild. No three.js here.
import { rebuildPacked, termBytes } from './gi-packed.js';

const ENOSYS = 52; // WASI's "not implemented": what any system call the C library makes gets

// The reader's instance, once: a rebuild(gi, payload, file) as gi-packed.js's
// rebuildPacked (file: the whole inflated .gi, header and payload), or null.
// A file it refuses goes to gi-packed.js's rebuild, which says why in the page
// reader's words (the ones docs/web.md and the tests hold); with { strict: true }
// it throws the C reader's own.
let ready = null;
export function wasmRebuild() {
  ready ??= instantiate().catch(() => null);
  return ready;
}

async function instantiate() {
  if (typeof WebAssembly === 'undefined') return null;
  const { default: base64 } = await import('./gi-reader-wasm.js');
  const text = atob(base64), binary = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) binary[i] = text.charCodeAt(i);
  const module = await WebAssembly.compile(binary);
  // The C library's few system calls (stdio it links but never uses here) fail.
  const imports = {};
  for (const { module: from, name, kind } of WebAssembly.Module.imports(module)) {
    if (kind !== 'function') throw new Error(`the reader imports a ${kind}`);
    (imports[from] ??= {})[name] = () => ENOSYS;
  }
  const x = (await WebAssembly.instantiate(module, imports)).exports;
  x._initialize?.();
  const state = { x, trapped: false };
  return (gi, payload, file, { strict = false } = {}) => rebuild(state, gi, payload, file, strict);
}

// A copy of n bytes at p in the instance's memory (which the next read reuses).
const copy = (x, p, n) => new Uint8Array(x.memory.buffer, p, n).slice();

// The C string at p.
const said = (x, p) => {
  const bytes = new Uint8Array(x.memory.buffer, p);
  return new TextDecoder().decode(bytes.subarray(0, bytes.indexOf(0)));
};

// The result has reader: 'wasm' where the C reader made it. After a trap (an abort in
// the C code) its memory may be inconsistent: the instance is not called again.
function rebuild(state, gi, payload, file, strict) {
  const { x } = state;
  try {
    if (state.trapped) throw new Error('the reader trapped on an earlier file');
    const out = read(x, gi, file);
    x.gi_free();
    return { ...out, reader: 'wasm' };
  } catch (e) {
    state.trapped ||= e instanceof WebAssembly.RuntimeError;
    if (!state.trapped) x.gi_free();
    if (strict) throw e;
  }
  return rebuildPacked(gi, payload);
}

// The C reader's textures, or an Error with its words (a trap too: an abort in the C code).
// Its pointers and sizes are unsigned: >>> 0.
function read(x, gi, file) {
  const p = x.gi_alloc(file.length) >>> 0;
  if (!p) throw new Error(`no memory for ${file.length} bytes`);
  new Uint8Array(x.memory.buffer, p, file.length).set(file);
  if (x.gi_read(p, file.length)) throw new Error(said(x, x.gi_error() >>> 0)); // (it freed p)
  const out = {
    indirection: copy(x, x.gi_indirection() >>> 0, x.gi_indirection_size() >>> 0),
    atlas: copy(x, x.gi_atlas() >>> 0, x.gi_atlas_size() >>> 0),
    storedPoints: x.gi_stored_points() >>> 0,
  };
  if (gi.version >= 6) out.sh = splitTerms(x, gi.version, out.atlas.length / 4);
  return out;
}

// The reader's 24 term bytes a texel as gi.sh's textures: term byte j of the version's
// (vdbgi_term_byte: version 8's bytes 9-13 are terms 4-8's red) in texture j >> 2,
// component j & 3. A word at a time where four bytes go together (versions 6 and 7, and
// version 8's first two textures), else a byte.
function splitTerms(x, version, texels) {
  const at = x.gi_terms() >>> 0, bytes = termBytes(version);
  const width = (j) => Math.min(bytes - (j & ~3), 4);
  const sh = [];
  for (let j = 0; j < bytes; j += 4) sh.push(new Int8Array(texels * width(j)));
  const words = new Uint32Array(x.memory.buffer, at, 6 * texels); // vdbgi_alloc keeps malloc's alignment
  const whole = version >= 8 ? 2 : 6;
  for (let i = 0; i < whole; i++) {
    const out = new Uint32Array(sh[i].buffer);
    for (let t = 0, o = i; t < texels; t++, o += 6) out[t] = words[o];
  }
  const src = new Int8Array(x.memory.buffer, at, 24 * texels);
  for (let j = 4 * whole; j < bytes; j++) {
    const out = sh[j >> 2], w = width(j), c = j & 3;
    for (let t = 0, o = j < 9 ? j : 9 + 3 * (j - 9); t < texels; t++, o += 24) out[t * w + c] = src[o];
  }
  return sh;
}
