// bench_viewer.mjs NAME=SCENE.glb,FILE.gi.gz ...: the viewer's load as a user
// sees it (make bench; docs/web.md): for each world and back end, the viewer
// page opened fresh with the scene and its volume, and the time from the start
// of the volume's load to its first lit frame, shaders compiled (the viewer
// draws nothing while the volume loads); median of 3 pages. Prints a table.
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { basename, join } from 'node:path';
import { withPage } from './browser.mjs';

const dir = mkdtempSync(join(tmpdir(), 'vdbgi-viewer-'));
const worlds = process.argv.slice(2).map((arg) => {
  const [name, files] = arg.split('=');
  const [scene, gi] = files.split(',');
  copyFileSync(scene, join(dir, `${name}-${basename(scene)}`));
  copyFileSync(gi, join(dir, `${name}-${basename(gi)}`));
  return { name, scene: `/files/${name}-${basename(scene)}`, gi: `/files/${name}-${basename(gi)}` };
});
const median = (a) => a.slice().sort((x, y) => x - y)[Math.floor(a.length / 2)];
const ms = (v) => `${v.toFixed(0)} ms`;
try {
  await withPage({ '/files': dir }, async ({ browser, url }) => {
    console.log('| world | back end | fetch | gunzip | check and rebuild | textures | upload | first lit frame |');
    console.log('|---|---|---:|---:|---:|---:|---:|---:|');
    for (const w of worlds)
      for (const backend of ['webgl', 'webgpu']) {
        const runs = [];
        for (let i = 0; i < 3; i++) {
          const page = await browser.newPage(); // a fresh tab each: SwiftShader's WebGPU stalls otherwise
          await page.setViewport({ width: 800, height: 600 });
          await page.goto(`${url}/web/viewer.html?scene=${w.scene}&gi=${w.gi}&backend=${backend}&gui=0`);
          await page.waitForFunction('window.vdbgiViewer?.status === "ready"', { timeout: 180000 });
          const t = await page.evaluate(() => window.vdbgiViewer.figures?.timings);
          await page.close();
          if (!t) throw new Error(`${w.name} (${backend}): no volume loaded`);
          runs.push(t);
        }
        const m = (k) => median(runs.map((r) => r[k] ?? 0));
        console.log(`| ${w.name} | ${backend === 'webgpu' ? 'WebGPU' : 'WebGL2'} | ${ms(m('fetch'))} | ${ms(m('gunzip'))} | ` +
          `${ms(m('parse'))} | ${ms(m('build'))} | ${backend === 'webgl' ? ms(m('upload')) : '–'} | **${ms(m('firstFrame'))}** |`);
      }
  }, { width: 800, height: 600 });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
