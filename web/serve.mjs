// serve.mjs: a static file server on 127.0.0.1 for the viewer and the browser
// tests (no dependencies). node web/serve.mjs [--port N] [--mount /url=DIR ...]
// [--query Q] serves the repository at / and each DIR at its /url, and prints
// the viewer's URL (with ?Q).
// Files go out as they are: a .gi.gz is never sent with Content-Encoding, so
// the page's DecompressionStream sees the file's own bytes.
import { createServer } from 'node:http';
import { createReadStream, statSync } from 'node:fs';
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

export function serve({ port = 0, mounts = {} } = {}) {
  const root = resolve(fileURLToPath(new URL('..', import.meta.url)));
  // Longest prefix first, so /files/x wins over /.
  const table = Object.entries({ '/': root, ...mounts })
    .map(([url, dir]) => [url.endsWith('/') ? url : `${url}/`, resolve(dir)])
    .sort((a, b) => b[0].length - a[0].length);
  const server = createServer((req, res) => {
    let path;
    try {
      path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
    } catch {
      res.writeHead(400).end();
      return;
    }
    const [prefix, dir] = table.find(([p]) => path.startsWith(p) || `${path}/` === p) ?? [];
    const file = dir && join(dir, path.slice(prefix.length));
    if (!file || (file !== dir && !file.startsWith(dir + sep))) {
      res.writeHead(403).end();
      return;
    }
    let size;
    try {
      const st = statSync(file);
      if (!st.isFile()) throw new Error('not a file');
      size = st.size;
    } catch {
      res.writeHead(404, { 'Content-Type': 'text/plain' }).end(`${path}: not found\n`);
      return;
    }
    res.writeHead(200, {
      'Content-Type': TYPES[extname(file)] ?? 'application/octet-stream',
      'Content-Length': size,
      'Cache-Control': 'no-store',
    });
    createReadStream(file).on('error', () => res.destroy()).pipe(res);
  });
  return new Promise((ok, fail) => {
    server.once('error', fail);
    server.listen(port, '127.0.0.1', () => ok({ server, url: `http://127.0.0.1:${server.address().port}` }));
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
