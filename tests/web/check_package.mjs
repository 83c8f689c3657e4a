// check_package.mjs APP_DIR: open APP_DIR/index.html (a scratch app built from
// web/README.md's example) in headless Chromium and check that it draws the
// scene: most of the frame is not the background, and no page said a warning
// or an error (browser.mjs fails the run on any).
import { withPage } from './browser.mjs';

const [app] = process.argv.slice(2);
await withPage({ '/app': app }, async ({ browser, url }) => {
  const page = await browser.newPage();
  await page.setViewport({ width: 800, height: 600 });
  await page.goto(`${url}/app/index.html`, { waitUntil: 'networkidle0', timeout: 120000 });
  await page.waitForFunction(() => document.querySelector('canvas'), { timeout: 60000 });
  await new Promise((done) => setTimeout(done, 3000)); // a few frames after the loads
  const shot = await page.screenshot({ encoding: 'base64' });
  // The page decodes its own screenshot: the share of pixels that are not the sky.
  const scene = await page.evaluate(async (png) => {
    const img = new Image();
    img.src = `data:image/png;base64,${png}`;
    await img.decode();
    const c = Object.assign(document.createElement('canvas'), { width: img.width, height: img.height });
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    const px = g.getImageData(0, 0, c.width, c.height).data;
    const sky = [px[0], px[1], px[2]]; // the top-left corner is sky in the example's view
    let other = 0;
    for (let i = 0; i < px.length; i += 4)
      other += Math.abs(px[i] - sky[0]) + Math.abs(px[i + 1] - sky[1]) + Math.abs(px[i + 2] - sky[2]) > 12;
    return other / (px.length / 4);
  }, shot);
  await page.close();
  const ok = scene > 0.3;
  console.log(`${ok ? 'ok' : 'FAIL'}: the example draws the scene over ${ok ? 'most of' : 'only'} the frame` +
    `${ok ? '' : ` (${(100 * scene).toFixed(0)} %)`}`);
  if (!ok) process.exitCode = 1;
});
