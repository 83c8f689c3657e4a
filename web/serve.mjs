// serve.mjs: a static file server on 127.0.0.1 for the viewer and the browser
// tests (no dependencies). node web/serve.mjs [--port N] [--mount /url=DIR ...]
// [--query Q] serves the repository at / and each DIR at its /url, and prints
// the viewer's URL (with ?Q).
// Files go out as they are: a .gi.gz is never sent with Content-Encoding, so
// the page's DecompressionStream sees the file's own bytes.
// It serves GET and HEAD only, to a Host header naming the loopback address it
// listens on (so a page elsewhere cannot reach it through DNS rebinding), never
// a dotfile or anything under a dot folder (.git), from the repository only
// what the viewer and the tests load (web/, data/, out/, tests/web/), and
// nothing a symlink leads to outside its root.
import { createServer } from 'node:http';
import { createReadStream, realpathSync, statSync } from 'node:fs';
import { resolve, join, extname, sep } from 'node:path';
import { fileURLToPath } from 'node:url';

const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.mjs': 'text/javascript; charset=utf-8',
  '.json': 'application/json',
  '.css': 'text/css',
  '.png': 'image/png',
  '.glb': 'model/gltf-binary',
  '.gltf': 'model/gltf+json',
};

// What the repository root serves: the viewer, its scenes and outputs, the tests' pages.
const REPOSITORY_PARTS = ['web/', 'data/', 'out/', 'tests/web/'];

export function serve({ port = 0, mounts = {} } = {}) {
  const root = resolve(fileURLToPath(new URL('..', import.meta.url)));
  // Longest prefix first, so /files/x wins over /.
  const table = Object.entries({ '/': root, ...mounts })
    .map(([url, dir]) => [url.endsWith('/') ? url : `${url}/`, resolve(dir)])
    .sort((a, b) => b[0].length - a[0].length);
  const refuse = (res, code, why) => res.writeHead(code, { 'Content-Type': 'text/plain' }).end(`${why}\n`);
  let hosts = [];
  const server = createServer((req, res) => {
    if (req.method !== 'GET' && req.method !== 'HEAD') {
      res.setHeader('Allow', 'GET, HEAD');
      refuse(res, 405, `${req.method}: only GET and HEAD`);
      return;
    }
    if (!hosts.includes((req.headers.host ?? '').toLowerCase())) {
      refuse(res, 403, 'this server answers only to its loopback address');
      return;
    }
    let path;
    try {
      path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    } catch {
      refuse(res, 400, 'bad path');
      return;
    }
    const [prefix, dir] = table.find(([p]) => path.startsWith(p) || `${path}/` === p) ?? [];
    const rest = dir === undefined ? '' : path.slice(prefix.length);
    const file = dir && join(dir, rest);
    const hidden = rest.split('/').some((part) => part.startsWith('.'));
    const outside = !file || (file !== dir && !file.startsWith(dir + sep)) ||
      (dir === root && !REPOSITORY_PARTS.some((part) => `${rest}/`.startsWith(part)));
    if (hidden || outside) {
      refuse(res, 403, `${path}: not served`);
      return;
    }
    let size;
    try {
      // A symlink may lead anywhere: what it names must still lie inside the root.
      const real = realpathSync(file), realDir = realpathSync(dir);
      if (real !== realDir && !real.startsWith(realDir + sep)) throw new Error('outside');
      const st = statSync(real);
      if (!st.isFile()) throw new Error('not a file');
      size = st.size;
    } catch {
      refuse(res, 404, `${path}: not found`);
      return;
    }
    res.writeHead(200, {
      'Content-Type': TYPES[extname(file)] ?? 'application/octet-stream',
      'Content-Length': size,
      'Cache-Control': 'no-store',
    });
    if (req.method === 'HEAD') res.end();
    else createReadStream(file).on('error', () => res.destroy()).pipe(res);
  });
  return new Promise((ok, fail) => {
    server.once('error', fail);
    server.listen(port, '127.0.0.1', () => {
      const p = server.address().port;
      hosts = [`127.0.0.1:${p}`, `localhost:${p}`];
      ok({ server, url: `http://127.0.0.1:${p}` });
    });
  });
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) {
  const args = process.argv.slice(2);
  let port = 8080, query = '';
  const mounts = {};
  for (let i = 0; i < args.length; i++) {
    if (args[i] === '--port') port = Number(args[++i]);
    else if (args[i] === '--mount') {
      const [url, dir] = args[++i].split('=');
      mounts[url] = dir;
    } else if (args[i] === '--query') {
      query = `?${args[++i]}`;
    } else if (args[i] === '--help' || args[i] === '-h') {
      console.log('usage: node web/serve.mjs [--port N] [--mount /url=DIR ...] [--query SCENE_AND_GI]');
      process.exit(0);
    } else {
      console.error(`serve.mjs: unknown argument '${args[i]}' (try --help)`);
      process.exit(2);
    }
  }
  const { url } = await serve({ port, mounts });
  console.log(`vdbgi viewer: ${url}/web/viewer.html${query}   (Ctrl-C stops)`);
}
