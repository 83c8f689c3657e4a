// check_lightmap.mjs LIT.glb: web/viewer.html in headless Chromium with a scene
// from gi-lightmap and no probe volume. The viewer finds the lightmaps (one on
// every material), says so, and the map only adds light: with lightmaps on no
// channel is darker than with them off, and most of the frame is brighter.
// The same with the WebGPU backend (the frame's mean light within 5 % of
// WebGL2's). With LAYERS.glb (gi-lightmap --layers): the panel has a slider a
// light; at weight 1 each the composite carries the baked sum's light (the mean
// within 1 %); a light at 0 only takes light away; every light at 0 gives the
// frame without lightmaps, byte for byte; WebGPU's composite (TSL) carries the
// same light and loses the same share of it with the sun at 0.
// --save DIR writes viewer_lightmap_off.png and viewer_lightmap_on.png.
import { copyFileSync, mkdtempSync, readFileSync, rmSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { lightChange, meanLight, withPage } from './browser.mjs';

const args = process.argv.slice(2);
const save = args.includes('--save') ? args[args.indexOf('--save') + 1] : null;
const layered = args[1] && !args[1].startsWith('--') ? args[1] : null;
const dir = mkdtempSync(join(tmpdir(), 'vdbgi-lightmap-'));
copyFileSync(args[0], join(dir, 'lit.glb'));
if (layered) copyFileSync(layered, join(dir, 'layers.glb'));
const bytes = readFileSync(args[0]);
const json = JSON.parse(bytes.subarray(20, 20 + bytes.readUInt32LE(12)).toString());
const materials = json.materials.filter((m) => m.extras?.vdbgi_lightmap).length;
// No tone mapping: Neutral's desaturation can lower one channel of a pixel as light is added.
const view = process.env.VIEW ?? 'cam=-2,7,20&at=20,2,-2&gui=0&tone=0';
let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed++;
};
const grab = (page) => page.evaluate(() => {
  const c = window.vdbgiViewer.api.snapshot();
  return { png: c.toDataURL('image/png'), px: Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data) };
});
async function open(browser, url, extra = '', file = 'lit.glb') {
  const page = await browser.newPage();
  await page.setViewport({ width: 800, height: 600 });
  await page.goto(`${url}/web/viewer.html?scene=/files/${file}&${view}${extra}`);
  await page.waitForFunction('window.vdbgiViewer?.status === "ready"', { timeout: 60000 });
  await page.evaluate(() => window.vdbgiViewer.api.frame());
  return page;
}

try {
  await withPage({ '/files': dir }, async ({ browser, url }) => {
    const page = await open(browser, url);
    const s = await page.evaluate(() => ({ error: window.vdbgiViewer.error, lightmaps: window.vdbgiViewer.lightmaps,
      text: document.getElementById('figures').textContent }));
    check(!s.error && s.lightmaps === materials && materials > 0 && s.text.includes(`lightmaps on ${materials} materials`),
      `the viewer finds the lightmap of each of the ${materials} materials and says so`);
    const on = await grab(page);
    await page.evaluate(() => window.vdbgiViewer.api.setLightmap(false));
    await page.evaluate(() => window.vdbgiViewer.api.frame());
    const off = await grab(page);
    const { darkerChannels: darker, brighterPixels: brighter } = lightChange(off.px, on.px);
    const pixels = on.px.length / 4;
    check(darker === 0, `the lightmap darkens no channel beyond rounding (${darker} channels)`);
    check(brighter > pixels / 2, `the lightmap lights most of the frame (${(100 * brighter / pixels).toFixed(0)} % of pixels)`);
    console.error(`mean 8-bit light: ${meanLight(off.px).toFixed(1)} without the lightmap, ${meanLight(on.px).toFixed(1)} with it`);
    if (save) {
      writeFileSync(join(save, 'viewer_lightmap_off.png'), Buffer.from(off.png.split(',')[1], 'base64'));
      writeFileSync(join(save, 'viewer_lightmap_on.png'), Buffer.from(on.png.split(',')[1], 'base64'));
    }
    const g = await open(browser, url, '&backend=webgpu');
    const gs = await g.evaluate(() => ({ error: window.vdbgiViewer.error, lightmaps: window.vdbgiViewer.lightmaps }));
    const gpu = await grab(g);
    await g.close();
    const ratio = meanLight(gpu.px) / meanLight(on.px);
    check(!gs.error && gs.lightmaps === materials && Math.abs(ratio - 1) < 0.05,
      `WebGPU: the lightmaps found, the frame's mean light within 5 % of WebGL2's (${ratio.toFixed(3)})`);
    if (layered) {
      const sum = await open(browser, url, '&layers=0', 'layers.glb');
      const baked = await grab(sum);
      const none = await sum.evaluate(() => window.vdbgiViewer.layers.length);
      await sum.close();
      const p = await open(browser, url, '', 'layers.glb');
      const names = await p.evaluate(() => window.vdbgiViewer.layers);
      const all = await grab(p);
      const ratio = meanLight(all.px) / meanLight(baked.px);
      check(none === 0 && names.join(' ') === 'sun ambient' && Math.abs(ratio - 1) < 0.01,
        `layers: sliders for ${names.join(', ')}; at weight 1 the composite's mean light within 1 % of the baked sum's (${ratio.toFixed(4)})`);
      await p.evaluate(() => window.vdbgiViewer.api.setLayer('sun', 0));
      await p.evaluate(() => window.vdbgiViewer.api.frame());
      const dim = await grab(p);
      const { brighterChannels: brighter, darkerPixels: darker } = lightChange(all.px, dim.px);
      check(brighter === 0 && darker > 0, `layers: the sun's at 0 takes light away only (${darker} pixels darker, ${brighter} channels brighter)`);
      await p.evaluate(() => window.vdbgiViewer.api.setLayer('ambient', 0));
      await p.evaluate(() => window.vdbgiViewer.api.frame());
      const dark = await grab(p);
      await p.evaluate(() => window.vdbgiViewer.api.setLightmap(false));
      await p.evaluate(() => window.vdbgiViewer.api.frame());
      const unlit = await grab(p);
      await p.close();
      check(dark.png === unlit.png, 'layers: every light at 0 gives the frame without lightmaps, byte for byte');
      // WebGPU composites in TSL: the same light as WebGL2's composite, and the sun's weight takes the same share.
      const g = await open(browser, url, '&backend=webgpu', 'layers.glb');
      const gNames = await g.evaluate(() => window.vdbgiViewer.layers);
      const gAll = await grab(g);
      await g.evaluate(() => window.vdbgiViewer.api.setLayer('sun', 0));
      await g.evaluate(() => window.vdbgiViewer.api.frame());
      const gDim = await grab(g);
      await g.close();
      const gRatio = meanLight(gAll.px) / meanLight(all.px), gDrop = 1 - meanLight(gDim.px) / meanLight(gAll.px), glDrop = 1 - meanLight(dim.px) / meanLight(all.px);
      check(gNames.join(' ') === 'sun ambient' && Math.abs(gRatio - 1) < 0.05 && glDrop > 0.005 && Math.abs(gDrop / glDrop - 1) < 0.2,
        `layers, WebGPU: the composite's light within 5 % of WebGL2's (${gRatio.toFixed(3)}); the sun at 0 takes ` +
        `${(100 * gDrop).toFixed(2)} % of the light away, WebGL2 ${(100 * glDrop).toFixed(2)} %`);
    }
  });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
