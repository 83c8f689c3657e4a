// check_probe_grid.mjs FILE.gi.gz...: makeProbeGrid (web/gi-probe-grid.js) in node,
// against tests/js/gi_loader.mjs's float32 reading of docs/format.md. At 3,000
// probes of each file's grid, for a random unit normal, the irradiance three's
// shader computes from the grid's nine half-float coefficients (its constants,
// lightprobes_pars_fragment) must be what our lookup reads there, within 0.4 %
// of L0 (half floats keep 11 bits); a grid's padding slices copy its first and
// last data slices; the grid covers every probe the volume holds; a volume too
// bright for half floats keeps float32; filled again, a grid keeps its texture; a
// grid past three's texture side is refused.
import { readFileSync } from 'node:fs';
import * as THREE from '../../web/node_modules/three/build/three.module.js';
import { LightProbeGridWebGL } from '../../web/node_modules/three/examples/jsm/lighting/LightProbeGridWebGL.js';
import { decodeGi } from '../../web/gi-format.js';
import { fillProbeGrid, makeProbeGrid, occupiedBox } from '../../web/gi-probe-grid.js';
import { GiVolume } from '../../web/vdbgi.js';
import { sampleGi } from './gi_loader.mjs';

let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed++;
};
// three's L2 irradiance for unit normal (x, y, z) from coefficients c[j][ch].
const threeIrradiance = (c, [x, y, z], ch) => Math.max(0, c[0][ch] * 0.886227 +
  2 * 0.511664 * (c[1][ch] * y + c[2][ch] * z + c[3][ch] * x) +
  2 * 0.429043 * (c[4][ch] * x * y + c[5][ch] * y * z + c[7][ch] * x * z) +
  c[6][ch] * (0.743125 * z * z - 0.247708) + c[8][ch] * 0.429043 * (x * x - y * y));

let seed = 7;
const rnd = () => (seed = (seed * 1103515245 + 12345) % 2147483648) / 2147483648;
for (const file of process.argv.slice(2)) {
  const name = file.split('/').pop();
  const bytes = new Uint8Array(readFileSync(file));
  const gi = await decodeGi(bytes.slice());
  const volume = new GiVolume(await decodeGi(bytes.slice()));
  const grid = makeProbeGrid(volume, LightProbeGridWebGL);
  const { x: nx, y: ny, z: nz } = grid.resolution;
  const data = grid.texture.image.data, slices = nz + 2;
  const texel = (t, slice, ix, iy) => {
    const o = 4 * ((slice * ny + iy) * nx + ix);
    return [0, 1, 2, 3].map((k) => THREE.DataUtils.fromHalfFloat(data[o + k]));
  };
  let worst = 0, lit = 0, padding = true;
  const at = new THREE.Vector3();
  for (let s = 0; s < 3000; s++) {
    const ix = Math.floor(rnd() * nx), iy = Math.floor(rnd() * ny), iz = Math.floor(rnd() * nz);
    let n = [rnd() - 0.5, rnd() - 0.5, rnd() - 0.5];
    n = n.map((v) => v / Math.hypot(...n));
    const pos = grid.getProbePosition(ix, iy, iz, at).toArray();
    const l0 = sampleGi(gi, pos), ours = sampleGi(gi, pos, null, n);
    const floats = [];
    for (let t = 0; t < 7; t++) floats.push(...texel(t, t * slices + 1 + iz, ix, iy));
    const c = Array.from({ length: 9 }, (_, j) => floats.slice(3 * j, 3 * j + 3));
    for (let ch = 0; ch < 3; ch++) {
      if (!(l0[ch] > 0)) continue;
      lit++;
      // Relative to L0, but for a floor of 1e-4: a half float keeps 11 bits down to 6e-5,
      // and a probe lit at 1e-12 rounds to 0 (no light a frame can show).
      worst = Math.max(worst, Math.abs(threeIrradiance(c, n, ch) / Math.PI - ours[ch]) / Math.max(l0[ch], 1e-4));
    }
    const t = Math.floor(rnd() * 7);
    if (iz === 0 && texel(t, t * slices, ix, iy).join() !== texel(t, t * slices + 1, ix, iy).join()) padding = false;
    if (iz === nz - 1 && texel(t, t * slices + nz + 1, ix, iy).join() !== texel(t, t * slices + nz, ix, iy).join()) padding = false;
  }
  const label = `${name} (${gi.sh ? 'L2' : 'scalar'}, ${gi.encoding ? 'RGB9E5' : 'RGBM'}, ${gi.layout === 2 ? 'compact' : 'seed'} layout)`;
  check(lit > 1000 && worst < 0.004,
    `${label}: three's irradiance from the grid is ours at ${lit} lit probe channels (largest difference ${worst < 0.004 ? 'under 0.4' : (100 * worst).toFixed(2)} % of L0)`);
  check(padding, `${label}: each sub-volume's padding slices copy its first and last data slices`);
  const occ = occupiedBox(volume), g = grid.boundingBox;
  check([0, 1, 2].every((k) => g.min.getComponent(k) <= occ.min[k] + 1e-9 && g.max.getComponent(k) >= occ.max[k] - 1e-9),
    `${label}: the grid's box holds every cell with a brick`);
}
// Past a half float's 65504: every RGB9E5 texel of a file given its largest exponent
// (L0 up to 65408), in both readings; the grid must keep float32 and still be ours.
for (const file of process.argv.slice(2)) {
  const bytes = new Uint8Array(readFileSync(file));
  const gi = await decodeGi(bytes.slice());
  if (gi.encoding !== 1) continue;
  for (let i = 3; i < gi.atlas.length; i += 4) gi.atlas[i] |= 0xf8;
  const volume = new GiVolume(await decodeGi(bytes.slice()));
  const words = volume.atlas.image.data;
  for (let i = 0; i < words.length; i++) words[i] = (words[i] | 0xf8000000) >>> 0;
  const grid = makeProbeGrid(volume, LightProbeGridWebGL);
  const texture = grid.texture;
  const { x: nx, y: ny, z: nz } = grid.resolution;
  let worst = 0, n = 0;
  const at = new THREE.Vector3();
  for (let s = 0; s < 500; s++) {
    const ix = Math.floor(rnd() * nx), iy = Math.floor(rnd() * ny), iz = Math.floor(rnd() * nz);
    const pos = grid.getProbePosition(ix, iy, iz, at).toArray();
    const l0 = sampleGi(gi, pos);
    const o = 4 * ((1 + iz) * ny * nx + iy * nx + ix);
    for (let ch = 0; ch < 3; ch++) {
      if (!(l0[ch] > 0)) continue;
      n++;
      worst = Math.max(worst, Math.abs(texture.image.data[o + ch] * 0.886227 / Math.PI - l0[ch]) / l0[ch]);
    }
  }
  check(texture.type === THREE.FloatType && n > 100 && worst < 1e-5,
    `${file.split('/').pop()} made ${n > 100 ? 'bright' : 'dark'} (L0 up to 65408): the grid keeps float32 ` +
    `(${texture.type === THREE.FloatType ? 'FloatType' : 'not FloatType'}), its L0 ours within ${worst < 1e-5 ? '1e-5' : worst.toExponential(1)}`);
  // Filled again, the grid keeps its texture (WebGPU's node holds it) with the new light.
  const version = texture.version;
  for (let i = 0; i < words.length; i++) words[i] = (words[i] & 0x07ffffff) >>> 0;
  fillProbeGrid(grid, volume);
  check(grid.texture !== texture && grid.texture.type === THREE.HalfFloatType && texture.version === version,
    'filled again with light half floats hold, the grid takes a new half-float texture');
  const again = grid.texture, v2 = again.version;
  fillProbeGrid(grid, volume);
  check(grid.texture === again && again.version > v2, 'filled again alike, the grid keeps its texture and uploads it anew');
}
{
  const volume = new GiVolume(await decodeGi(new Uint8Array(readFileSync(process.argv[2]))));
  const s = volume.info.spacing;
  let message = '';
  try {
    makeProbeGrid(volume, LightProbeGridWebGL, { box: { min: [0, 0, 0], max: [4, 4, 400 * s] } });
  } catch (e) {
    message = e.message;
  }
  check(/past 2048 a side/.test(message), `a grid 400 probes deep (a 2,814-slice atlas) is refused: ${message.split(':')[0]}`);
  let wrong = '';
  try { makeProbeGrid(volume, THREE.Mesh); } catch (e) { wrong = e.message; }
  check(/LightProbeGridWebGL/.test(wrong), 'a class that is not a probe grid is refused, naming the two that are');
}
process.exit(failed ? 1 : 0);
