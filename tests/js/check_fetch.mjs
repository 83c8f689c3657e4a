// check_fetch.mjs FILE.gi.gz: loadGi over HTTP as an unlucky server serves it, in
// node (its fetch and streams are the browser's): a whole file loads, with progress
// events that end at its size; a 404, a server that never answers, a body that
// stops half way, a connection reset mid-body and a refused port each reject within
// the timeout asked (0.5 s; 30 s by default, LOAD_TIMEOUT_MS) with a message that
// begins with the URL and says what happened; a caller's abort rejects with the
// caller's own reason.
import { readFileSync } from 'node:fs';
import { createServer } from 'node:http';
import { loadGi, LOAD_TIMEOUT_MS } from '../../web/vdbgi.js';

const file = readFileSync(process.argv[2]);
const half = file.length >> 1;
const sockets = new Set();
const server = createServer((req, res) => {
  const send = (n) => {
    res.writeHead(200, { 'Content-Type': 'application/octet-stream', 'Content-Length': file.length });
    res.write(file.subarray(0, n));
  };
  if (req.url === '/ok') {
    res.writeHead(200, { 'Content-Type': 'application/octet-stream', 'Content-Length': file.length });
    // In four writes 30 ms apart, so that progress has steps to report.
    const q = Math.ceil(file.length / 4);
    const part = (i) => (i < 4 ? (res.write(file.subarray(i * q, (i + 1) * q)), setTimeout(() => part(i + 1), 30))
      : res.end());
    part(0);
  } else if (req.url === '/missing') {
    res.writeHead(404).end();
  } else if (req.url === '/silent') {
    // accepts, never answers
  } else if (req.url === '/stall') {
    send(half);
  } else if (req.url === '/reset') {
    send(half);
    setTimeout(() => req.socket.destroy(), 50);
  }
});
server.on('connection', (s) => { sockets.add(s); s.on('close', () => sockets.delete(s)); });
await new Promise((done) => server.listen(0, '127.0.0.1', done));
const base = `http://127.0.0.1:${server.address().port}`;
// A port nothing listens on: the server's, closed at the end, is taken; ask the OS for another.
const closed = await new Promise((done) => {
  const s = createServer().listen(0, '127.0.0.1', () => { const p = s.address().port; s.close(() => done(p)); });
});

let failed = 0;
const check = (ok, what) => {
  console.log(`${ok ? 'ok' : 'FAILED'}: ${what}`);
  if (!ok) failed++;
};
check(LOAD_TIMEOUT_MS === 30000, `the default timeout is ${LOAD_TIMEOUT_MS / 1000} s`);
const steps = [];
const v = await loadGi(`${base}/ok`, { timeout: 500, onProgress: (p) => steps.push(p) });
check(v.fileBytes === file.length && steps.length >= 2 && steps.at(-1).loaded === file.length &&
  steps.every((p) => p.total === file.length),
`a whole file loads, with ${steps.length >= 2 ? 'progress' : 'no progress'} up to its ${file.length} bytes`);
v.dispose();
const cases = [['/missing', `${base}/missing`], ['/silent', `${base}/silent`], ['/stall', `${base}/stall`],
  ['/reset', `${base}/reset`], ['a refused port', `http://127.0.0.1:${closed}/x.gi.gz`]];
for (const [name, url] of cases) {
  const t = performance.now();
  let message = null;
  try {
    (await loadGi(url, { timeout: 500 })).dispose();
  } catch (e) {
    message = e.message;
  }
  const ms = performance.now() - t;
  const said = message?.startsWith(`${url}: `) ? message.slice(url.length + 2) : message;
  check(message !== null && message.startsWith(`${url}: `) && ms < 2000,
    `${name}: rejects${ms < 2000 ? ' within 2 s' : ` after ${(ms / 1000).toFixed(1)} s`}, naming the URL: ` +
    said.replace(`after ${half} bytes`, 'after half the bytes'));
}
const ac = new AbortController();
const pending = loadGi(`${base}/silent`, { signal: ac.signal });
setTimeout(() => ac.abort(new Error('the caller gave up')), 100);
const reason = await pending.then(() => null, (e) => e.message);
check(reason === 'the caller gave up', `an abort rejects with the caller's own reason: ${reason}`);
for (const s of sockets) s.destroy();
server.close();
process.exit(failed ? 1 : 0);
