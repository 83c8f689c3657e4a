// bench_probe_grid.mjs NAME=SCENE.glb,SCENE.gi.gz...: our bake through three's own
// light probe grid (makeProbeGrid, issue 46, item 2) against our runtime, in
// headless Chromium (SwiftShader), WebGL2 and WebGPU, each scene lit by the bounce
// alone at 960 x 540: the grid's probes and bytes beside the volume's, the time
// to fill it, the median of 8 frames with no bounce light, with ours per fragment
// and with three's grid, and how far the grid's frame is from ours. A markdown table.
// NAME picks the camera by its first word (interior, or the demo world's).
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { withPage } from './browser.mjs';

// Inside the interior's room A; the demo world's camera (tests/web/render.mjs, stage()).
const CAMERAS = {
  interior: { fov: 70, position: [0.6, 1.6, 0.6], target: [6, 1.2, 4.5] },
  world: { fov: 50, position: [26, 17, 30], target: [0, 1, 0] },
};
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-gridbench-'));
const scenes = process.argv.slice(2).map((arg, i) => {
  const [name, files] = arg.split('=');
  const [glb, gi] = files.split(',');
  copyFileSync(glb, join(dir, `s${i}.glb`));
  copyFileSync(gi, join(dir, `s${i}.gi.gz`));
  return { name, scene: `/files/s${i}.glb`, gi: `/files/s${i}.gi.gz`, camera: CAMERAS[name.split(',')[0]] ?? CAMERAS.world };
});
const mb = (b) => (b / 1e6).toFixed(2);
console.log('| scene | back end | three\'s grid: probes, MB | our volume, MB | fill, ms | frame: no bounce / ours / three\'s grid, ms | grid/ours: mean, RMSE |');
console.log('|---|---|---|---:|---:|---|---|');
try {
  await withPage({ '/files': dir }, async ({ fresh }) => {
    for (const s of scenes)
      for (const backend of ['webgl', 'webgpu']) {
        const task = { kind: 'grid', backend, scene: s.scene, gi: s.gi, camera: s.camera, width: 960, height: 540 };
        const { page, run } = await fresh();
        const r = await run(task);
        const t = await run({ ...task, frames: 8 });
        await page.close();
        let so = 0, se = 0, n = 0;
        for (let i = 0; i < r.ours.length; i += 4) {
          if (!r.ours[i + 3]) continue;
          for (let k = 0; k < 3; k++) {
            so += r.ours[i + k];
            se += (r.three[i + k] - r.ours[i + k]) ** 2;
            n++;
          }
        }
        let st = 0;
        for (let i = 0; i < r.three.length; i += 4) if (r.ours[i + 3]) st += r.three[i] + r.three[i + 1] + r.three[i + 2];
        const f = t.frameMs;
        console.log(`| ${s.name} | ${backend === 'webgl' ? 'WebGL2' : 'WebGPU'} | ${r.resolution.join(' x ')}, ${mb(r.gridBytes)} | ` +
          `${mb(r.volumeBytes)} | ${r.fillMs.toFixed(0)} | ${f.none.toFixed(0)} / ${f.ours.toFixed(0)} / ${f.three.toFixed(0)} | ` +
          `${(st / so).toFixed(4)}, ${(100 * Math.sqrt(se / n) / (so / n)).toFixed(2)} % |`);
      }
  });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
