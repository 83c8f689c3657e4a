// gi_loader.mjs: an independent loader and sampler for .gi files, written from
// docs/format.md alone, the way a web page would load one: gunzip through
// DecompressionStream('gzip'), parse the header with a DataView, and run the
// seed's lookup in float32 (Math.fround after every operation the shader does).
// It refuses, with an Error, every file docs/format.md says a reader must refuse.
import { DecompressionStream } from 'node:stream/web';

const f = Math.fround;

async function gunzip(bytes) {
  const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('gzip'));
  const reader = stream.getReader();
  const chunks = [];
  let length = 0;
  for (;;) {
    const { done, value } = await reader.read();
    if (done) break;
    chunks.push(value);
    length += value.length;
  }
  const out = new Uint8Array(length);
  let at = 0;
  for (const c of chunks) { out.set(c, at); at += c.length; }
  return out;
}

export async function loadGi(fileBytes) {
  const buf = await gunzip(fileBytes);
  // DecompressionStream ignores bytes after the stream; its trailer's length must end the file.
  const tail = new DataView(fileBytes.buffer, fileBytes.byteOffset, fileBytes.byteLength);
  if (fileBytes.length < 4 || tail.getUint32(fileBytes.length - 4, true) !== buf.length >>> 0)
    throw new Error('bytes after the gzip stream');
  if (buf.length < 112) throw new Error('shorter than a .gi header');
  const dv = new DataView(buf.buffer, buf.byteOffset, buf.byteLength);
  const magic = new TextDecoder().decode(buf.subarray(0, 8));
  if (magic !== 'vdbgi.gi') throw new Error('not a .gi file');
  const u32 = (o) => dv.getUint32(o, true);
  const f32 = (o) => dv.getFloat32(o, true);
  const vec = (o, get) => [get(o), get(o + 4), get(o + 8)];
  const version = u32(8);
  if (version !== 1 && version !== 2) throw new Error(`unsupported version ${version}`);
  // Version 1 is seed 000's layout (6^3 texels a brick); version 2 says which at byte 104.
  const layout = version === 2 ? u32(104) : 0;
  if (layout > 1 || (version === 1 && u32(104) !== 0)) throw new Error(`unknown layout ${u32(104)}`);
  const headerSize = u32(12);
  const gi = {
    layout,
    encoding: u32(16),
    rgbmRange: f32(20),
    indDims: vec(24, u32),
    atlasDims: vec(36, u32),
    boxMin: vec(48, f32),
    boxMax: vec(60, f32),
    spacing: f32(72),
    maxLevel: u32(76),
    bricks: [u32(80), u32(84), u32(88), u32(92)],
  };
  // Every limit docs/format.md states, so that no lookup can leave the textures.
  const b = layout === 1 ? 5 : 6;
  if (headerSize < 112 || headerSize > 65536) throw new Error(`bad header size ${headerSize}`);
  if (gi.encoding > 1) throw new Error(`unknown encoding ${gi.encoding}`);
  if (!(gi.rgbmRange > 0) || !Number.isFinite(gi.rgbmRange)) throw new Error('bad RGBM range');
  for (let k = 0; k < 3; k++) {
    if (gi.indDims[k] < 1 || gi.indDims[k] > 2048) throw new Error('bad indirection size');
    if (gi.atlasDims[k] < b || gi.atlasDims[k] > 256 * b || gi.atlasDims[k] % b)
      throw new Error('bad atlas size');
    if (!Number.isFinite(gi.boxMin[k]) || !Number.isFinite(gi.boxMax[k]) || !(gi.boxMax[k] > gi.boxMin[k]))
      throw new Error('bad volume box');
  }
  if (gi.maxLevel > 3) throw new Error('bad max level');
  const indBytes = u32(96), atlasBytes = u32(100);
  const prod = (d) => d[0] * d[1] * d[2] * 4;
  if (indBytes !== prod(gi.indDims) || atlasBytes !== prod(gi.atlasDims))
    throw new Error('texture sizes disagree with their dimensions');
  if (buf.length !== headerSize + indBytes + atlasBytes)
    throw new Error(`file holds ${buf.length} bytes, header says ${headerSize + indBytes + atlasBytes}`);
  gi.indirection = buf.subarray(headerSize, headerSize + indBytes);
  gi.atlas = buf.subarray(headerSize + indBytes);
  const slots = gi.atlasDims.map((d) => d / b);
  for (let i = 0; i < indBytes; i += 4) {
    const t = gi.indirection.subarray(i, i + 4);
    if (t[3] !== 0 && (t[0] >= slots[0] || t[1] >= slots[1] || t[2] >= slots[2] || t[3] > gi.maxLevel + 1))
      throw new Error(`indirection texel ${i / 4} points outside the atlas`);
  }
  return gi;
}

const clamp = (v, lo, hi) => Math.min(Math.max(v, lo), hi);

function atlasTexel(gi, x, y, z) {
  const [dx, dy] = gi.atlasDims;
  const o = 4 * ((z * dy + y) * dx + x);
  const t = gi.atlas;
  if (gi.encoding === 1) {
    const w = (t[o] | (t[o + 1] << 8) | (t[o + 2] << 16) | (t[o + 3] << 24)) >>> 0;
    const scale = 2 ** ((w >>> 27) - 24);
    return [f((w & 511) * scale), f(((w >>> 9) & 511) * scale), f(((w >>> 18) & 511) * scale), 1];
  }
  return [f(t[o] / 255), f(t[o + 1] / 255), f(t[o + 2] / 255), f(t[o + 3] / 255)];
}

// A texture unit's LINEAR filter at normalised coordinates, clamp to edge.
function sampleLinear(gi, uvw) {
  const i0 = [], i1 = [], fr = [];
  for (let k = 0; k < 3; k++) {
    const dim = gi.atlasDims[k];
    const t = f(f(uvw[k] * dim) - 0.5);
    const fl = Math.floor(t);
    fr[k] = f(t - fl);
    i0[k] = clamp(fl, 0, dim - 1);
    i1[k] = clamp(fl + 1, 0, dim - 1);
  }
  const out = [0, 0, 0, 0];
  for (let c = 0; c < 8; c++) {
    const w = f(f((c & 1 ? fr[0] : f(1 - fr[0])) * (c & 2 ? fr[1] : f(1 - fr[1]))) *
                (c & 4 ? fr[2] : f(1 - fr[2])));
    const t = atlasTexel(gi, c & 1 ? i1[0] : i0[0], c & 2 ? i1[1] : i0[1], c & 4 ? i1[2] : i0[2]);
    for (let k = 0; k < 4; k++) out[k] = f(out[k] + f(w * t[k]));
  }
  return out;
}

// The seed's volumeIrradiance(): NEAREST indirection, level and slot, LINEAR atlas, decode;
// the compact layout changes only where a brick's probes stand.
export function sampleGi(gi, pos) {
  const p = [], base = [];
  for (let k = 0; k < 3; k++) {
    const box = f(f(pos[k] - gi.boxMin[k]) / f(gi.boxMax[k] - gi.boxMin[k]));
    p[k] = f(f(box * (gi.indDims[k] * 4)) - 0.5);
    base[k] = Math.floor(f(p[k] / 4));
  }
  const it = base.map((b, k) => clamp(Math.floor(f(f(f(b + 0.5) / gi.indDims[k]) * gi.indDims[k])), 0, gi.indDims[k] - 1));
  const [ix, iy] = gi.indDims;
  const o = 4 * ((it[2] * iy + it[1]) * ix + it[0]);
  const ind = [0, 1, 2, 3].map((k) => f(gi.indirection[o + k] / 255));
  const level = Math.max(f(f(ind[3] * 255) - 1), 0);
  const span = f(2 ** level);
  const uvw = [];
  for (let k = 0; k < 3; k++) {
    const slot = f(ind[k] * 255);
    const originCell = f(f(Math.floor(f(base[k] / span)) * span) * 4);
    let texel;
    if (gi.layout === 1) { // compact: probe q at originCell + q * span, 5^3 texels a brick
      const q = f(f(p[k] - originCell) / span);
      texel = f(f(slot * 5) + q);
    } else {
      const q = f(f(f(f(p[k] - originCell) + 0.5) / span) - 0.5);
      texel = f(f(f(slot * 6) + 1) + q);
    }
    uvw[k] = f(f(texel + 0.5) / gi.atlasDims[k]);
  }
  const s = sampleLinear(gi, uvw);
  return gi.encoding === 1 ? [s[0], s[1], s[2]]
                           : [0, 1, 2].map((k) => f(f(s[k] * s[3]) * gi.rgbmRange));
}
