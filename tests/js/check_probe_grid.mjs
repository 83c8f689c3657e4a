// check_probe_grid.mjs FILE.gi.gz...: makeProbeGrid (web/gi-probe-grid.js) in node,
// against tests/js/gi_loader.mjs's float32 reading of docs/format.md. At 3,000
// probes of each file's grid, for a random unit normal, the irradiance three's
// shader computes from the grid's nine half-float coefficients (its constants,
// lightprobes_pars_fragment) must be what our lookup reads there, within 0.4 %
// of L0 (half floats keep 11 bits); a grid's padding slices copy its first and
// last data slices; the grid covers every probe the volume holds; a grid past
// three's texture side is refused.
import { readFileSync } from 'node:fs';
import * as THREE from '../../web/node_modules/three/build/three.module.js';
import { LightProbeGridWebGL } from '../../web/node_modules/three/examples/jsm/lighting/LightProbeGridWebGL.js';
import { decodeGi } from '../../web/gi-format.js';
import { makeProbeGrid, occupiedBox } from '../../web/gi-probe-grid.js';
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
      worst = Math.max(worst, Math.abs(threeIrradiance(c, n, ch) / Math.PI - ours[ch]) / l0[ch]);
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
