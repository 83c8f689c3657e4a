// bench_probe_grid.mjs NAME=SCENE.glb,SCENE.gi.gz...: our bake through three's own
// light probe grid (makeProbeGrid, issue 46, item 2) against our runtime, in
// headless Chromium (SwiftShader), WebGL2 and WebGPU, each scene lit by the bounce
// alone at 960 x 540: the grid's probes and bytes beside the volume's, the time
// to fill it, the median of 8 frames with no bounce light, with ours per fragment
// and with three's grid, and how far the grid's frame is from ours. A markdown table.
// NAME picks the camera by its first word (interior, or the demo world's).
import { copyFileSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { decodeGi } from '../../web/gi-format.js';
import { occupiedBox } from '../../web/gi-probe-grid.js';
import { GiVolume } from '../../web/vdbgi.js';
import { agreement } from './agreement.mjs';
import { withPage } from './browser.mjs';

// Inside the interior's room A; the demo world's camera (tests/web/render.mjs, stage()).
const CAMERAS = {
  interior: { fov: 70, position: [0.6, 1.6, 0.6], target: [6, 1.2, 4.5] },
  world: { fov: 50, position: [26, 17, 30], target: [0, 1, 0] },
};
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-gridbench-'));
// NAME=-,FILE.gi.gz: no frames, only the dense grid's size (a world too large to draw so).
const sizeOnly = [];
const scenes = process.argv.slice(2).flatMap((arg, i) => {
  const [name, files] = arg.split('=');
  const [glb, gi] = files.split(',');
  if (glb === '-') {
    sizeOnly.push({ name, gi });
    return [];
  }
  copyFileSync(glb, join(dir, `s${i}.glb`));
  copyFileSync(gi, join(dir, `s${i}.gi.gz`));
  return [{ name, scene: `/files/s${i}.glb`, gi: `/files/s${i}.gi.gz`, camera: CAMERAS[name.split(',')[0]] ?? CAMERAS.world }];
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
        const { mean, rmse } = agreement(r.ours, r.three);
        const f = t.frameMs;
        if (backend === 'webgl') {
          const [x, y, z] = r.resolution, sp = r.spacing;
          s.sizes = [{ name: s.name, spacing: sp, probes: x * y * z },
            { name: s.name, spacing: 2 * sp, probes: Math.ceil(x / 2) * Math.ceil(y / 2) * Math.ceil(z / 2) }];
        }
        console.log(`| ${s.name} | ${backend === 'webgl' ? 'WebGL2' : 'WebGPU'} | ${r.resolution.join(' x ')}, ${mb(r.gridBytes)} | ` +
          `${mb(r.volumeBytes)} | ${r.fillMs.toFixed(0)} | ${f.none.toFixed(0)} / ${f.ours.toFixed(0)} / ${f.three.toFixed(0)} | ` +
          `${mean.toFixed(4)}, ${(100 * rmse).toFixed(2)} % |`);
      }
  });
  // Where three's own WebGL bake cannot run: each scene's dense grid at its volume's
  // spacing (and at twice it), as makeProbeGrid sizes it, against the 9 x N target
  // the bake needs.
  // One row a grid (a scene given twice, with and without its terms, has one).
  const sizes = scenes.flatMap((s) => s.sizes)
    .filter((z, i, all) => all.findIndex((o) => o.probes === z.probes && o.spacing === z.spacing) === i);
  for (const { name, gi } of sizeOnly) {
    const volume = new GiVolume(await decodeGi(new Uint8Array(readFileSync(gi)), {}, { maxBytes: 2 ** 31 }));
    const box = occupiedBox(volume), sp = volume.info.spacing;
    for (const k of [1, 2])
      sizes.push({ name, spacing: k * sp, probes: box.min.reduce((n, lo, a) => n * Math.round((box.max[a] - lo) / (k * sp)), 1) });
  }
  await withPage({ '/files': dir }, async ({ run }) => {
    const r = await run({ kind: 'gridLimit', probes: sizes.map((z) => z.probes) });
    console.log();
    console.log(`three's WebGL bake of the same grids (a 9 x N float target; this browser's largest side ${r.maxTextureSize}):`);
    console.log();
    console.log('| scene | spacing | probes | its float32 grid (112 B a probe), MB | its bake\'s target |');
    console.log('|---|---:|---:|---:|---|');
    sizes.forEach((z, i) => console.log(`| ${z.name} | ${z.spacing} m | ${z.probes} | ${mb(z.probes * 112)} | ` +
      `${r.errors[i] === 0 ? 'made' : `WebGL error 0x${r.errors[i].toString(16)}: it cannot bake`} |`));
  }, { allow: [/out of range|INVALID_VALUE/] });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
