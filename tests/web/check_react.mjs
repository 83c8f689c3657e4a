// check_react.mjs DIR: React Three Fiber against plain three.js. DIR holds world.glb
// and world.gi.gz; the two pages of tests/web/react/ are bundled into it with
// esbuild (three, React and R3F from web/node_modules, one copy of each) and
// opened in headless Chromium, in WebGL2 and in WebGPU. Both frames are lit by
// the volume alone: they must be the same pixels, and the R3F frame with the
// light switched off black.
import { writeFileSync } from 'node:fs';
import { createRequire } from 'node:module';
import { screenshotPixels, withPage } from './browser.mjs';

const [dir] = process.argv.slice(2);
const web = new URL('../../web/', import.meta.url);
const esbuild = createRequire(web)('esbuild');
for (const page of ['plain', 'r3f']) {
  await esbuild.build({
    entryPoints: [new URL(`react/${page}.js`, import.meta.url).pathname],
    bundle: true, format: 'esm', outfile: `${dir}/${page}.bundle.js`, logLevel: 'error',
    nodePaths: [new URL('node_modules', web).pathname],
    define: { 'process.env.NODE_ENV': '"production"' },
  });
  writeFileSync(`${dir}/${page}.html`, `<!doctype html><html><head><link rel="icon" href="data:,"></head>` +
    `<body style="margin:0;background:#000">` +
    `<script type="module" src="${page}.bundle.js"></script></body></html>\n`);
}

// R3F 9.8.2 (the newest) still makes a THREE.Clock, which three 0.187 deprecates: its
// warning, not ours, on every R3F page (web/README.md).
const allow = [/THREE\.Clock: This module has been deprecated/];
await withPage({ '/app': dir }, async ({ browser, url }) => {
  // The canvas's RGB as the page shows it, after the page's frame(...args).
  const frame = async (name, backend, ...args) => {
    const page = await browser.newPage();
    await page.goto(`${url}/app/${name}.html${backend === 'WebGPU' ? '?webgpu' : ''}`, { waitUntil: 'load' });
    await page.waitForFunction(() => typeof window.frame === 'function', { timeout: 120000 });
    await page.evaluate((a) => window.frame(...a), args);
    const px = await screenshotPixels(page, await page.$('canvas'));
    await page.close();
    return px;
  };
  for (const backend of ['WebGL2', 'WebGPU']) {
    const plain = await frame('plain', backend), r3f = await frame('r3f', backend);
    const off = await frame('r3f', backend, false);
    let differ = 0, lit = 0, offLit = 0;
    for (let i = 0; i < plain.length; i += 4) {
      const rgb = (px) => [px[i], px[i + 1], px[i + 2]];
      const [a, b, c] = [rgb(plain), rgb(r3f), rgb(off)];
      differ += a.some((v, k) => Math.abs(v - b[k]) > 1);
      lit += a.some((v) => v > 8);
      offLit += c.some((v) => v > 8);
    }
    const pixels = plain.length / 4;
    console.log(`${backend}, plain three.js: ${(100 * lit / pixels).toFixed(0)} % of the frame lit by the volume`);
    const checks = [
      [lit > 0.3 * pixels, 'the plain page lights most of the frame'],
      [differ === 0, `the R3F frame is the plain one to an 8-bit step (${differ} pixels differ)`],
      [offLit === 0, `with the light off the R3F frame is black (${offLit} pixels lit)`],
    ];
    for (const [ok, what] of checks) {
      console.log(`${ok ? 'ok' : 'FAIL'}: ${backend}: ${what}`);
      if (!ok) process.exitCode = 1;
    }
  }
}, { allow });
