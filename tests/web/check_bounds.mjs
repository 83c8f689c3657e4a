// check_bounds.mjs ROOM.gi.gz ROOM.vdb: the browser loader within bounds (issue 47,
// items 1, 2 and 6). Each input goes to loadGi(url) with its defaults in a fresh
// tab of headless Chromium, WebGL2 and WebGPU, and a floor is drawn with what
// loads. Judged by the browser's process memory (the proportional set size of
// every Chromium process, sampled every 20 ms, from after the tab made its
// renderer: the JS heap hides textures and inflated bytes):
//   bomb, sent Content-Encoding: gzip: a valid header, then 10^9 zeros (the
//     browser inflates it; the loader stops at the header's size);
//   bomb.gi.gz: the same bytes as a file (the loader inflates, and stops);
//   huge-atlas.gi.gz: well formed, an empty 963 MB atlas (refused by the budget);
//   budget-edge.gi.gz: well formed, 30.4 MiB of empty textures (loads and draws);
//   absurd-range, cut short, a .vdb, an HTML page: refused by name;
//   room.gi.gz: a real volume, which loads and lights the floor.
// Every refusal names the URL and what is wrong; every input is done within
// +256 MB of process memory. Times are reported (make bench's job to judge).
import { readFileSync, readdirSync } from 'node:fs';
import { createServer } from 'node:http';
import { gunzipSync, gzipSync, createGzip } from 'node:zlib';
import { withPage } from './browser.mjs';

const [giPath, vdbPath] = process.argv.slice(2);
const room = readFileSync(giPath);
const raw = gunzipSync(room);
const MB = 1 << 20;

// gzip of `head` and then `zeros` zero bytes, streamed (never a buffer that size).
async function gzipZeros(head, zeros) {
  const gz = createGzip({ level: 9, chunkSize: MB });
  const out = [];
  gz.on('data', (d) => out.push(d));
  const done = new Promise((resolve) => gz.on('end', resolve));
  gz.write(head);
  const block = Buffer.alloc(16 * MB);
  for (let left = zeros; left > 0; left -= block.length)
    if (!gz.write(block.subarray(0, Math.min(left, block.length)))) await new Promise((r) => gz.once('drain', r));
  gz.end();
  await done;
  return Buffer.concat(out);
}

// A version 1 header (docs/format.md) for an empty seed-layout volume: 4^3 cells of
// 1 m over 16 m, the atlas dims given; every cell empty.
function emptyHeader(atlas) {
  const h = Buffer.alloc(112);
  h.write('vdbgi.gi', 0, 'latin1');
  const u32 = [1, 112, 0];
  u32.forEach((v, i) => h.writeUInt32LE(v, 8 + 4 * i));
  h.writeFloatLE(8, 20);
  [4, 4, 4, ...atlas].forEach((v, i) => h.writeUInt32LE(v, 24 + 4 * i));
  [0, 0, 0, 16, 16, 16, 1].forEach((v, i) => h.writeFloatLE(v, 48 + 4 * i));
  h.writeUInt32LE(256, 96);
  h.writeUInt32LE(atlas[0] * atlas[1] * atlas[2] * 4, 100);
  return h;
}
const emptyVolume = (atlas) => gzipZeros(emptyHeader(atlas), 256 + atlas[0] * atlas[1] * atlas[2] * 4);

const absurd = Buffer.from(raw);
absurd.writeFloatLE(3.4e38, 20);
const bomb = await gzipZeros(raw, 1e9);
const files = {
  'bomb': { body: bomb, headers: { 'Content-Encoding': 'gzip' } },
  'bomb.gi.gz': { body: bomb },
  'huge-atlas.gi.gz': { body: await emptyVolume([1536, 1536, 102]) },
  'budget-edge.gi.gz': { body: await emptyVolume([1536, 864, 6]) },
  'absurd-range.gi.gz': { body: gzipSync(absurd) },
  'cut.gi.gz': { body: room.subarray(0, room.length >> 1) },
  'room.vdb': { body: readFileSync(vdbPath) },
  'missing.gi.gz': { body: Buffer.from('<!DOCTYPE html>\n<html><body>Not here</body></html>\n'),
    headers: { 'Content-Type': 'text/html' } },
  'room.gi.gz': { body: room },
};
// What each input must do: load (and how the floor looks), or be refused saying this.
const expect = {
  'bomb': [/holds more than the \d+ bytes its header declares/, 'more bytes than the header declares'],
  'bomb.gi.gz': [/holds more than the \d+ bytes its header declares/, 'more bytes than the header declares'],
  'huge-atlas.gi.gz': [/unpacks to 918\.0 MiB .* past the 32\.0 MiB budget: pass loadGi a larger maxBytes/, 'the budget'],
  'budget-edge.gi.gz': 'loads dark',
  'absurd-range.gi.gz': [/rgbm_range 3\.4e\+38 is outside/, 'the rgbm_range'],
  'cut.gi.gz': [/cut short: the \.gi ends at byte \d+ of the \d+ its header declares/, 'where it is cut'],
  'room.vdb': [/an OpenVDB file \(\.vdb\), not a \.gi\.gz: convert it first \(vdb-to-gi/, 'vdb-to-gi'],
  'missing.gi.gz': [/text beginning "<!DOCTYPE html>/, 'an HTML page'],
  'room.gi.gz': 'loads lit',
};

const server = createServer((req, res) => {
  const f = files[decodeURIComponent(req.url.slice(1))];
  if (!f) return res.writeHead(404).end();
  res.writeHead(200, { 'Content-Type': 'application/octet-stream', 'Content-Length': f.body.length,
    'Access-Control-Allow-Origin': '*', ...f.headers });
  res.end(f.body);
});
await new Promise((done) => server.listen(0, '127.0.0.1', done));
const base = `http://127.0.0.1:${server.address().port}`;

// The proportional set size of a process and all its descendants, in bytes.
function treePss(root) {
  const children = new Map();
  for (const d of readdirSync('/proc')) {
    if (!/^\d+$/.test(d)) continue;
    try {
      const stat = readFileSync(`/proc/${d}/stat`, 'latin1');
      const ppid = Number(stat.slice(stat.lastIndexOf(')') + 2).split(' ')[1]);
      if (!children.has(ppid)) children.set(ppid, []);
      children.get(ppid).push(Number(d));
    } catch { /* gone */ }
  }
  let total = 0;
  const stack = [root];
  while (stack.length) {
    const pid = stack.pop();
    try {
      const m = /^Pss:\s+(\d+) kB/m.exec(readFileSync(`/proc/${pid}/smaps_rollup`, 'latin1'));
      if (m) total += Number(m[1]) * 1024;
    } catch { /* gone */ }
    stack.push(...(children.get(pid) ?? []));
  }
  return total;
}

let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed++;
};
const rows = [];
try {
  await withPage({}, async ({ fresh, browser, page: first }) => {
    await first.close();
    const pid = browser.process().pid;
    for (const backend of ['webgl', 'webgpu']) {
      for (const name of Object.keys(files)) {
        const { page, run } = await fresh();
        await run({ kind: 'boundsSetup', backend });
        // The peak over a step, above what the tab held before it.
        const measure = async (task) => {
          const before = treePss(pid);
          let peak = before;
          const timer = setInterval(() => { peak = Math.max(peak, treePss(pid)); }, 20);
          try {
            const r = await run(task);
            return { ...r, grew: (Math.max(peak, treePss(pid)) - before) / MB };
          } finally {
            clearInterval(timer);
          }
        };
        const url = `${base}/${name}`;
        const r = await measure({ kind: 'boundsLoad', gi: url });
        // The room (x and z -3..3, 3 m tall) lights a floor inside it.
        const drawn = r.ok ? await measure({ kind: 'boundsDraw', floor: name === 'room.gi.gz' ? [-3, -3, 3, 3, 0.5] : undefined }) : null;
        await page.close();
        const want = expect[name];
        const label = `${backend === 'webgl' ? 'WebGL2' : 'WebGPU'} ${name}`;
        rows.push({ label, ms: r.ms, grew: r.grew, drawn, said: r.ok ? `loaded, floor ${drawn.light.toFixed(1)}` : r.error });
        if (typeof want === 'string') {
          const lit = want === 'loads lit';
          check(r.ok && (lit ? drawn.light > 1 : drawn.light < 1), `${label} ${want}${r.ok ? '' : `: ${r.error}`}`);
        } else {
          const [says, what] = want;
          check(!r.ok && r.error.startsWith(`${url}: `) && says.test(r.error),
            `${label} refused, naming the URL and ${what}` +
            (r.ok ? ' (it loaded)' : says.test(r.error) ? '' : ` (said "${r.error}")`));
        }
        check(r.grew < 256, `${label}: the load within +256 MB of process memory` + (r.grew < 256 ? '' : ` (+${r.grew.toFixed(0)} MB)`));
      }
    }
  }, { allow: [/Failed to load resource/, /GL_INVALID|WebGL|GPU stall/] });
} finally {
  server.close();
}
// The figures, for docs/web.md ("Bounds"): to stderr, as they vary run to run.
const f = (ms, mb) => `${(ms / 1000).toFixed(2)} s, +${mb.toFixed(0)} MB`;
console.error('| input | loadGi | first frame | what the loader said |');
console.error('|---|---:|---:|---|');
for (const r of rows)
  console.error(`| ${r.label} | ${f(r.ms, r.grew)} | ${r.drawn ? f(r.drawn.ms, r.drawn.grew) : ''} | ${r.said.replace(/^http:\/\/[^ ]*: /, '')} |`);
process.exit(failed ? 1 : 0);
