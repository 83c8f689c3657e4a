// check_package.mjs APP_DIR [--r3f]: open APP_DIR/index.html (a scratch app built
// from web/README.md's example) in headless Chromium and check that it draws the
// scene: most of the frame is not the background, and no page said a warning
// or an error (browser.mjs fails the run on any). --r3f: a React Three Fiber app,
// whose THREE.Clock warning is R3F's own (web/README.md).
import { screenshotPixels, withPage } from './browser.mjs';

const [app, kind] = process.argv.slice(2);
const allow = kind === '--r3f' ? [/THREE\.Clock: This module has been deprecated/] : [];
await withPage({ '/app': app }, async ({ browser, url }) => {
  const page = await browser.newPage();
  await page.setViewport({ width: 800, height: 600 });
  await page.goto(`${url}/app/index.html`, { waitUntil: 'networkidle0', timeout: 120000 });
  await page.waitForFunction(() => document.querySelector('canvas'), { timeout: 60000 });
  await new Promise((done) => setTimeout(done, 3000)); // a few frames after the loads
  // The share of pixels that are not the sky.
  const px = await screenshotPixels(page);
  const sky = [px[0], px[1], px[2]]; // the top-left corner is sky in the example's view
  let other = 0;
  for (let i = 0; i < px.length; i += 4)
    other += Math.abs(px[i] - sky[0]) + Math.abs(px[i + 1] - sky[1]) + Math.abs(px[i + 2] - sky[2]) > 12;
  const scene = other / (px.length / 4);
  await page.close();
  const ok = scene > 0.3;
  console.log(`${ok ? 'ok' : 'FAIL'}: the example draws the scene over ${ok ? 'most of' : 'only'} the frame` +
    `${ok ? '' : ` (${(100 * scene).toFixed(0)} %)`}`);
  if (!ok) process.exitCode = 1;
}, { allow });
