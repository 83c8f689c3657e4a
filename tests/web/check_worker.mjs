// check_worker.mjs DIR: loadGi's two decoders and two readers (issue 40, item 1).
// DIR holds scalar.gi.gz, l2.gi.gz, l2v8.gi.gz (version 8: four term textures,
// one RG8), cut.gi.gz (l2's first half), bad.gi.gz (l2 with a level byte no
// converter writes) and gi-worker.js, the worker as esbuild bundles it
// (web/README.md). Each file is loaded with the worker (the default,
// gi-worker.js beside vdbgi.js: the C reader as WebAssembly), on the page
// (worker: false: the JavaScript reader), with a worker script that does not
// exist (the page takes over), with the bundled worker (the WebAssembly inside
// it) and with the worker told ?reader=js: the textures must be the same bytes
// every way, timings.decoder and timings.reader must say which decoded and
// rebuilt, and the damaged files must be refused in the same words.
import { withPage } from './browser.mjs';

const [dir] = process.argv.slice(2);
const ways = [['worker wasm', 'auto'], ['page js', false], ['page js', '/web/no-such-worker.js'],
  ['worker wasm', '/files/gi-worker.js'], ['worker js', '/web/gi-worker.js?reader=js']];
// The missing worker script's 404, which the fallback test asks for.
const allow = [/Failed to load resource: the server responded with a status of 404/];
await withPage({ '/files': dir }, async ({ run }) => {
  for (const file of ['scalar', 'l2', 'l2v8', 'cut', 'bad']) {
    const got = [];
    for (const [, worker] of ways) got.push(await run({ kind: 'load', gi: `/files/${file}.gi.gz`, worker, digest: true }));
    const how = (r) => `${r.timings.decoder} ${r.timings.reader}`;
    const said = got.map((r) => (r.ok ? `${how(r)}, textures ${r.digest}` : `refused: ${r.error}`));
    const decodersOk = got.every((r, i) => !r.ok || how(r) === ways[i][0]);
    const same = said.every((s) => s.replace(/^\w+ \w+, /, '') === said[0].replace(/^\w+ \w+, /, ''));
    const ok = decodersOk && same;
    console.log(`${ok ? 'ok' : 'FAIL'}: ${file}: ${got[0].ok ? `${got[0].digest}, the same from` : `"${got[0].error.replace(/^.*\.gi\.gz: /, '')}" from`}` +
      ` ${got.map((r, i) => (r.ok ? how(r) : ways[i][0].split(' ')[0])).join(', ')}`);
    if (!ok) {
      for (let i = 0; i < ways.length; i++) console.log(`  worker ${ways[i][1]}: ${said[i]}`);
      process.exitCode = 1;
    }
  }
}, { allow });
