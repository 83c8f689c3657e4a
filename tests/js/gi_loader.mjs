// gi_loader.mjs: the CPU half of the JavaScript reading of docs/format.md.
// The file is read by web/gi-format.js, the very parser the browser runtime
// uses (DecompressionStream, DataView, every refusal docs/format.md lists);
// this adds the seed's lookup in float32 (Math.fround after every operation
// the shader does), so node can hold both to the C sampler.
import { decodeGi, indirectionColumns, layoutGeometry, LAYOUT_COMPACT, SH2_RANGE, termSlot } from '../../web/gi-format.js';

const f = Math.fround;

export const loadGi = decodeGi;

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
// With `detail`, also the spread (largest minus smallest) of each channel over
// the eight texels it blends, which bounds what a filter's weight error can do.
function sampleLinear(gi, uvw, detail, texel = atlasTexel) {
  const i0 = [], i1 = [], fr = [];
  for (let k = 0; k < 3; k++) {
    const dim = gi.atlasDims[k];
    const t = f(f(uvw[k] * dim) - 0.5);
    const fl = Math.floor(t);
    fr[k] = f(t - fl);
    i0[k] = clamp(fl, 0, dim - 1);
    i1[k] = clamp(fl + 1, 0, dim - 1);
  }
  const out = [0, 0, 0, 0], lo = [Infinity, Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity, -Infinity];
  for (let c = 0; c < 8; c++) {
    const w = f(f((c & 1 ? fr[0] : f(1 - fr[0])) * (c & 2 ? fr[1] : f(1 - fr[1]))) *
                (c & 4 ? fr[2] : f(1 - fr[2])));
    const t = texel(gi, c & 1 ? i1[0] : i0[0], c & 2 ? i1[1] : i0[1], c & 4 ? i1[2] : i0[2]);
    for (let k = 0; k < 4; k++) {
      out[k] = f(out[k] + f(w * t[k]));
      lo[k] = Math.min(lo[k], t[k]);
      hi[k] = Math.max(hi[k], t[k]);
    }
  }
  if (detail) {
    detail.filtered = out.slice();
    detail.spread = hi.map((h, k) => h - lo[k]);
  }
  return out;
}

// L2 term `term`'s three ratios at an atlas texel, as a snorm8 texture reads them
// (termSlot: version 8's terms 4-8 one byte for the three).
const termTexel = (term) => (gi, x, y, z) => {
  const [dx, dy] = gi.atlasDims;
  const out = [0, 0, 0, 0];
  for (let k = 0; k < 3; k++) {
    const [tex, comp, size] = termSlot(gi.shBytes, 3 * term + k);
    out[k] = Math.max(f(gi.sh[tex][size * ((z * dy + y) * dx + x) + comp] / 127), -1);
  }
  return out;
};

// The seed's volumeIrradiance(): NEAREST indirection, level and slot, LINEAR atlas, decode;
// the compact layout changes only where a brick's probes stand. With a unit
// normal and L2 terms (versions 6 and 7), what a surface facing it reads
// (docs/format.md, "Version 6"), in lib/format/sampler.c's float32 order.
export function sampleGi(gi, pos, detail = null, normal = null) {
  const p = [], base = [];
  for (let k = 0; k < 3; k++) {
    const box = f(f(pos[k] - gi.boxMin[k]) / f(gi.boxMax[k] - gi.boxMin[k]));
    p[k] = f(f(box * (gi.indDims[k] * 4)) - 0.5);
    base[k] = Math.floor(f(p[k] / 4));
  }
  // The runtime's indirection (docs/format.md): the cell's column, its run, the
  // run's texel; a cell outside the run reads 0,0,0,0 as the 3D texture would,
  // but for the compact layout's lift below it.
  const cols = (gi.columns ??= indirectionColumns(gi.indirection, gi.indDims));
  // texelFetch at (column, row), as the shader computes them; outside the texture, zeros.
  const bytesAt = (i) => {
    const w = cols.width;
    let row = Math.floor(f(f(i + 0.5) / w));
    const col0 = i - row * w;
    row += col0 < 0 ? -1 : col0 >= w ? 1 : 0;
    const col = i - row * w;
    if (col < 0 || col >= w || row < 0 || row >= cols.height) return [0, 0, 0, 0];
    const o = 4 * (row * w + col);
    return [0, 1, 2, 3].map((k) => Math.floor(f(f(f(cols.data[o + k] / 255) * 255) + 0.5)));
  };
  const [ix, , iz] = gi.indDims;
  const cell = base.map((v, k) => clamp(v, 0, gi.indDims[k] - 1));
  const c = cell[0] + ix * cell[2];
  const run = bytesAt(2 * c), at = bytesAt(2 * c + 1);
  const ymin = run[0] + 256 * run[1], count = run[2] + 256 * run[3];
  const compact = gi.layout === LAYOUT_COMPACT;
  // Compact: below its column's run a position reads the run's lowest brick at
  // its bottom plane (the lift): the cell and base rise to the run's first cell.
  const lift = compact && count > 0;
  if (lift) base[1] = Math.max(base[1], ymin);
  const k0 = lift ? Math.max(cell[1] - ymin, 0) : cell[1] - ymin;
  const entry = bytesAt(Math.min(2 * ix * iz + at[0] + 256 * at[1] + 65536 * at[2] + Math.max(k0, 0),
                                 cols.width * cols.height - 1));
  const b = k0 >= 0 && k0 < count ? entry : [0, 0, 0, 0];
  const geo = layoutGeometry(gi.layout);
  // Seed: rgb the slot, a the level + 1 (0: empty). Compact: a holds the level
  // in bits 0-1 and the brick's first texel mod 4 per axis above; rgb that texel / 4.
  const level = compact ? b[3] % 4 : Math.max(b[3] - 1, 0);
  if (detail) detail.level = compact ? (b.every((v) => v === 0) ? -1 : level) : b[3] - 1; // -1: no brick
  const span = f(2 ** level);
  const uvw = [];
  for (let k = 0; k < 3; k++) {
    const first = compact ? b[k] * 4 + (Math.floor(b[3] / 4 ** (k + 1)) % 4) : b[k] * geo.brick + geo.pad;
    const originCell = f(f(Math.floor(f(base[k] / span)) * span) * 4);
    // Seed: probe q at the centre of its span-wide block; compact: at its corner.
    const q0 = f(f(f(f(p[k] - originCell) + geo.centre) / span) - geo.centre);
    const q = compact && k === 1 ? Math.max(q0, 0) : q0; // the lift's bottom plane
    const texel = f(first + q);
    uvw[k] = f(f(texel + 0.5) / gi.atlasDims[k]);
  }
  const s = sampleLinear(gi, uvw, detail);
  const rgb = gi.encoding === 1 ? [s[0], s[1], s[2]]
                                : [0, 1, 2].map((k) => f(f(s[k] * s[3]) * gi.rgbmRange));
  if (!normal || !gi.sh) return rgb;
  const [x, y, z] = normal;
  const poly = [x, y, z, f(x * y), f(y * z), f(f(f(3 * z) * z) - 1), f(x * z), f(f(x * x) - f(y * y))];
  const sum = [1, 1, 1];
  // detail.termWeight[k]: how far channel k's sum moves per unit of filter error, over the terms.
  if (detail) detail.termWeight = [0, 0, 0];
  for (let t = 0; t < 8; t++) {
    const d = detail ? {} : null;
    const r = sampleLinear(gi, uvw, d, termTexel(t));
    for (let k = 0; k < 3; k++) {
      sum[k] = f(sum[k] + f(f(r[k] * SH2_RANGE[t]) * poly[t]));
      if (detail) detail.termWeight[k] += d.spread[k] * SH2_RANGE[t] * Math.abs(poly[t]);
    }
  }
  if (detail) {
    detail.sum = sum;
    detail.l0 = rgb;
  }
  return rgb.map((v, k) => Math.max(f(v * sum[k]), 0));
}
