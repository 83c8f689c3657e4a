// check_viewer.mjs SCENE.glb GOOD.gi.gz [--save DIR]: web/viewer.html in
// headless Chromium (WebGL2).
//  - With a good file (WebGL2 and WebGPU) it shows the file's figures and no error; GI on only
//    adds light (no channel darker than GI off) and lights most of the scene.
//  - Dropping both files on an empty page loads them.
//  - With a truncated file and with a foreign one (the .glb itself) it shows
//    an error naming the file and keeps rendering the scene without GI: the
//    frame is the same, byte for byte, as the good file's with GI off.
// --save DIR writes the pictures: viewer_gi_off.png, viewer_gi_on.png, and the
// debug views viewer_levels.png and viewer_bricks.png.
import { copyFileSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { lightChange, meanLight, withPage } from './browser.mjs';

const args = process.argv.slice(2);
const [scene, good] = args;
const save = args.includes('--save') ? args[args.indexOf('--save') + 1] : null;
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-viewer-'));
copyFileSync(scene, join(dir, 'world.glb'));
copyFileSync(good, join(dir, 'world.gi.gz'));
const bytes = readFileSync(good);
writeFileSync(join(dir, 'cut.gi.gz'), bytes.subarray(0, Math.floor(bytes.length / 2)));

// Towards the canyon wall at x = +24 in its own shadow, over shaded grass.
const view = process.env.VIEW ?? 'cam=-2,7,20&at=20,2,-2&gui=0';
let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed++;
};

// Each file in a fresh tab: SwiftShader's WebGPU stalls in a tab that had a WebGL2 context.
async function open(browser, url, gi, extra = '') {
  const page = await browser.newPage();
  await page.setViewport({ width: 800, height: 600 });
  await page.goto(`${url}/web/viewer.html?scene=/files/world.glb&gi=/files/${gi}&${view}${extra}`);
  await page.waitForFunction('window.vdbgiViewer?.status === "ready"', { timeout: 60000 });
  await page.evaluate(() => window.vdbgiViewer.api.frame());
  const state = await page.evaluate(() => ({ error: window.vdbgiViewer.error, figures: window.vdbgiViewer.figures,
    text: document.getElementById('figures').textContent, shown: document.getElementById('error').textContent }));
  return { page, ...state };
}

// The canvas as a PNG and as pixels, from a frame drawn for it.
const grab = (page) => page.evaluate(() => {
  const c = window.vdbgiViewer.api.snapshot();
  return { png: c.toDataURL('image/png'), px: Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data) };
});

try {
  await withPage({ '/files': dir }, async ({ browser, url }) => {
    const s = await open(browser, url, 'world.gi.gz');
    const page = s.page;
    check(!s.error && s.figures && s.figures.bricks.reduce((a, b) => a + b) > 0 && /bricks L0\.\.L3/.test(s.text),
      'a good file: no error, the figures shown');
    const on = await grab(page);
    await page.evaluate(() => window.vdbgiViewer.api.setGi(false));
    await page.evaluate(() => window.vdbgiViewer.api.frame());
    const off = await grab(page);
    const { darkerChannels: darker, brighterPixels: brighter, added } = lightChange(off.px, on.px);
    const pixels = on.px.length / 4;
    check(darker === 0, `GI on darkens no channel beyond rounding (${darker} channels)`);
    check(brighter > pixels / 2, `GI on lights most of the frame (${(100 * brighter / pixels).toFixed(0)} % of pixels)`);
    console.error(`added light, mean per pixel: r ${(added[0] / pixels).toFixed(2)} g ${(added[1] / pixels).toFixed(2)} ` +
      `b ${(added[2] / pixels).toFixed(2)} (8-bit)`);
    if (save) {
      const write = (name, shot) => writeFileSync(join(save, name), Buffer.from(shot.png.split(',')[1], 'base64'));
      write('viewer_gi_off.png', off);
      write('viewer_gi_on.png', on);
      // The debug views (web/vdbgi.js DebugView: 2 brick level, 3 brick boundaries).
      for (const [view, name] of [[2, 'viewer_levels.png'], [3, 'viewer_bricks.png']]) {
        await page.evaluate((v) => window.vdbgiViewer.api.setDebug(v), view);
        write(name, await grab(page));
      }
      await page.evaluate(() => window.vdbgiViewer.api.setDebug(0));
    }
    const g = await open(browser, url, 'world.gi.gz', '&backend=webgpu');
    const gpuFrame = await grab(g.page);
    await g.page.close();
    check(!g.error && g.figures && /WebGPU/.test(g.text), `WebGPU: no error, the figures shown${g.error ? ` (${g.error})` : ''}`);
    // The same scene through WebGPURenderer and TSL: it differs from WebGL2 in
    // shadow filtering and rasterisation, so compare the light, not the bytes.
    const ratio = meanLight(gpuFrame.px) / meanLight(on.px);
    check(Math.abs(ratio - 1) < 0.05, `WebGPU: the frame's mean light within 5 % of WebGL2's with GI on (${ratio.toFixed(3)})`);
    // Drag and drop: both files on a page opened without any.
    const d = await browser.newPage();
    await d.goto(`${url}/web/viewer.html?gui=0`);
    await d.waitForFunction('window.vdbgiViewer?.status === "ready"', { timeout: 60000 });
    await d.evaluate(async () => {
      const dt = new DataTransfer();
      for (const [src, name] of [['/files/world.glb', 'world.glb'], ['/files/world.gi.gz', 'dropped.gi.gz']])
        dt.items.add(new File([await (await fetch(src)).arrayBuffer()], name));
      window.dispatchEvent(new DragEvent('drop', { dataTransfer: dt, cancelable: true }));
    });
    await d.waitForFunction('window.vdbgiViewer.gi === "dropped.gi.gz" || window.vdbgiViewer.error', { timeout: 60000 });
    const dropped = await d.evaluate(() => ({ scene: window.vdbgiViewer.scene, error: window.vdbgiViewer.error,
      text: document.getElementById('figures').textContent }));
    await d.close();
    check(!dropped.error && dropped.scene === 'world.glb' && dropped.text.startsWith('dropped.gi.gz:'),
      'dropping a .glb and a .gi.gz on the page loads both');
    for (const bad of ['cut.gi.gz', 'world.glb']) {
      const b = await open(browser, url, bad);
      check(b.error && b.error.startsWith(`/files/${bad}:`) && b.shown === b.error, `${bad}: the page says "${b.error}"`);
      const frame = await grab(b.page);
      await b.page.close();
      check(frame.png === off.png, `${bad}: the scene still renders, without GI`);
    }
  }, { allow: [/^error: Error: \/files\/(cut\.gi\.gz: cut short|world\.glb: a binary glTF)/] }); // the bad files, on purpose
} finally {
  rmSync(dir, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
