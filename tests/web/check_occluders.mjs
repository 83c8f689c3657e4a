// check_occluders.mjs FLOOR.gi.gz: occluders in headless Chromium, WebGL2 and
// WebGPU, on a floor lit only by indirect light: a flat lightmap (apply()'s
// volume: false) and FLOOR.gi.gz read per fragment. At 400 floor pixels the
// frame with occluders over the frame without must be what they leave of the
// cosine-weighted hemisphere: a sphere of radius r whose centre lies d away
// at angle theta from the normal, wholly above the horizon, covers
// cos(theta) (r / d)^2; a ball resting on the floor, cut by the horizon, is
// counted by tracing 40,000 stratified cosine-weighted rays at the pixel
// (and covers nothing for a pixel under it, inside it); a capsule counts as
// the sphere at its segment's point nearest the pixel; shares multiply. A
// seventeenth shape is refused.
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { withPage } from './browser.mjs';

const dir = mkdtempSync(join(tmpdir(), 'vdbgi-occ-'));
copyFileSync(process.argv[2], join(dir, 'floor.gi.gz'));
// A ball, and a body lying along x (two capsules end to end), well apart.
const occluders = [
  { sphere: { center: [-2, 1, -1.5], radius: 0.5 } },
  { sphere: { center: [2, 0.3, -2], radius: 0.5 } },
  { capsules: [{ a: [0.5, 0.7, 1.5], b: [1.5, 0.7, 1.5], radius: 0.3 }, { a: [1.5, 0.7, 1.5], b: [2.5, 0.7, 1.5], radius: 0.3 }] },
];
const share = (p, c, r) => {
  const d = [c[0] - p[0], c[1] - p[1], c[2] - p[2]];
  const l2 = d[0] ** 2 + d[1] ** 2 + d[2] ** 2;
  return (d[1] / Math.sqrt(l2)) * (r * r) / l2; // the normal is +y
};
const nearest = (p, a, b) => {
  const ab = a.map((v, k) => b[k] - v);
  const t = Math.min(1, Math.max(0, ab.reduce((s, v, k) => s + v * (p[k] - a[k]), 0) / ab.reduce((s, v) => s + v * v, 0)));
  return a.map((v, k) => v + t * ab[k]);
};
// The share of p's cosine-weighted hemisphere (normal +y) rays find the sphere (c, r) in.
const traced = (p, c, r) => {
  const o = p.map((v, k) => v - c[k]);
  const oo = o[0] ** 2 + o[1] ** 2 + o[2] ** 2 - r * r;
  if (oo <= 0.002 * r * r) return 0; // inside: not its occluder
  const N = 200;
  let hits = 0;
  for (let i = 0; i < N; i++)
    for (let j = 0; j < N; j++) {
      const u1 = (i + 0.5) / N, phi = 2 * Math.PI * (j + 0.5) / N, s = Math.sqrt(u1);
      const d = [s * Math.cos(phi), Math.sqrt(1 - u1), s * Math.sin(phi)];
      const b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
      hits += b < 0 && b * b > oo;
    }
  return hits / (N * N);
};
const expected = (p) => {
  let v = (1 - share(p, occluders[0].sphere.center, occluders[0].sphere.radius)) *
    (1 - traced(p, occluders[1].sphere.center, occluders[1].sphere.radius));
  for (const c of occluders[2].capsules) v *= 1 - share(p, nearest(p, c.a, c.b), c.radius);
  return v;
};
// 400 floor pixels spread over the frame, away from the rim of the resting ball's
// footprint (where inside and outside are a rounding apart).
const rim = (p) => Math.abs(Math.hypot(p[0] - 2, p[2] + 2) - Math.sqrt(0.5 ** 2 - 0.3 ** 2)) < 0.02;

let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed++;
};
try {
  await withPage({ '/files': dir }, async ({ run, fresh }) => {
    for (const backend of ['webgl', 'webgpu'])
      for (const lit of ['lightmap', 'volume']) {
        // SwiftShader's WebGPU loses its device in a tab that had a WebGL2 context.
        const go = backend === 'webgpu' ? (await fresh()).run : run;
        const r = await go({ kind: 'occlude', backend, occluders, gi: lit === 'volume' ? '/files/floor.gi.gz' : null });
        let worst = 0, n = 0, darkest = 1;
        for (let k = 0; k < 400; k++) {
          const i = Math.floor((k + 0.5) * r.before.length / 400) + (k % 7);
          const p = r.pos.slice(4 * i, 4 * i + 3);
          if (r.pos[4 * i + 3] !== 1 || !(r.before[i] > 1e-4) || rim(p)) continue;
          const ratio = r.after[i] / r.before[i];
          worst = Math.max(worst, Math.abs(ratio - expected(p)));
          darkest = Math.min(darkest, ratio);
          n++;
        }
        check(n > 380 && worst < 2e-3 && darkest < 0.8,
          `${backend === 'webgl' ? 'WebGL2' : 'WebGPU'}, ${lit}: at ${n} floor pixels the light the ` +
          'spheres and capsules let through is what they leave of the hemisphere, within 0.002 ' +
          `(worst ${worst.toFixed(5)}; the darkest keeps ${darkest.toFixed(3)})`);
        if (backend === 'webgl' && lit === 'lightmap')
          check(/at most 16 \(MAX_OCCLUDERS\)/.test(r.refused ?? ''), `a seventeenth shape is refused: ${r.refused}`);
      }
  });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
