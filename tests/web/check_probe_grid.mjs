// check_probe_grid.mjs SCENE.glb SCENE.gi.gz: our bake through three's own
// lighting path (issue 46, item 2). makeProbeGrid fills a LightProbeGridWebGL
// (WebGL2) or LightProbeGrid (WebGPU) from the volume; the scene's materials,
// untouched, then read it as three reads its own baked grid. Lit by nothing
// but the bounce, from inside each room of the interior, that frame must be our
// runtime's (per fragment, the same volume): mean light within 2 %, RMSE over
// the pixels within 2 % of the mean.
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { agreement } from './agreement.mjs';
import { withPage } from './browser.mjs';

const [scene, gi] = process.argv.slice(2);
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-grid-'));
copyFileSync(scene, join(dir, 'scene.glb'));
copyFileSync(gi, join(dir, 'scene.gi.gz'));
// Room A from its south-west corner towards the doorway; room B from its east wall.
const views = [
  { name: 'room A', camera: { fov: 70, position: [0.6, 1.6, 0.6], target: [6, 1.2, 4.5] } },
  { name: 'room B', camera: { fov: 70, position: [11.4, 1.6, 0.8], target: [6.5, 1.0, 4] } },
];
let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed++;
};
const pct = (x) => (100 * x).toFixed(2);
try {
  await withPage({ '/files': dir }, async ({ fresh }) => {
    for (const backend of ['webgl', 'webgpu'])
      for (const view of views) {
        // SwiftShader's WebGPU loses its device in a tab that had a WebGL2 context.
        const { page, run } = await fresh();
        const r = await run({ kind: 'grid', backend, scene: '/files/scene.glb', gi: '/files/scene.gi.gz', camera: view.camera });
        await page.close();
        const label = `${backend === 'webgl' ? 'WebGL2' : 'WebGPU'}, ${view.name}`;
        const { channels: n, light: so, mean, rmse } = agreement(r.ours, r.three);
        check(n > 0.5 * 3 * r.ours.length / 4 && so > 0, `${label}: the scene covers the frame and the bounce lights it`);
        check(Math.abs(mean - 1) <= 0.02 && rmse <= 0.02,
          `${label}: three's grid of ${r.resolution.join(' x ')} probes (${(r.gridBytes / 1e6).toFixed(2)} MB; the volume ` +
          `${(r.volumeBytes / 1e6).toFixed(2)} MB), filled in ${r.fillMs.toFixed(0)} ms, draws our frame: mean light ` +
          `${mean.toFixed(4)} of ours, RMSE ${pct(rmse)} % of the mean (both within 2 %)`);
      }
  });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
