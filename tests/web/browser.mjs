// browser.mjs: start the static server and Debian's headless Chromium
// (puppeteer-core: it drives the installed browser and downloads nothing),
// open tests/web/render.html, and run tasks in it.
//   WebGL2 on SwiftShader; WebGPU on SwiftShader's Vulkan adapter.
import { existsSync } from 'node:fs';
import { serve } from '../../web/serve.mjs';

const require = (await import('node:module')).createRequire(new URL('../../web/', import.meta.url));
const puppeteer = require('puppeteer-core');

export const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';

const FLAGS = [
  '--headless=new', '--no-sandbox', '--disable-gpu-sandbox', '--no-first-run', '--mute-audio',
  '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader', '--use-webgpu-adapter=swiftshader',
];

export function haveChromium() {
  return existsSync(CHROMIUM);
}

// Open the test page with `mounts` served ({ '/files': dir }) and hand fn a
// run(task) that executes in the page, and fresh(), which opens another tab
// of it (SwiftShader's WebGPU loses its device in a tab that had a WebGL2
// context); closes everything afterwards.
// Any console warning or error, or uncaught exception, in any page fails the run,
// but for those `allow` (regular expressions) expects: a test of a bad file.
export async function withPage(mounts, fn, { width = 800, height = 600, page: pagePath = '/tests/web/render.html',
  allow = [] } = {}) {
  const { server, url } = await serve({ mounts });
  // A benchmark's task runs minutes on SwiftShader: past puppeteer's 3-minute default.
  const browser = await puppeteer.launch({ executablePath: CHROMIUM, args: FLAGS,
    defaultViewport: { width, height }, protocolTimeout: 600000 });
  const messages = [];
  // Every page's console, the test page's and those a test opens itself.
  const listen = (page) => {
    page.on('console', (m) => messages.push(`${m.type()}: ${m.text()}`));
    page.on('pageerror', (e) => messages.push(`pageerror: ${e.message}`));
  };
  browser.on('targetcreated', async (target) => {
    const page = await target.page().catch(() => null);
    if (page) listen(page);
  });
  try {
    const fresh = async () => {
      const page = await browser.newPage();
      await page.goto(`${url}${pagePath}`, { waitUntil: 'load' });
      await page.waitForFunction('window.vdbgiReady === true', { timeout: 30000 });
      return { page, run: (task) => page.evaluate((t) => window.vdbgiRun(t), task) };
    };
    const { page, run } = await fresh();
    const result = await fn({ page, run, fresh, url, messages, browser });
    if (process.env.VDBGI_SHOW_CONSOLE)
      for (const m of messages) console.error(`console ${m.slice(0, 200)}`);
    // Chromium's own note that a synchronous read-back waited for the GPU: what a test that
    // reads frames back does, never the package's doing.
    const expected = [...allow, /GPU stall due to ReadPixels/];
    const unexpected = messages.filter((m) => /^(warn|warning|error|assert|pageerror):/.test(m) &&
      !expected.some((re) => re.test(m)));
    if (unexpected.length)
      throw new Error(`the pages said ${unexpected.length} warnings or errors:\n    ` +
        [...new Set(unexpected)].slice(0, 5).map((m) => m.slice(0, 300)).join('\n    '));
    return result;
  } catch (e) {
    if (messages.length) e.message += `\n  page said:\n    ${messages.slice(-10).join('\n    ')}`;
    throw e;
  } finally {
    await browser.close();
    server.close();
  }
}

// A screenshot's RGBA8 pixels (top row first), decoded by the page itself: the element's,
// or the whole page's when element is null.
export async function screenshotPixels(page, element = null) {
  const png = await (element ?? page).screenshot({ encoding: 'base64' });
  return page.evaluate(async (data) => {
    const img = new Image();
    img.src = `data:image/png;base64,${data}`;
    await img.decode();
    const c = Object.assign(document.createElement('canvas'), { width: img.width, height: img.height });
    const g = c.getContext('2d');
    g.drawImage(img, 0, 0);
    return Array.from(g.getImageData(0, 0, c.width, c.height).data);
  }, png);
}

// The mean 8-bit value of a frame's RGB channels (an RGBA8 pixel array).
export const meanLight = (px) => px.reduce((a, v, i) => (i % 4 === 3 ? a : a + v), 0) / (px.length * 0.75);

// How frame `after` differs from frame `before` (RGBA8 pixel arrays): the channels
// lower or higher by more than one 8-bit step, the pixels with any such channel,
// and the light added per channel.
export function lightChange(before, after) {
  const c = { darkerChannels: 0, brighterChannels: 0, darkerPixels: 0, brighterPixels: 0, added: [0, 0, 0] };
  for (let i = 0; i < before.length; i += 4) {
    let down = false, up = false;
    for (let k = 0; k < 3; k++) {
      const d = after[i + k] - before[i + k];
      if (d < -1) c.darkerChannels++, down = true;
      if (d > 1) c.brighterChannels++, up = true;
      c.added[k] += Math.max(d, 0);
    }
    c.darkerPixels += down;
    c.brighterPixels += up;
  }
  return c;
}
