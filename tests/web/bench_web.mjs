// bench_web.mjs SCENE.glb SCENE.gi.gz [NAME=FILE.gi.gz ...]: the browser
// runtime's figures in headless Chromium on SwiftShader (make bench).
//  - load: each file, fetched from 127.0.0.1, gunzipped (DecompressionStream),
//    checked, made into textures and uploaded (WebGL2), median of 5 loads, with
//    the longest task the page ran meanwhile (PerformanceObserver, 50 ms and up),
//    decoded in loadGi's worker (with the C reader as WebAssembly, its default, and
//    told ?reader=js) and on the page (worker: false), and the frames a
//    second an animated page (8 ms of its own work a frame) drew meanwhile;
//  - frames: SCENE at 800 x 600 lit with SCENE.gi.gz, frame time with GI off,
//    per vertex and per fragment (WebGL2 and WebGPU). SwiftShader renders on
//    the CPU, so only the ratios say anything about a GPU.
// Prints markdown tables.
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, join } from 'node:path';
import { withPage } from './browser.mjs';

const [scene, sceneGi, ...more] = process.argv.slice(2);
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-bench-'));
copyFileSync(scene, join(dir, 'scene.glb'));
copyFileSync(sceneGi, join(dir, 'scene.gi.gz'));
const files = [['bundled 48 m', 'scene.gi.gz']];
for (const m of more) {
  const [name, file] = m.includes('=') ? m.split('=') : [basename(m), m];
  copyFileSync(file, join(dir, basename(file)));
  files.push([name, basename(file)]);
}
const median = (a) => a.slice().sort((x, y) => x - y)[Math.floor(a.length / 2)];
const f1 = (v) => v.toFixed(1);

try {
  await withPage({ '/files': dir }, async ({ run, fresh }) => {
    console.log('| file | decoder | size | VRAM | fetch | gunzip | check | textures | upload | total | longest task | page\'s fps meanwhile |');
    console.log('|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|');
    for (const [name, file] of files) for (const worker of ['auto', '/web/gi-worker.js?reader=js', false]) {
      const runs = [];
      for (let i = 0; i < 5; i++) {
        const r = await run({ kind: 'load', gi: `/files/${file}`, worker });
        if (!r.ok) throw new Error(`${file}: ${r.error}`);
        runs.push(r);
      }
      const t = (k) => median(runs.map((r) => r.timings[k]));
      // fetch holds gunzip (a URL's body is unpacked as it arrives): the total is the wall clock.
      const total = median(runs.map((r) => r.wall));
      const longest = median(runs.map((r) => r.longestTask));
      // Two more loads with the page animating: its frames a second, the lower.
      let fps = Infinity;
      for (let i = 0; i < 2; i++) fps = Math.min(fps, (await run({ kind: 'load', gi: `/files/${file}`, worker, animate: true })).fps);
      console.log(`| ${name} | ${runs[0].timings.decoder} (${runs[0].timings.reader}) | ${(runs[0].fileBytes / 1e6).toFixed(2)} MB | ${(runs[0].vramBytes / 1e6).toFixed(2)} MB | ` +
        `${f1(t('fetch'))} ms | ${f1(t('gunzip'))} ms | ${f1(t('parse'))} ms | ${f1(t('build'))} ms | ${f1(t('upload'))} ms | ${f1(total)} ms | ${longest ? `${f1(longest)} ms` : 'none ≥ 50 ms'} | ${fps.toFixed(0)} |`);
    }
    console.log();
    console.log('| backend | GI off | GI per vertex | GI per fragment | per vertex / off | per fragment / off |');
    console.log('|---|---:|---:|---:|---:|---:|');
    for (const backend of ['webgl', 'webgpu']) {
      const tab = await fresh();
      const r = await tab.run({ kind: 'frames', backend, scene: '/files/scene.glb', gi: '/files/scene.gi.gz',
        width: 800, height: 600, frames: 30 });
      console.log(`| ${backend === 'webgl' ? 'WebGL2' : 'WebGPU'} | ${f1(r.off)} ms | ${f1(r.vertex)} ms | ${f1(r.fragment)} ms | ` +
        `${(r.vertex / r.off).toFixed(2)} | ${(r.fragment / r.off).toFixed(2)} |`);
      await tab.page.close();
    }
  });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
