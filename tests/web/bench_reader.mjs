// bench_reader.mjs FILE.gi.gz...: the worker's rebuild of a packed .gi by the C reader
// built to WebAssembly (web/gi-wasm.js) against the JavaScript one (web/gi-packed.js),
// in node (V8, as Chromium): parseGi and prepareTextures of the inflated file, as the
// worker runs them once its bytes are whole. A worker reads one file and ends, so what
// a load pays is a first run: each is timed in a fresh process (five of each,
// alternating, so that the machine's other load falls on both), the WebAssembly one
// with its compile; then the best of five warm runs.
import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { gunzipSync } from 'node:zlib';
import { fileURLToPath } from 'node:url';
import { parseGi } from '../../web/gi-format.js';
import { prepareTextures } from '../../web/gi-gpu.js';
import { wasmRebuild } from '../../web/gi-wasm.js';

const now = () => performance.now();
const args = process.argv.slice(2);

if (args[0] === '--one') {
  // One process: [first run, compile, best warm run], in ms.
  const [, reader, file] = args;
  const bytes = new Uint8Array(gunzipSync(readFileSync(file)));
  let t = now();
  const rebuild = reader === 'wasm' ? await wasmRebuild() : undefined;
  const compile = now() - t;
  if (reader === 'wasm' && !rebuild) throw new Error('no WebAssembly reader (make builds web/gi-reader-wasm.js)');
  const once = () => {
    const buf = bytes.slice(); // the worker's reader hands parseGi fresh bytes each load
    const t0 = now();
    prepareTextures(parseGi(buf, rebuild));
    return now() - t0;
  };
  const first = once();
  let best = Infinity;
  for (let i = 0; i < 5; i++) best = Math.min(best, once());
  console.log(JSON.stringify([first, compile, best]));
} else {
  const self = fileURLToPath(import.meta.url);
  const median = (a) => a.slice().sort((x, y) => x - y)[a.length >> 1];
  const ms = (v) => `${v.toFixed(0)} ms`;
  console.log('| file | inflated | JS, first run | WASM, first run (compile) | WASM / JS | JS warm | WASM warm |');
  console.log('|---|---:|---:|---:|---:|---:|---:|');
  for (const arg of args) {
    const [name, file] = arg.includes('=') ? arg.split('=') : [arg, arg];
    const runs = { js: [], wasm: [] };
    for (let i = 0; i < 5; i++)
      for (const reader of ['js', 'wasm'])
        runs[reader].push(JSON.parse(execFileSync(process.execPath, [self, '--one', reader, file], { encoding: 'utf8' })));
    const first = (r) => median(runs[r].map((x) => x[0]));
    const best = (r) => Math.min(...runs[r].map((x) => x[2]));
    const inflated = gunzipSync(readFileSync(file)).length;
    console.log(`| ${name} | ${(inflated / 1e6).toFixed(2)} MB | ${ms(first('js'))} | ${ms(first('wasm'))} ` +
      `(${ms(median(runs.wasm.map((x) => x[1])))}) | ${(first('wasm') / first('js')).toFixed(2)} | ${ms(best('js'))} | ${ms(best('wasm'))} |`);
  }
}
