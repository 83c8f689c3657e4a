// check_probe.mjs BACKEND SCENE.glb FILE.gi.gz GI-INSPECT: render SCENE in
// the probe-colour view (per fragment) in headless Chromium with web/
// (BACKEND webgl or webgpu), read back each pixel's colour and world position
// from float targets, and compare a few hundred covered pixels with the C
// sampler (gi-inspect --at) at the same positions. docs/web.md derives the
// tolerance; exit 1 if any channel exceeds it. The brick-level view must show
// the level the indirection gives at each of those pixels. With THREE_PACKAGE
// set, the page runs on that copy of three (web/node_modules/THREE_PACKAGE).
import { spawnSync } from 'node:child_process';
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { withPage } from './browser.mjs';
import { readFileSync } from 'node:fs';
import { loadGi, sampleGi } from '../js/gi_loader.mjs';

const [backend, scene, file, inspect] = process.argv.slice(2);
const KNOBS = { intensity: 1.7, self: 0.3, bleed: 0.4 };
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-web-'));
copyFileSync(scene, join(dir, 'scene.glb'));
copyFileSync(file, join(dir, 'volume.gi.gz'));

let result;
try {
  // THREE_PACKAGE=three-0.165: another copy of three under web/node_modules (the range we claim).
  const three = process.env.THREE_PACKAGE;
  result = await withPage({ '/files': dir }, ({ run }) =>
    run({ kind: 'probe', backend, scene: '/files/scene.glb', gi: '/files/volume.gi.gz', width: 256, height: 256,
      points: 400, knobs: KNOBS }), { page: three ? `/tests/web/render.html?three=${three}` : undefined });
} finally {
  rmSync(dir, { recursive: true, force: true });
}

const gi = await loadGi(readFileSync(file));
// With L2 terms each pixel reads half a spacing off its surface with its own
// normal (docs/format.md, "Version 6"): gi-inspect takes one normal a run, so
// the float32 loader, held to gi-inspect by cli/convert_js_loader, gives the
// value there. Without, gi-inspect at the pixel's position.
const f = Math.fround;
const offset = f(f(0.5 * f(gi.boxMax[0] - gi.boxMin[0])) / (gi.indDims[0] * 4));
const reading = (p) => {
  const len = Math.hypot(...p.normal);
  const n = p.normal.map((v) => f(v / len));
  return { pos: p.pos.map((v, k) => f(v + f(n[k] * offset))), n };
};
let want;
if (gi.sh) {
  want = result.points.map((p) => { const r = reading(p); return sampleGi(gi, r.pos, null, r.n); });
} else {
  const at = result.points.flatMap((p) => ['--at', p.pos.map((v) => v.toPrecision(9)).join(',')]);
  const c = spawnSync(resolve(inspect), [file, ...at], { encoding: 'utf8' });
  if (c.status !== 0) {
    console.log(`gi-inspect failed: ${c.stderr}`);
    process.exit(1);
  }
  want = c.stdout.split('\n').map((l) => l.match(/^at\s+\S+ -> (\S+) (\S+) (\S+)$/)).filter(Boolean)
    .map((m) => m.slice(1, 4).map(Number));
}
if (want.length !== result.points.length) {
  console.log(`gi-inspect gave ${want.length} values for ${result.points.length} points`);
  process.exit(1);
}

// Tolerance (docs/web.md): a GPU's filter weights are fixed point, at least 8
// fractional bits (D3D11, Vulkan's usual subTexelPrecisionBits), so each
// axis's weight may be off by 2^-9 and a filtered channel by 3 x 2^-9 x its
// spread over the eight texels blended. RGBM multiplies filtered rgb by
// filtered m: R (drgb m + rgb dm). RGB9E5 is filtered as floats. Plus float32
// arithmetic and the 6 significant digits gi-inspect prints.
const W = 3 * 2 ** -9;
// With L2 terms the colour's error scales by the terms' sum, and each term's
// filter error (its texels' spread, in ratios) moves the sum by its range x |p(n)|.
const tolerance = (p, v) => {
  const d = {};
  const r = gi.sh ? reading(p) : { pos: p.pos, n: null };
  sampleGi(gi, r.pos, d, r.n);
  const [red, g, b, m] = d.filtered, s = d.spread;
  return [red, g, b].map((c, k) => {
    const l0 = gi.encoding === 1 ? W * s[k] : gi.rgbmRange * W * (s[k] * m + c * s[3]);
    const terms = gi.sh ? l0 * Math.abs(d.sum[k]) + d.l0[k] * W * d.termWeight[k] : l0;
    return terms + 1e-5 * Math.abs(v[k]) + 1e-7;
  });
};
let worst = 0, worstRel = 0, bad = 0, lit = 0, sumSq = 0, n = 0;
result.points.forEach((p, i) => {
  const tol = tolerance(p, want[i]);
  for (let k = 0; k < 3; k++) {
    const d = Math.abs(p.irr[k] - want[i][k]);
    const t = tol[k];
    worst = Math.max(worst, d);
    worstRel = Math.max(worstRel, d / t);
    sumSq += d * d;
    n++;
    if (!(d <= t)) bad++;
  }
  if (want[i].some((v) => v > 0)) lit++;
});
const rms = Math.sqrt(sumSq / n);

// The brick-level view shows each level's colour (docs/web.md) at every pixel.
const LEVEL_COLOURS = { '-1': [0.25, 0.25, 0.25], 0: [0.1, 0.35, 1], 1: [0.1, 0.85, 0.25], 2: [1, 0.85, 0.1], 3: [1, 0.2, 0.1] };
const levelsSeen = new Set();
let levelBad = 0;
for (const p of result.points) {
  const d = {};
  sampleGi(gi, gi.sh ? reading(p).pos : p.pos, d);
  levelsSeen.add(d.level);
  if (LEVEL_COLOURS[d.level].some((c, k) => Math.abs(c - p.level[k]) > 1e-6)) levelBad++;
}
const layout = (gi.layout === 2 ? 'compact' : 'seed') + (gi.sh ? ' L2' : ''), enc = gi.encoding === 1 ? 'rgb9e5' : 'rgbm';
console.error(`${backend} ${enc} ${layout}: ${result.points.length} points of ${result.covered} covered, ` +
  `${lit} lit; worst ${worst.toExponential(2)} (${(100 * worstRel).toFixed(1)} % of tolerance), rms ${rms.toExponential(2)}`);
// The knobs (docs/web.md): lit by GI alone, a pixel is bounce(E, a) with E
// the probe view's colour; the physical knobs give E x a, so a = that / E.
function bounce(e, a, { intensity, self, bleed }) {
  const mean = (c) => (c[0] + c[1] + c[2]) / 3;
  const ownHue = a.map((v) => v - mean(a)), hue = e.map((v) => v - mean(e));
  const len2 = ownHue.reduce((s, v) => s + v * v, 0);
  const along = len2 > 1e-8 ? Math.max(hue.reduce((s, v, k) => s + v * ownHue[k], 0), 0) / len2 : 0;
  return e.map((v, k) => Math.max(v - (1 - self) * along * ownHue[k], 0) * (a[k] + (1 - a[k]) * bleed) * intensity);
}
let knobBad = 0, knobChecked = 0, knobWorst = 0;
for (const p of result.points) {
  if (p.irr.some((v) => v < 1e-3)) continue;
  const a = p.physical.map((v, k) => v / p.irr[k]);
  const want = bounce(p.irr, a, KNOBS);
  knobChecked++;
  for (let k = 0; k < 3; k++) {
    const d = Math.abs(p.styled[k] - want[k]);
    knobWorst = Math.max(knobWorst, d / Math.max(want[k], 1e-3));
    if (d > 1e-4 * Math.max(want[k], 1e-2)) knobBad++;
  }
}
// At metalness 0.5 a standard material reflects half the bounce.
let metalBad = 0;
for (const p of result.points)
  for (let k = 0; k < 3; k++)
    if (Math.abs(p.halfMetal[k] - 0.5 * p.physical[k]) > 1e-4 * Math.max(p.physical[k], 1e-2)) metalBad++;
console.error(`  metalness 0.5: ${metalBad} channels not half the bounce`);
knobBad += metalBad;
bad += knobBad;
console.error(`  knobs ${JSON.stringify(KNOBS)}: ${knobChecked} pixels, worst relative ${knobWorst.toExponential(2)}, ${knobBad} off`);
console.error(`  levels seen: ${[...levelsSeen].sort().join(', ')}; ${levelBad} pixels show another level's colour`);
console.error(`  positions project back within ${result.offPixel.toExponential(2)} pixels of their pixels`);
if (!(result.offPixel < 0.1)) { // measured 0.037: the rasteriser's interpolation
  console.log(`${backend}: a pixel's world position projects ${result.offPixel} pixels away from it`);
  process.exit(1);
}
// The brick-boundary view: lines between bricks, 12 % of the lit pixels here (28 % when
// the lifted ground below the lowest bricks came out black); a
// position read from below its column's lowest brick (the lift) is no boundary.
const { lit: litPixels, blackened } = result.bricksView;
console.error(`  brick boundaries: ${blackened} of ${litPixels} lit pixels black`);
if (!(blackened <= 0.18 * litPixels)) {
  console.log(`${backend} ${enc} ${layout}: the brick-boundary view blacks out ${blackened} of ${litPixels} lit pixels`);
  process.exit(1);
}
// Read with their normals, fewer pixels clear 1e-3 in every channel (floors facing the black sky).
if (bad || levelBad || knobChecked < (gi.sh ? 150 : 300) || result.points.length < 300 || lit < 300) {
  console.log(`${backend} ${enc} ${layout}: ${bad} channels beyond tolerance (${knobBad} of them with the knobs), ` +
    `${levelBad} wrong level colours, ${knobChecked} pixels with the knobs, ` +
    `${lit} lit points of ${result.points.length}`);
  process.exit(1);
}
console.log(`${backend} ${enc} ${layout}: ${result.points.length} pixels agree with the ` +
  `${gi.sh ? 'float32 loader (held to the C sampler)' : 'C sampler'}, ` +
  `bricks of levels ${[...levelsSeen].sort().join(', ')} among them`);
