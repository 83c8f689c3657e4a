// check_split.mjs LIT.glb WORLD.gi.gz: GiRuntime.lightScene() (issue 40, item 2), the
// split in one call, in headless Chromium, WebGL2 and WebGPU: a gi-lightmap .glb's
// meshes take their lightmaps, a sphere named as moving takes the volume per
// fragment and shadows what is near it. The frame equals the one docs/lightmap.md's
// recipe draws by hand (within float rounding); lightScene() counts every mesh
// whose material has a lightmap; the split adds the baked bounce to the sun and
// ambient's light.
import { copyFileSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { withPage } from './browser.mjs';

const [lit, gi] = process.argv.slice(2);
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-split-'));
copyFileSync(lit, join(dir, 'lit.glb'));
copyFileSync(gi, join(dir, 'world.gi.gz'));
const bytes = readFileSync(lit);
const json = JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString());
const withMap = new Set(json.materials.flatMap((m, i) => (m.extras?.vdbgi_lightmap ? [i] : [])));
const meshesWithMap = json.nodes.filter((n) => n.mesh !== undefined)
  .flatMap((n) => json.meshes[n.mesh].primitives).filter((p) => withMap.has(p.material)).length;
let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed++;
};
try {
  await withPage({ '/files': dir }, async ({ fresh }) => {
    for (const backend of ['webgl', 'webgpu']) {
      const { page, run } = await fresh();
      const r = await run({ kind: 'split', backend, scene: '/files/lit.glb', gi: '/files/world.gi.gz', hero: [2, 1.2, 3] });
      await page.close();
      const name = backend === 'webgl' ? 'WebGL2' : 'WebGPU';
      let worst = 0, split = 0, alone = 0;
      for (let i = 0; i < r.byCall.length; i += 4) {
        if (!r.unlit[i + 3]) continue;
        for (let k = 0; k < 3; k++) {
          worst = Math.max(worst, Math.abs(r.byCall[i + k] - r.byHand[i + k]) / Math.max(r.byHand[i + k], 1e-3));
          split += r.byCall[i + k];
          alone += r.unlit[i + k];
        }
      }
      check(r.counts.lightmapped === meshesWithMap && r.counts.moving === 1,
        `${name}: lightScene() lights ${r.counts.lightmapped} meshes by their lightmaps (the .glb has ${meshesWithMap}), ` +
        `${r.counts.volume} by the volume, ${r.counts.moving} moving`);
      check(worst < 1e-4, `${name}: the frame is the hand-written recipe's (largest difference ${worst < 1e-4 ? 'below 1e-4' : worst.toExponential(2)} relative)`);
      // The bounce the lightmaps hold (the sun stays live) adds to what the lights give.
      check(split > 1.02 * alone, `${name}: the split adds the bounce: the frame's light ${split > 1.02 * alone ? 'more than 1.02' : 'only'} times ` +
        `the sun and ambient's${split > 1.02 * alone ? '' : ` (${(split / alone).toFixed(3)})`}`);
    }
  });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
