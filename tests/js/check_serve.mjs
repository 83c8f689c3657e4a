// check_serve.mjs DIR [RAW]: what web/serve.mjs answers, request by request. DIR is
// mounted at /files and holds ok.txt and a symlink, out.txt, to a file outside it.
// RAW (tests/hostile/http) holds requests as bytes, PORT standing for the port:
// each is sent as it is and its status line printed.
import { readdirSync, readFileSync } from 'node:fs';
import { request } from 'node:http';
import { connect } from 'node:net';
import { serve } from '../../web/serve.mjs';

const [dir, raw] = process.argv.slice(2);
const { server, url } = await serve({ mounts: { '/files': dir } });
const { port } = new URL(url);
const ask = (method, path, host = `127.0.0.1:${port}`) => new Promise((done, fail) => {
  const req = request({ host: '127.0.0.1', port, method, path, headers: { Host: host } }, (res) => {
    res.resume();
    res.on('end', () => done(res.statusCode));
  });
  req.on('error', fail);
  req.end();
});
const cases = [
  ['GET', '/web/viewer.html'], ['HEAD', '/web/viewer.html'], ['GET', '/data/world.glb'],
  ['GET', '/tests/web/render.html'], ['GET', '/files/ok.txt'],
  ['GET', '/web/viewer.html', `localhost:${port}`],
  ['GET', '/web/viewer.html', 'evil.example'], ['GET', '/web/viewer.html', `evil.example:${port}`],
  ['POST', '/web/viewer.html'], ['DELETE', '/files/ok.txt'],
  ['GET', '/.git/config'], ['GET', '/web/.hidden'], ['GET', '/files/../README.md'],
  ['GET', '/%2e%2e/README.md'], ['GET', '/README.md'], ['GET', '/lib/vdbgi.h'], ['GET', '/'],
  ['GET', '/files/out.txt'],
];
for (const [method, path, host] of cases)
  console.log(`${method} ${path}${host ? ` (Host: ${host.replace(String(port), 'PORT')})` : ''}: ${await ask(method, path, host)}`);
// The first line the server answers to bytes sent as they are (or how it ended).
const send = (bytes) => new Promise((done) => {
  let got = '';
  const socket = connect(port, '127.0.0.1', () => socket.end(bytes));
  socket.on('data', (d) => { got += d.toString('latin1'); });
  socket.on('error', (e) => done(`socket error ${e.code}`));
  socket.on('close', () => done(got.split('\r\n')[0] || 'closed without an answer'));
});
if (raw)
  for (const name of readdirSync(raw).filter((n) => n.endsWith('.http')).sort()) {
    const bytes = readFileSync(`${raw}/${name}`, 'latin1').replaceAll('PORT', String(port));
    console.log(`${name}: ${await send(Buffer.from(bytes, 'latin1'))}`);
  }
server.close();
