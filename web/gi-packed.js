// gi-packed.js: the runtime textures of a version 5 to 8 .gi (docs/format.md,
// "Version 5" to "Version 8"), rebuilt from its level bytes, its bricks'
// places and the probe values (and L2 terms) it stores once. Bit for bit what lib/format/packed.c rebuilds: every float operation below
// is a float32 one (Math.fround) in the C code's order, and the encoders
// round as the C ones do, so a test can compare the two byte for byte.

import { now, yieldToPage, SLICE_MS } from './gi-stream.js';

const N = 5, TEXELS = 125, PAD = 2;
const f = Math.fround;

// A version 5 atlas holds at most this many texels a brick (docs/format.md); gi-format.js
// checks it with the header, before the atlas is weighed against the budget.
export const ATLAS_TEXELS_PER_BRICK = 500;

// The L2 terms' bytes a stored point and a texel hold: 24 (versions 6 and 7: eight
// terms x RGB), or 14 (version 8: terms 1-3 x RGB, then terms 4-8 one byte each,
// the ratio of their luminance that the three channels share).
export const SH_BYTES = 24;
export const SH_BYTES_LUMA2 = 14;
export const termBytes = (version) => (version >= 8 ? SH_BYTES_LUMA2 : SH_BYTES);

// Where term byte j (3 term + channel, 0..23) of a texel lies in gi.sh, for a volume of
// shBytes term bytes a texel: [texture, component, components a texel of that texture].
// Versions 6 and 7: six RGBA8 textures. Version 8: three RGBA8 and one RG8, terms 4-8's
// three channels one byte.
export function termSlot(shBytes, j) {
  if (shBytes !== SH_BYTES_LUMA2) return [j >> 2, j & 3, 4];
  const b = j < 9 ? j : 9 + Math.floor((j - 9) / 3);
  return [b >> 2, b & 3, b < 12 ? 4 : 2];
}

// Each brick's first atlas texel from the placement table (u16 x of every
// brick, then y, then z), checked as lib/format/packed.c checks it: inside the
// atlas, in a layer (y a multiple of 5), sharing texels only with bricks of
// its level that hold the same lattice points there, and never the block of
// zeros at the atlas's corner. blockTexel: each texel's place in a brick's block
// of the atlas, from the block's first texel (blockTexels).
function* readPlacement(table, keys, lv, dims, blockTexel) {
  const count = keys.length;
  const dv = new DataView(table.buffer, table.byteOffset, table.byteLength);
  const origin = new Uint16Array(3 * count);
  for (let b = 0; b < count; b++) {
    for (let k = 0; k < 3; k++) origin[3 * b + k] = dv.getUint16(2 * (k * count + b), true);
    const x = origin[3 * b], y = origin[3 * b + 1], z = origin[3 * b + 2];
    if (x + N > dims[0] || y + N > dims[1] || z + N > dims[2] || y % N)
      throw new Error(`brick ${b} at texel ${x},${y},${z} is not in a layer of the ${dims.join('x')} atlas`);
  }
  const owner = new Uint32Array(dims[0] * dims[1] * dims[2]);
  const ZERO = 0xffffffff;
  for (let t = 0; t < TEXELS; t++) owner[blockTexel[t]] = ZERO;
  // Layer by layer, in brick order within one, as lib/format/packed.c (the first overlap found is the one named).
  const order = Array.from({ length: count }, (_, b) => b).sort((a, b) => origin[3 * a + 1] - origin[3 * b + 1] || a - b);
  yield* strides(count, STRIDE, (n) => {
    const b = order[n], ox = origin[3 * b], oy = origin[3 * b + 1], oz = origin[3 * b + 2];
    const base = (oz * dims[1] + oy) * dims[0] + ox;
    for (let t = 0; t < TEXELS; t++) {
      const i = base + blockTexel[t];
      if (owner[i] === 0) {
        owner[i] = b + 1;
        continue;
      }
      const j = owner[i] - 1, kj = keys[j], kb = keys[b];
      const same = owner[i] !== ZERO && lv[j] === lv[b] && origin[3 * j] - 4 * kj[0] === ox - 4 * kb[0] &&
        origin[3 * j + 1] - 4 * kj[1] === oy - 4 * kb[1] && origin[3 * j + 2] - 4 * kj[2] === oz - 4 * kb[2];
      if (!same) {
        const x = ox + (t % N), y = oy + (Math.floor(t / N) % N), z = oz + Math.floor(t / (N * N));
        throw new Error(`brick ${b} overlaps ${owner[i] === ZERO ? 'the block of zeros' : "another brick's points"} at texel ${x},${y},${z}`);
      }
    }
  });
  return origin;
}

// Each texel t of a brick's 5^3 block: its place in an atlas of dims from the block's first texel.
function blockTexels(dims) {
  const off = new Int32Array(TEXELS);
  for (let t = 0; t < TEXELS; t++)
    off[t] = (Math.floor(t / (N * N)) * dims[1] + Math.floor(t / N) % N) * dims[0] + (t % N);
  return off;
}

const popcount = (x) => {
  x -= (x >>> 1) & 0x55555555;
  x = (x & 0x33333333) + ((x >>> 2) & 0x33333333);
  return (((x + (x >>> 4)) & 0x0f0f0f0f) * 0x01010101) >>> 24;
};

// Round to nearest, ties to even, as C's lrintf.
function rint(x) {
  const r = Math.round(x);
  return r - x === 0.5 && r % 2 !== 0 ? r - 1 : r;
}

const f32 = new Float32Array(1), u32 = new Uint32Array(f32.buffer);

function rgbmDecode(b, o, range, out) {
  const m = f(f(b[o + 3] / 255) * range);
  for (let k = 0; k < 3; k++) out[k] = f(f(b[o + k] / 255) * m);
}

function rgb9e5Decode(b, o, out) {
  const w = (b[o] | (b[o + 1] << 8) | (b[o + 2] << 16) | (b[o + 3] << 24)) >>> 0;
  const scale = 2 ** ((w >>> 27) - 24);
  for (let k = 0; k < 3; k++) out[k] = f(((w >>> (9 * k)) & 511) * scale);
}

const sanitise = (c) => (c > 0 ? c : 0);

function rgbmEncode(rgb, range, b, o) {
  const c = [sanitise(rgb[0]), sanitise(rgb[1]), sanitise(rgb[2])];
  const mx = Math.max(c[0], c[1], c[2]);
  if (!(mx > 0)) {
    b.fill(0, o, o + 4);
    return false;
  }
  let m8 = Math.ceil(f(Math.min(f(mx / range), 1) * 255));
  if (m8 < 1) m8 = 1;
  const scale = f(f(m8 / 255) * range);
  for (let k = 0; k < 3; k++) b[o + k] = rint(f(Math.min(f(c[k] / scale), 1) * 255));
  b[o + 3] = m8;
  return mx > range;
}

function rgb9e5Encode(rgb, b, o) {
  const MAX = 65408;
  const c = [0, 1, 2].map((k) => Math.min(sanitise(rgb[k]), MAX));
  const mx = Math.max(c[0], c[1], c[2]);
  f32[0] = mx;
  // floor(log2(mx)) from the float's exponent bits (exact); tiny values clamp anyway.
  let exp = mx >= 2 ** -126 ? ((u32[0] >>> 23) & 255) - 127 : -127;
  if (exp < -16) exp = -16;
  exp += 16;
  let denom = 2 ** (exp - 24);
  if (Math.floor(mx / denom + 0.5) === 512) {
    exp += 1;
    denom *= 2;
  }
  const w = (Math.floor(c[0] / denom + 0.5) | (Math.floor(c[1] / denom + 0.5) << 9) |
    (Math.floor(c[2] / denom + 0.5) << 18) | (exp << 27)) >>> 0;
  b[o] = w & 255, b[o + 1] = (w >>> 8) & 255, b[o + 2] = (w >>> 16) & 255, b[o + 3] = w >>> 24;
  return rgb.some((v) => v > MAX);
}

// Trilinear over a compact brick's 5^3 float samples at fine lattice point p (lib/convert/coarsen.c).
function interpolate(s, key, level, p, out) {
  const span = f(1 << level);
  const i0 = [0, 0, 0], fr = [0, 0, 0];
  for (let k = 0; k < 3; k++) {
    const origin = f(f(key[k] * 4) * span);
    const t = f(f(p[k] - origin) / span);
    const fl = Math.floor(t);
    i0[k] = fl;
    fr[k] = f(t - fl);
    if (i0[k] > N - 2) {
      i0[k] = N - 2;
      fr[k] = 1;
    }
  }
  out[0] = out[1] = out[2] = 0;
  for (let c = 0; c < 8; c++) {
    const w = f(f((c & 1 ? fr[0] : f(1 - fr[0])) * (c & 2 ? fr[1] : f(1 - fr[1]))) *
      (c & 4 ? fr[2] : f(1 - fr[2])));
    const x = i0[0] + (c & 1), y = i0[1] + ((c >> 1) & 1), z = i0[2] + ((c >> 2) & 1);
    const v = 3 * ((z * N + y) * N + x);
    for (let k = 0; k < 3; k++) out[k] = f(out[k] + f(w * s[v + k]));
  }
}

// Rebuild { indirection, atlas, storedPoints } from a version 5 to 8 payload, or
// throw an Error naming what is inconsistent. `gi` is the parsed header.
export function rebuildPacked(gi, payload) {
  const steps = rebuildSteps(gi, payload);
  for (;;) {
    const { done, value } = steps.next();
    if (done) return value;
  }
}

// The same, giving the page back every `sliceMs` of work (a 1 MB L2 file is half a
// second of it), so that no task of the page's runs much longer than that.
export async function rebuildPackedSliced(gi, payload, sliceMs = SLICE_MS) {
  const steps = rebuildSteps(gi, payload);
  let start = now();
  for (;;) {
    const { done, value } = steps.next();
    if (done) return value;
    if (now() - start > sliceMs) {
      await yieldToPage();
      start = now();
    }
  }
}

// Bricks or grid cells between the rebuild's checks of the time.
const STRIDE = 128;

// fn(i) for i in 0..n-1, yielding before every `stride` of them. The loop over a
// stride runs in a plain function, which V8 optimises while it runs; a once-called
// generator's own loops it optimised late or not at all (a first rebuild of an L2
// file took 1.4x the time with the loops written in the generator).
const run = (from, to, fn) => {
  for (let i = from; i < to; i++) fn(i);
};
function* strides(n, stride, fn) {
  for (let i = 0; i < n; i += stride) {
    yield;
    run(i, Math.min(i + stride, n), fn);
  }
}

// The rebuild, as a generator that yields between strides of its work.
function* rebuildSteps(gi, payload) {
  const d = gi.indDims, cells = d[0] * d[1] * d[2];
  const levels = payload.subarray(0, cells);
  const cellAt = (x, y, z) => (z * d[1] + y) * d[0] + x;
  // The bricks, in scan order: each met at its block's first cell; no more than the header counts.
  const keys = [], lv = [], most = gi.bricks.reduce((a, b) => a + b, 0), perLevel = [0, 0, 0, 0];
  yield* strides(d[1] * d[2], 1, (row) => {
    const y = row % d[1], z = Math.floor(row / d[1]);
    for (let x = 0; x < d[0]; x++) {
      const b = levels[cellAt(x, y, z)];
      if (b === 0) continue;
      if (b > gi.maxLevel + 1)
        throw new Error(`cell ${x},${y},${z} has level ${b - 1}, above the file's max level ${gi.maxLevel}`);
      const span = 1 << (b - 1);
      const fx = x - (x % span), fy = y - (y % span), fz = z - (z % span);
      if (fx !== x || fy !== y || fz !== z) {
        if (levels[cellAt(fx, fy, fz)] !== b)
          throw new Error(`cell ${x},${y},${z} is level ${b - 1} but its block's first cell is not`);
        continue;
      }
      for (let k = z; k < Math.min(z + span, d[2]); k++)
        for (let j = y; j < Math.min(y + span, d[1]); j++)
          for (let i = x; i < Math.min(x + span, d[0]); i++)
            if (levels[cellAt(i, j, k)] !== b)
              throw new Error(`the level-${b - 1} block at cell ${x},${y},${z} has a cell of another level`);
      // Counted past the header's total (for the message), listed only up to it.
      perLevel[b - 1]++;
      if (keys.length === most) continue;
      keys.push([x / span, y / span, z / span]);
      lv.push(b - 1);
    }
  });
  const count = keys.length;
  for (let l = 0; l < 4; l++)
    if (perLevel[l] !== gi.bricks[l]) throw new Error(`bricks[${l}] says ${gi.bricks[l]}, the level bytes hold ${perLevel[l]}`);
  // Each cell's brick, for the stitching.
  const cellBrick = new Int32Array(cells).fill(-1);
  const brickCells = (b, fn) => {
    const span = 1 << lv[b], key = keys[b], x0 = key[0] * span, y0 = key[1] * span, z0 = key[2] * span;
    for (let z = z0; z < Math.min(z0 + span, d[2]); z++)
      for (let y = y0; y < Math.min(y0 + span, d[1]); y++)
        for (let x = x0; x < Math.min(x0 + span, d[0]); x++) fn(cellAt(x, y, z));
  };
  yield* strides(count, STRIDE, (b) => {
    brickCells(b, (c) => { cellBrick[c] = b; });
  });
  const dims = gi.atlasDims, blockTexel = blockTexels(dims);
  const origin = yield* readPlacement(payload.subarray(cells, cells + 6 * count), keys, lv, dims, blockTexel);
  // Indirection: r, g, b the brick's first texel / 4; a its level, and the texel mod 4 per axis.
  const indirection = new Uint8Array(4 * cells);
  yield* strides(count, STRIDE, (b) => {
    const o = origin.subarray(3 * b, 3 * b + 3);
    const t = [o[0] >> 2, o[1] >> 2, o[2] >> 2, lv[b] | ((o[0] & 3) << 2) | ((o[1] & 3) << 4) | ((o[2] & 3) << 6)];
    brickCells(b, (c) => indirection.set(t, 4 * c));
  });
  const point = [0, 0, 0];
  const texelPoint = (b, t, p) => {
    const span = 1 << lv[b], key = keys[b];
    p[0] = (key[0] * 4 + (t % N)) * span;
    p[1] = (key[1] * 4 + (Math.floor(t / N) % N)) * span;
    p[2] = (key[2] * 4 + Math.floor(t / (N * N))) * span;
  };
  // The coarsest brick whose cells touch lattice point p, if coarser than level.
  let coarseIndex = 0, coarseLevel = 0;
  const coarserBrickAt = (p, level) => {
    let best = level;
    for (let c = 0; c < 8; c++) {
      const dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
      const x = (p[0] >> 2) - dx, y = (p[1] >> 2) - dy, z = (p[2] >> 2) - dz;
      if ((dx && p[0] % 4) || (dy && p[1] % 4) || (dz && p[2] % 4)) continue;
      if (x < 0 || y < 0 || z < 0 || x >= d[0] || y >= d[1] || z >= d[2]) continue;
      const j = cellBrick[cellAt(x, y, z)];
      if (j < 0 || lv[j] <= best) continue;
      best = lv[j];
      coarseIndex = j;
    }
    coarseLevel = best;
    return best > level;
  };
  // Which texels take a coarser brick's value: none unless a cell around the block is coarser.
  const stitch = new Uint32Array(4 * count);
  yield* strides(count, STRIDE, (b) => {
    const span = 1 << lv[b];
    let near = false;
    const key = keys[b];
    const x0 = Math.max(key[0] * span - 1, 0), x1 = Math.min(key[0] * span + span, d[0] - 1);
    const y0 = Math.max(key[1] * span - 1, 0), y1 = Math.min(key[1] * span + span, d[1] - 1);
    const z0 = Math.max(key[2] * span - 1, 0), z1 = Math.min(key[2] * span + span, d[2] - 1);
    for (let z = z0; z <= z1 && !near; z++)
      for (let y = y0; y <= y1 && !near; y++)
        for (let x = x0; x <= x1 && !near; x++) {
          const j = cellBrick[cellAt(x, y, z)];
          near = j >= 0 && lv[j] > lv[b];
        }
    if (!near) return;
    for (let t = 0; t < TEXELS; t++) {
      if (t % N % 4 && Math.floor(t / N) % N % 4 && Math.floor(t / (N * N)) % 4) continue;
      texelPoint(b, t, point);
      if (coarserBrickAt(point, lv[b])) stitch[4 * b + (t >> 5)] |= 1 << (t & 31);
    }
  });
  // Sets point, coarseIndex and coarseLevel for a stitched texel.
  const stitched = (b, t) => {
    if (!((stitch[4 * b + (t >> 5)] >>> (t & 31)) & 1)) return false;
    texelPoint(b, t, point);
    return coarserBrickAt(point, lv[b]);
  };
  // The stored points, a mask of 64 a cell (two words) and each cell's first index.
  const g = d.map((v) => v + PAD), gcells = g[0] * g[1] * g[2];
  const lo32 = new Uint32Array(gcells), hi32 = new Uint32Array(gcells), offset = new Uint32Array(gcells);
  const gridAt = (p) => {
    const cx = p[0] >> 2, cy = p[1] >> 2, cz = p[2] >> 2;
    if (p[0] < 0 || p[1] < 0 || p[2] < 0 || cx >= g[0] || cy >= g[1] || cz >= g[2]) return -1;
    return (cz * g[1] + cy) * g[0] + cx;
  };
  const bitOf = (p) => ((p[2] & 3) * 4 + (p[1] & 3)) * 4 + (p[0] & 3);
  yield* strides(count, STRIDE, (b) => {
    const span = 1 << lv[b], key = keys[b], any = stitch[4 * b] | stitch[4 * b + 1] | stitch[4 * b + 2] | stitch[4 * b + 3];
    for (let t = 0, qz = 0; qz < N; qz++)
      for (let qy = 0; qy < N; qy++)
        for (let qx = 0; qx < N; qx++, t++) {
          if (any && stitched(b, t)) continue;
          point[0] = (key[0] * 4 + qx) * span, point[1] = (key[1] * 4 + qy) * span, point[2] = (key[2] * 4 + qz) * span;
          const c = gridAt(point);
          if (c < 0) continue;
          const bit = bitOf(point);
          if (bit < 32) lo32[c] |= 1 << bit;
          else hi32[c] |= 1 << (bit - 32);
        }
  });
  let points = 0;
  for (let c = 0; c < gcells; c++) {
    offset[c] = points;
    points += popcount(lo32[c]) + popcount(hi32[c]);
  }
  if (points !== gi.storedPoints)
    throw new Error(`the bricks read ${points} points, the header says ${gi.storedPoints} are stored`);
  // The stored point at lattice point x, y, z, or -1.
  const at3 = (x, y, z) => {
    if (x < 0 || y < 0 || z < 0) return -1;
    const cx = x >> 2, cy = y >> 2, cz = z >> 2;
    if (cx >= g[0] || cy >= g[1] || cz >= g[2]) return -1;
    const c = (cz * g[1] + cy) * g[0] + cx, bit = ((z & 3) * 4 + (y & 3)) * 4 + (x & 3);
    if (bit < 32) {
      if (!((lo32[c] >>> bit) & 1)) return -1;
      return offset[c] + popcount(lo32[c] & ((1 << bit) - 1));
    }
    if (!((hi32[c] >>> (bit - 32)) & 1)) return -1;
    return offset[c] + popcount(lo32[c]) + popcount(hi32[c] & ((1 << (bit - 32)) - 1));
  };
  const indexOf = (p) => at3(p[0], p[1], p[2]);
  // The values: residuals against a prediction from the -x, -y, -x-y and -z
  // neighbours (docs/format.md, step 5), plane by plane; an RGBM multiplier
  // before the colour bytes it rescales the neighbours' colours to.
  const planes = payload.subarray(cells + 6 * count);
  const values = new Uint8Array(4 * points);
  const rgbm = gi.encoding === 0;
  const order = rgbm ? [3, 0, 1, 2] : [0, 1, 2, 3];
  const rescaled = (j, k, m) => {
    if (m === 0) return values[4 * j + k];
    return Math.min(Math.floor((2 * values[4 * j + k] * values[4 * j + 3] + m) / (2 * m)), 255);
  };
  // LOCO-I's median edge detector on the -x, -y and -x-y neighbours' numbers.
  const medianEdge = (A, B, C) => {
    const lo = Math.min(A, B), hi = Math.max(A, B);
    return C >= hi ? lo : C <= lo ? hi : A + B - C;
  };
  // Every stored point in storage order, visit(i, x, y, z), yielding between strides of grid cells.
  function* forEachPoint(visit) {
    yield* strides(gcells, 8 * STRIDE, (c) => {
      if (!lo32[c] && !hi32[c]) return;
      const cx = c % g[0], cy = Math.floor(c / g[0]) % g[1], cz = Math.floor(c / (g[0] * g[1]));
      for (let bit = 0, i = offset[c]; bit < 64; bit++) {
        if (!(((bit < 32 ? lo32[c] : hi32[c]) >>> (bit & 31)) & 1)) continue;
        visit(i++, cx * 4 + (bit & 3), cy * 4 + ((bit >> 2) & 3), cz * 4 + (bit >> 4));
      }
    });
  }
  yield* forEachPoint((i, x, y, z) => {
    const a = at3(x - 1, y, z), b = at3(x, y - 1, z), cc = at3(x - 1, y - 1, z), e = at3(x, y, z - 1);
    for (let o = 0; o < 4; o++) {
      const k = order[o];
      const m = rgbm && k < 3 ? values[4 * i + 3] : 0;
      let pred = 0;
      if (a >= 0 && b >= 0 && cc >= 0) {
        pred = medianEdge(rescaled(a, k, m), rescaled(b, k, m), rescaled(cc, k, m));
      } else {
        const j = a >= 0 ? a : b >= 0 ? b : e;
        if (j >= 0) pred = rescaled(j, k, m);
      }
      values[4 * i + k] = (planes[k * points + i] + pred) & 255;
    }
  });
  // Versions 6 to 8: each stored point's 24 L2 term bytes, from the planes
  // after the values. Version 6: a residual on the same byte of the point at
  // -x, else -y, else -z. Version 7: the median edge detector on the signed
  // bytes of -x, -y and -x-y where all three are stored (else version 6's),
  // and a green or blue residual stored less the red or green one. Version 8:
  // version 7 without the planes of terms 4-8's green and blue, whose
  // residuals are 0 (their channels share one ratio): those bytes copy red's.
  let terms = null;
  if (gi.version >= 6) {
    terms = new Uint8Array(24 * points);
    const signedTerms = new Int8Array(terms.buffer); // the same bytes, read as the signed numbers they are
    const tplanes = planes.subarray(4 * points);
    const v7 = gi.version >= 7;
    // Each of the 24 bytes' plane (-1: none, a zero residual).
    const planeOf = Int32Array.from({ length: 24 }, (_, k) =>
      gi.version < 8 || k < 9 ? k : (k - 9) % 3 ? -1 : 9 + (k - 9) / 3);
    yield* forEachPoint((i, x, y, z) => {
      const a = at3(x - 1, y, z), b = at3(x, y - 1, z), e = at3(x, y, z - 1);
      const c = v7 && a >= 0 && b >= 0 ? at3(x - 1, y - 1, z) : -1;
      const j = a >= 0 ? a : b >= 0 ? b : e;
      const ta = 24 * a, tb = 24 * b, tc = 24 * c, tj = 24 * j, ti = 24 * i;
      let d = 0;
      for (let k = 0; k < 24; k++) {
        let pred = 0;
        if (c >= 0) { // medianEdge, inline: this loop is a sixth of an L2 file's rebuild
          const A = signedTerms[ta + k], B = signedTerms[tb + k], C = signedTerms[tc + k];
          const lo = A < B ? A : B, hi = A < B ? B : A;
          pred = C >= hi ? lo : C <= lo ? hi : A + B - C;
        } else if (j >= 0) {
          pred = terms[tj + k];
        }
        const r = planeOf[k] < 0 ? 0 : tplanes[planeOf[k] * points + i];
        d = v7 && k % 3 ? (r + d) & 255 : r;
        terms[ti + k] = (d + pred) & 255;
      }
    });
  }
  // One pass of the rebuild (lib/format/packed.c's rebuild_pass): stored texels
  // copied, stitched ones interpolated from their coarser brick (coarse
  // bricks' samples kept as floats, coarsest first) and encoded.
  // decode(idx, out): a stored point's three numbers; copy(idx, texel): its
  // bytes into atlas texel `texel`, or null (a term pass: the stored texels'
  // bytes are copied before, and only the stitched ones are visited);
  // encode(rgb, texel): a stitched value.
  const cidx = new Int32Array(count).fill(-1);
  let coarse = 0;
  for (let b = 0; b < count; b++) if (lv[b]) cidx[b] = coarse++;
  const fs = new Float32Array(Math.max(coarse, 1) * TEXELS * 3);
  const rgb = new Float32Array(3), tmp = [0, 0, 0];
  const interpolateFrom = (j, cl, p, out) => {
    interpolate(fs.subarray(cidx[j] * TEXELS * 3, (cidx[j] + 1) * TEXELS * 3), keys[j], cl, p, tmp);
    out[0] = tmp[0], out[1] = tmp[1], out[2] = tmp[2];
  };
  // Each brick texel's stored point (-1: none), or STITCHED: looked up once, for the
  // one pass of an L1 volume and the nine of an L2 one. A stitched texel's coarser
  // brick is found again when it is met (stitched() sets point and coarseIndex).
  // The stitched texels, (brick, texel) in brick order, are listed too: all a term
  // pass visits past the coarse bricks.
  const STITCHED = -2;
  const texelIndex = new Int32Array(count * TEXELS), stitchedList = [];
  yield* strides(count, STRIDE, (b) => {
    const span = 1 << lv[b], key = keys[b], any = stitch[4 * b] | stitch[4 * b + 1] | stitch[4 * b + 2] | stitch[4 * b + 3];
    for (let t = 0, qz = 0; qz < N; qz++)
      for (let qy = 0; qy < N; qy++)
        for (let qx = 0; qx < N; qx++, t++) {
          if (any && stitched(b, t)) {
            texelIndex[b * TEXELS + t] = STITCHED;
            stitchedList.push(b, t);
          } else {
            texelIndex[b * TEXELS + t] = at3((key[0] * 4 + qx) * span, (key[1] * 4 + qy) * span, (key[2] * 4 + qz) * span);
          }
        }
  });
  const brickTexel = (b) => (origin[3 * b + 2] * dims[1] + origin[3 * b + 1]) * dims[0] + origin[3 * b];
  // The coarse bricks, coarsest first (brick order within a level): what every pass
  // samples first.
  const coarseOrder = [];
  for (let level = gi.maxLevel; level >= 1; level--)
    for (let b = 0; b < count; b++) if (lv[b] === level) coarseOrder.push(b);
  const s3 = new Float32Array(3);
  // A stitched texel's value into rgb (stitched() finds its point and coarser brick).
  const stitchedValue = (b, t) => {
    stitched(b, t);
    if (cidx[b] >= 0) {
      const o = (cidx[b] * TEXELS + t) * 3;
      rgb[0] = fs[o], rgb[1] = fs[o + 1], rgb[2] = fs[o + 2];
    } else {
      interpolateFrom(coarseIndex, coarseLevel, point, rgb);
    }
  };
  function* pass(decode, copy, encode) {
    yield* strides(coarseOrder.length, STRIDE, (n) => {
      const b = coarseOrder[n];
      for (let t = 0; t < TEXELS; t++) {
        const idx = texelIndex[b * TEXELS + t];
        if (idx === STITCHED && stitched(b, t)) interpolateFrom(coarseIndex, coarseLevel, point, s3);
        else decode(idx, s3);
        const o = (cidx[b] * TEXELS + t) * 3;
        fs[o] = s3[0], fs[o + 1] = s3[1], fs[o + 2] = s3[2];
      }
    });
    if (!copy) {
      yield* strides(stitchedList.length / 2, STRIDE, (half) => {
        const n = 2 * half;
        const b = stitchedList[n], t = stitchedList[n + 1];
        stitchedValue(b, t);
        encode(rgb, brickTexel(b) + blockTexel[t]);
      });
      return;
    }
    yield* strides(count, STRIDE, (b) => {
      const base = brickTexel(b);
      for (let t = 0; t < TEXELS; t++) {
        const idx = texelIndex[b * TEXELS + t];
        if (idx !== STITCHED) {
          if (idx >= 0) copy(idx, base + blockTexel[t]);
          continue;
        }
        stitchedValue(b, t);
        encode(rgb, base + blockTexel[t]);
      }
    });
  }

  const atlas = new Uint8Array(4 * dims[0] * dims[1] * dims[2]);
  // A stored texel's four bytes as one word (both arrays start at byte 0 of their own buffers).
  const atlasWords = new Uint32Array(atlas.buffer), valueWords = new Uint32Array(values.buffer);
  yield* pass((idx, out) => {
    if (idx < 0) out.fill(0);
    else if (rgbm) rgbmDecode(values, 4 * idx, gi.rgbmRange, out);
    else rgb9e5Decode(values, 4 * idx, out);
  }, (idx, texel) => {
    atlasWords[texel] = valueWords[idx];
  }, (c, texel) => {
    if (rgbm) rgbmEncode(c, gi.rgbmRange, atlas, 4 * texel);
    else rgb9e5Encode(c, atlas, 4 * texel);
  });
  if (!terms) return { indirection, atlas, storedPoints: points };
  // The L2 terms (docs/format.md, "Version 6"): term byte j = 3 term + channel
  // of a texel goes to texture j >> 2, component j & 3; each term's three
  // signed bytes interpolate as numbers (-128 as -127), rounded half to even.
  const texels = dims[0] * dims[1] * dims[2];
  const sh = Array.from({ length: 6 }, () => new Int8Array(4 * texels));
  const signed = (v) => (v > 127 ? Math.max(v - 256, -127) : v);
  // A stored texel's 24 bytes in one go; the passes per term then only stitch.
  // Texture j's texel holds bytes 4j..4j+3 of the point's 24: word j of its six.
  const [sh0, sh1, sh2, sh3, sh4, sh5] = sh.map((q) => new Uint32Array(q.buffer));
  const termWords = new Uint32Array(terms.buffer);
  yield* strides(count, STRIDE, (b) => {
    const base = brickTexel(b);
    for (let t = 0; t < TEXELS; t++) {
      const idx = texelIndex[b * TEXELS + t];
      if (idx < 0) continue;
      const o = base + blockTexel[t], i = 6 * idx;
      sh0[o] = termWords[i], sh1[o] = termWords[i + 1], sh2[o] = termWords[i + 2];
      sh3[o] = termWords[i + 3], sh4[o] = termWords[i + 4], sh5[o] = termWords[i + 5];
    }
  });
  for (let term = 0; term < 8; term++)
    yield* pass((idx, out) => {
      for (let k = 0; k < 3; k++) out[k] = idx < 0 ? 0 : signed(terms[24 * idx + 3 * term + k]);
    }, null, (c, texel) => {
      for (let k = 0; k < 3; k++) {
        const j = 3 * term + k;
        sh[j >> 2][4 * texel + (j & 3)] = rint(Math.min(Math.max(c[k], -127), 127));
      }
    });
  if (gi.version < 8) return { indirection, atlas, storedPoints: points, sh };
  // Version 8's four textures: bytes 0-7 as they are, 8-11 the first band's last byte
  // and terms 4-6's shared one, 12-13 (two bytes a texel) those of terms 7 and 8.
  const rg = new Int8Array(2 * texels);
  for (let t = 0; t < texels; t++) {
    sh[2][4 * t + 2] = sh[3][4 * t];
    sh[2][4 * t + 3] = sh[3][4 * t + 3];
    rg[2 * t] = sh[4][4 * t + 2];
    rg[2 * t + 1] = sh[5][4 * t + 1];
  }
  return { indirection, atlas, storedPoints: points, sh: [sh[0], sh[1], sh[2], rg] };
}
