// gi-probe-grid.js: a loaded volume through three.js's own light probe grid
// (r187's LightProbeGridWebGL for WebGL2, LightProbeGrid for WebGPU), which
// every built-in material reads with no shader of ours. That grid is a dense
// box of L2 spherical-harmonic radiance coefficients in one RGBA 3D atlas:
// seven sub-volumes along z, each nz + 2 slices (a copy of its first and last
// data slice on either side), coefficient floats 4t..4t+3 of
// (c0.rgb, c1.rgb, .. c8.rgb, 0) in sub-volume t. makeProbeGrid fills it on the
// CPU from the volume's own textures, read as the C sampler reads them (the
// shaders agree but for a term byte of -128, which the converter never writes),
// instead of the grid's in-page bake; docs/web.md says when to pick which.
import * as THREE from 'three';
import { ENCODING_RGB9E5, LAYOUT_COMPACT, layoutGeometry, SH2_RANGE, termSlot } from './gi-format.js';

// WebGL2's guaranteed 3D texture side is 256; 2048 is what desktops and
// SwiftShader give, and the atlas's depth is 7 (nz + 2) slices.
export const MAX_GRID_SIDE = 2048;

// The largest finite half float.
const HALF_MAX = 65504;

// three's L2 irradiance (lightprobes_pars_fragment, getShIrradianceAt), for unit
// normal (x, y, z), is E = c0 A0 + A1 (c1 y + c2 z + c3 x) + A2 (c4 xy + c5 yz +
// c7 xz) + c6 (A6 z^2 - A6 / 3) + A8 c8 (x^2 - y^2), with its own constants:
const A0 = 0.886227, A1 = 2 * 0.511664, A2 = 2 * 0.429043, A6 = 0.743125, A8 = 0.429043;
// Ours (docs/format.md, "Version 6") is E / pi = c0 (1 + sum r_k R_k p_k) with
// p = (x, y, z, xy, yz, 3z^2 - 1, xz, x^2 - y^2). Three's coefficient j, for
// j = 0..8, is pi / SCALE[j] times our term TERM[j] (-1: c0), matching each
// monomial; 3z^2 - 1 against A6 z^2 - A6 / 3 gives c6 the factor 3.
const TERM = [-1, 1, 2, 0, 3, 4, 5, 6, 7];
const SCALE = [A0, A1, A1, A1, A2, A2, A6 / 3, A2, A8];

// The runtime's lookup (vdbgi.js, vdbgiLookup) at `pos` without a normal, in
// float64: out[0..2] the filtered L0, out[3 + 3k + c] the filtered ratio of term k
// times its range. `v` is what lookup() needs of a GiVolume (see volumeArrays).
function lookup(v, pos, out) {
  const { boxMin, boxSize, indDims, geo, compact } = v;
  const p = [0, 0, 0], base = [0, 0, 0], cell = [0, 0, 0];
  for (let k = 0; k < 3; k++) {
    p[k] = (pos[k] - boxMin[k]) / boxSize[k] * (indDims[k] * 4) - 0.5;
    // A grid probe on the volume's lattice lands on a whole texel, which may be a
    // brick's first: float64's last bit must not move it into the brick before.
    const r = Math.round(p[k]);
    if (Math.abs(p[k] - r) < 1e-9 * Math.max(1, Math.abs(r))) p[k] = r;
    base[k] = Math.floor(p[k] / 4);
    cell[k] = Math.min(Math.max(base[k], 0), indDims[k] - 1);
  }
  const cols = v.columns;
  const byte = (i, c) => cols[4 * i + c];
  const column = cell[0] + indDims[0] * cell[2];
  const run = 2 * column, at = 2 * column + 1;
  const ymin = byte(run, 0) + 256 * byte(run, 1), count = byte(run, 2) + 256 * byte(run, 3);
  const lift = compact && count > 0;
  if (lift) base[1] = Math.max(base[1], ymin);
  const kk = lift ? Math.max(cell[1] - ymin, 0) : cell[1] - ymin;
  const entry = Math.min(2 * indDims[0] * indDims[2] + byte(at, 0) + 256 * byte(at, 1) + 65536 * byte(at, 2) + Math.max(kk, 0),
                         cols.length / 4 - 1);
  const inRun = kk >= 0 && kk < count;
  const ind = [0, 1, 2, 3].map((c) => (inRun ? byte(entry, c) : 0));
  const level = compact ? ind[3] % 4 : Math.max(ind[3] - 1, 0);
  const span = 2 ** level;
  const i0 = [0, 0, 0], fr = [0, 0, 0];
  for (let k = 0; k < 3; k++) {
    const origin = Math.floor(base[k] / span) * span * 4;
    let q = (p[k] - origin + geo.centre) / span - geo.centre;
    if (compact && k === 1) q = Math.max(q, 0);
    const first = compact ? ind[k] * 4 + (Math.floor(ind[3] / 4 ** (k + 1)) % 4) : ind[k] * geo.brick + geo.pad;
    // The texel coordinate the shader's uvw reads (uvw * dims - 0.5), filtered.
    const t = first + q;
    i0[k] = Math.floor(t);
    fr[k] = t - i0[k];
  }
  // The eight texels the LINEAR filter blends (clamped to the edge), and their weights.
  const dims = v.atlasDims;
  const acc = [0, 0, 0, 0], rgba = [0, 0, 0, 0];
  out.fill(0);
  for (let c = 0; c < 8; c++) {
    let w = 1, idx = 0;
    for (let k = 2; k >= 0; k--) {
      const hi = (c >> k) & 1;
      w *= hi ? fr[k] : 1 - fr[k];
      idx = idx * dims[k] + Math.min(Math.max(i0[k] + hi, 0), dims[k] - 1);
    }
    if (w === 0) continue;
    v.texel(idx, rgba);
    for (let ch = 0; ch < 4; ch++) acc[ch] += w * rgba[ch];
    // Each term byte as the C sampler reads it, max(q / 127, -1), before the filter.
    if (v.sh) {
      for (let j = 0; j < 24; j++) {
        const [tex, comp, size] = v.slots[j];
        out[3 + j] += w * Math.max((v.sh[tex][size * idx + comp] - 128) / 127, -1);
      }
    }
  }
  // RGBM decodes after the filter, as the shader does; RGB9E5 was decoded a texel at a time.
  for (let ch = 0; ch < 3; ch++) out[ch] = v.rgbm ? acc[ch] * acc[3] * v.rgbmRange : acc[ch];
  if (v.sh) for (let j = 0; j < 24; j++) out[3 + j] *= SH2_RANGE[Math.floor(j / 3)];
}

// What lookup() reads of a GiVolume: its textures' own bytes (three keeps a
// DataTexture's array after the upload) and its header's figures.
function volumeArrays(volume) {
  const { info } = volume;
  const rgbm = info.encoding !== ENCODING_RGB9E5;
  const atlas = volume.atlas.image.data;
  const texel = rgbm
    ? (i, out) => { for (let c = 0; c < 4; c++) out[c] = atlas[4 * i + c] / 255; }
    : (i, out) => {
      // Shared exponent: three 9-bit mantissas, bits 27-31 the exponent biased by 15 + 9.
      const w = atlas[i], scale = 2 ** ((w >>> 27) - 24);
      out[0] = (w & 511) * scale; out[1] = ((w >>> 9) & 511) * scale; out[2] = ((w >>> 18) & 511) * scale; out[3] = 1;
    };
  return {
    boxMin: info.boxMin, boxSize: info.boxMax.map((hi, k) => hi - info.boxMin[k]), indDims: info.indDims,
    atlasDims: info.atlasDims, geo: layoutGeometry(info.layout), compact: info.layout === LAYOUT_COMPACT,
    columns: volume.columns.image.data, rgbm, rgbmRange: info.rgbmRange, texel,
    sh: volume.sh ? volume.sh.map((t) => t.image.data) : null,
    slots: Array.from({ length: 24 }, (_, j) => termSlot(info.shBytes, j)),
  };
}

// Fill `grid` (a LightProbeGridWebGL or LightProbeGrid, placed and sized: its
// position, width, height, depth and resolution) from `volume`: each probe takes
// the volume's light at the probe, turned into three's nine coefficients, in a
// half-float atlas (8 bytes a texel, 56 a probe: three's WebGL bake keeps 112).
// The grid's own texture is replaced (filling it again reuses ours); its
// dispose() frees ours too.
export function fillProbeGrid(grid, volume) {
  const { x: nx, y: ny, z: nz } = grid.resolution;
  const slices = nz + 2, depth = 7 * slices;
  if (Math.max(nx, ny, depth) > MAX_GRID_SIDE)
    throw new Error(`a probe grid of ${nx} x ${ny} x ${nz} needs a ${nx} x ${ny} x ${depth} texture, past ${MAX_GRID_SIDE} a side: ` +
                    'give makeProbeGrid a smaller box or a larger spacing');
  const v = volumeArrays(volume);
  const floats = new Float32Array(4 * nx * ny * depth);
  const out = new Float64Array(27), coef = new Float64Array(28);
  const at = new THREE.Vector3();
  let largest = 0;
  for (let iz = 0; iz < nz; iz++)
    for (let iy = 0; iy < ny; iy++)
      for (let ix = 0; ix < nx; ix++) {
        lookup(v, grid.getProbePosition(ix, iy, iz, at).toArray(), out);
        for (let j = 0; j < 9; j++)
          for (let c = 0; c < 3; c++) {
            const ours = TERM[j] < 0 ? out[c] : out[c] * out[3 + 3 * TERM[j] + c];
            coef[3 * j + c] = Math.PI * ours / SCALE[j];
            largest = Math.max(largest, Math.abs(coef[3 * j + c]));
          }
        // Sub-volume t's texel at data slice iz, and at its padding slice at either end.
        for (let t = 0; t < 7; t++) {
          const put = (slice) => {
            const o = 4 * ((slice * ny + iy) * nx + ix);
            for (let c = 0; c < 4; c++) floats[o + c] = coef[4 * t + c];
          };
          put(t * slices + 1 + iz);
          if (iz === 0) put(t * slices);
          if (iz === nz - 1) put(t * slices + nz + 1);
        }
      }
  // Half floats unless a coefficient passes their largest, 65504 (an L0 above about
  // 10,000: RGBM's range allows it); then float32, as three's own WebGL bake keeps.
  const wide = largest > HALF_MAX;
  const data = wide ? floats : new Uint16Array(floats.length);
  if (!wide) for (let i = 0; i < floats.length; i++) data[i] = THREE.DataUtils.toHalfFloat(floats[i]);
  const type = wide ? THREE.FloatType : THREE.HalfFloatType;
  // A grid filled before keeps its texture, so that WebGPU's node, which took it when
  // the grid was first drawn, sees the new light (a new size or type, float32 against
  // half, needs a new texture: in WebGPU, a new grid).
  const old = grid.texture;
  let texture;
  if (old?.vdbgiFilled && old.type === type && old.image.width === nx && old.image.height === ny &&
      old.image.depth === depth) {
    texture = old;
    texture.image.data = data;
  } else {
    if (old?.vdbgiFilled) old.dispose();
    texture = new THREE.Data3DTexture(data, nx, ny, depth);
    texture.format = THREE.RGBAFormat;
    texture.type = type;
    texture.minFilter = texture.magFilter = THREE.LinearFilter;
    texture.wrapS = texture.wrapT = texture.wrapR = THREE.ClampToEdgeWrapping;
    texture.generateMipmaps = false;
    texture.colorSpace = THREE.NoColorSpace;
    texture.vdbgiFilled = true;
  }
  texture.needsUpdate = true;
  grid.texture = texture;
  grid.updateBoundingBox();
  if (!grid.vdbgiDispose) {
    const dispose = grid.dispose.bind(grid);
    grid.vdbgiDispose = () => {
      if (grid.texture?.vdbgiFilled) grid.texture.dispose();
      grid.texture = null;
      dispose();
    };
    grid.dispose = grid.vdbgiDispose;
  }
  return grid;
}

// The box of the volume's cells that hold bricks (each column's run of cells,
// docs/format.md, "The runtime's indirection"): where its light is. null if none.
export function occupiedBox(volume) {
  const { indDims, boxMin, spacing } = volume.info;
  const cols = volume.columns.image.data;
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let z = 0; z < indDims[2]; z++)
    for (let x = 0; x < indDims[0]; x++) {
      const o = 8 * (x + indDims[0] * z);
      const ymin = cols[o] + 256 * cols[o + 1], count = cols[o + 2] + 256 * cols[o + 3];
      if (!count) continue;
      [x, ymin, z].forEach((c, k) => { lo[k] = Math.min(lo[k], c); });
      [x + 1, ymin + count, z + 1].forEach((c, k) => { hi[k] = Math.max(hi[k], c); });
    }
  if (lo[0] === Infinity) return null;
  const cell = 4 * spacing;
  return { min: lo.map((c, k) => boxMin[k] + c * cell), max: hi.map((c, k) => boxMin[k] + c * cell) };
}

// A `Grid` (pass LightProbeGridWebGL or LightProbeGrid from three/addons/lighting/)
// over `box` (a THREE.Box3 or { min, max } of arrays; by default occupiedBox(),
// the cells of the volume that hold its bricks) at `spacing` (the volume's by default), filled by fillProbeGrid. The
// box grows to the volume's lattice, so that at the volume's spacing every probe
// stands on one of the volume's own. Add the grid to the scene, as three's docs do.
export function makeProbeGrid(volume, Grid, { box = null, spacing = volume.info.spacing } = {}) {
  if (typeof Grid?.prototype?.getProbePosition !== 'function')
    throw new Error('makeProbeGrid: pass three\'s LightProbeGridWebGL (WebGL2) or LightProbeGrid (WebGPU) class, from three/addons/lighting/ (three r187 or later)');
  if (!(spacing > 0)) throw new Error(`makeProbeGrid: spacing ${spacing} is not a positive number of metres`);
  const { boxMin } = volume.info;
  box ??= occupiedBox(volume);
  if (!box) throw new Error('makeProbeGrid: the volume holds no bricks, so no light to fill a grid with');
  const lo = box.min.toArray?.() ?? box.min, hi = box.max.toArray?.() ?? box.max;
  const min = [], size = [], res = [];
  for (let k = 0; k < 3; k++) {
    if (!(hi[k] > lo[k])) throw new Error(`makeProbeGrid: the box is empty along ${'xyz'[k]} (${lo[k]} to ${hi[k]})`);
    // Snap outward to the lattice of probe cells at boxMin + i spacing (1e-6 of a cell of slack).
    const a = Math.floor((lo[k] - boxMin[k]) / spacing + 1e-6), b = Math.ceil((hi[k] - boxMin[k]) / spacing - 1e-6);
    res[k] = Math.max(1, b - a);
    min[k] = boxMin[k] + a * spacing;
    size[k] = res[k] * spacing;
  }
  const grid = new Grid(size[0], size[1], size[2], res[0], res[1], res[2]);
  grid.position.set(min[0] + size[0] / 2, min[1] + size[1] / 2, min[2] + size[2] / 2);
  return fillProbeGrid(grid, volume);
}
