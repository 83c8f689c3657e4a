// check_worker.mjs DIR: loadGi's two decoders (issue 40, item 1). DIR holds
// scalar.gi.gz, l2.gi.gz, l2v8.gi.gz (version 8: four term textures, one RG8),
// cut.gi.gz (l2's first half) and gi-worker.js, the
// worker as esbuild bundles it (web/README.md). Each file is loaded with the
// worker (the default, gi-worker.js beside vdbgi.js), on the page (worker:
// false), with a worker script that does not exist (the page takes over), and
// with the bundled worker: the textures must be the same bytes every way,
// timings.decoder must say which decoded, and the cut file must be refused in
// the same words.
import { withPage } from './browser.mjs';

const [dir] = process.argv.slice(2);
const ways = [['worker', 'auto'], ['page', false], ['page', '/web/no-such-worker.js'],
  ['worker', '/files/gi-worker.js']];
// The missing worker script's 404, which the fallback test asks for.
const allow = [/Failed to load resource: the server responded with a status of 404/];
await withPage({ '/files': dir }, async ({ run }) => {
  for (const file of ['scalar', 'l2', 'l2v8', 'cut']) {
    const got = [];
    for (const [, worker] of ways) got.push(await run({ kind: 'load', gi: `/files/${file}.gi.gz`, worker, digest: true }));
    const said = got.map((r) => (r.ok ? `${r.timings.decoder}, textures ${r.digest}` : `refused: ${r.error}`));
    const want = ways.map(([decoder]) => decoder);
    const decodersOk = got.every((r, i) => !r.ok || r.timings.decoder === want[i]);
    const same = said.every((s) => s.replace(/^(worker|page), /, '') === said[0].replace(/^(worker|page), /, ''));
    const ok = decodersOk && same;
    console.log(`${ok ? 'ok' : 'FAIL'}: ${file}: ${got[0].ok ? `${got[0].digest}, the same from` : `"${got[0].error.replace(/^.*\.gi\.gz: /, '')}" from`}` +
      ` ${got.map((r) => (r.ok ? r.timings.decoder : ways[got.indexOf(r)][0])).join(', ')}`);
    if (!ok) {
      for (let i = 0; i < ways.length; i++) console.log(`  worker ${ways[i][1]}: ${said[i]}`);
      process.exitCode = 1;
    }
  }
}, { allow });
