// bench_occluders.mjs SCENE.glb SCENE.gi.gz [FRAMES]: what 16 occluders cost a
// frame in headless Chromium on SwiftShader, WebGL2 and WebGPU: SCENE at 800 x
// 600 lit with SCENE.gi.gz per vertex and per fragment, without occluders and
// with 16 spheres over it (render.mjs's frames task). SwiftShader renders on
// the CPU: only the ratios say anything about a GPU. Prints a markdown table.
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { withPage } from './browser.mjs';

const [scene, gi, frames = '10'] = process.argv.slice(2);
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-occ-bench-'));
copyFileSync(scene, join(dir, 'scene.glb'));
copyFileSync(gi, join(dir, 'scene.gi.gz'));
const ms = (v) => `${v.toFixed(1)} ms`;
try {
  await withPage({ '/files': dir }, async ({ fresh }) => {
    console.log('| backend | per vertex | + 16 occluders | ratio | per fragment | + 16 occluders | ratio |');
    console.log('|---|---:|---:|---:|---:|---:|---:|');
    for (const backend of ['webgl', 'webgpu']) {
      const tab = await fresh();
      const r = await tab.run({ kind: 'frames', backend, scene: '/files/scene.glb', gi: '/files/scene.gi.gz',
        width: 800, height: 600, frames: Number(frames), occluders: 16 });
      console.log(`| ${backend === 'webgl' ? 'WebGL2' : 'WebGPU'} | ${ms(r.vertex)} | ${ms(r.vertexOccluded)} | ` +
        `${(r.vertexOccluded / r.vertex).toFixed(3)} | ${ms(r.fragment)} | ${ms(r.fragmentOccluded)} | ` +
        `${(r.fragmentOccluded / r.fragment).toFixed(3)} |`);
      await tab.page.close();
    }
  });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
