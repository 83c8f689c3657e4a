// check_wasm.mjs FILE.gi.gz...: the C reader built to WebAssembly (web/gi-wasm.js,
// which the decoding worker runs) rebuilds every texture of each packed file,
// byte for byte, as the JavaScript reader does (gi-packed.js, which cli/convert_js_loader
// holds to the C reader natively), and where the JavaScript one refuses a file,
// so does it.
import { readFile } from 'node:fs/promises';
import { giReader, parseGi } from '../../web/gi-format.js';
import { wasmRebuild } from '../../web/gi-wasm.js';

const rebuild = await wasmRebuild();
if (!rebuild) {
  console.log('no WebAssembly reader: make builds web/gi-reader-wasm.js');
  process.exit(1);
}
// The reader alone: a refusal here is the C reader's (the worker's would be retried in JavaScript).
const strict = (gi, payload, file) => rebuild(gi, payload, file, { strict: true });
let failed = false;
for (const file of process.argv.slice(2)) {
  // Inflated as the worker does (gi-stream.js): a file it refuses reaches neither reader.
  const reader = giReader();
  let bytes;
  try {
    await reader.push(new Uint8Array(await readFile(file)));
    bytes = await reader.end();
  } catch (e) {
    console.log(`WebAssembly refused: ${e.message} (the stream reader's, before either)`);
    continue;
  }
  const attempt = (fn) => {
    try {
      return parseGi(bytes.slice(), fn);
    } catch (e) {
      return e;
    }
  };
  const js = attempt(undefined), wasm = attempt(strict);
  let said;
  if (js instanceof Error || wasm instanceof Error) {
    // The header's refusals are gi-format.js's before either rebuild; the rest the C reader's own.
    const ok = js instanceof Error && wasm instanceof Error;
    said = ok ? `refused: ${wasm.message}` : `JavaScript: ${js.message ?? 'read'}; WebAssembly: ${wasm.message ?? 'read'}`;
    failed ||= !ok;
  } else if (js.version < 5) {
    said = `version ${js.version}: textures as they are, checked in place (no rebuild)`;
  } else {
    const textures = [['indirection', js.indirection, wasm.indirection], ['atlas', js.atlas, wasm.atlas],
      ...(js.sh ?? []).map((t, i) => [`terms ${i}`, t, wasm.sh?.[i]])];
    if ((wasm.sh?.length ?? 0) !== (js.sh?.length ?? 0)) textures.push(['term textures', [js.sh?.length], [wasm.sh?.length]]);
    const differ = textures.filter(([, a, b]) => !b || a.length !== b.length || a.some((v, i) => v !== b[i]));
    const total = textures.reduce((n, [, a]) => n + a.length, 0);
    said = differ.length ? `${differ.map(([name]) => name).join(', ')} differ` :
      `version ${js.version}: ${textures.length} textures, ${total} bytes, the JavaScript reader's`;
    failed ||= differ.length > 0;
  }
  console.log(`WebAssembly ${said}`);
}
process.exit(failed ? 1 : 0);
