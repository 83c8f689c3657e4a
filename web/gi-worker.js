// gi-worker.js: loadGi's decoding in a module worker, which vdbgi.js starts
// from beside itself (or from the script its `worker` option names). The page
// sends a .gi.gz's chunks as they arrive, each transferred; here they are
// checked and unpacked as gi-stream.js says (giReader), then parsed, rebuilt
// (by the C reader built to WebAssembly, gi-wasm.js, compiled while the file
// arrives; by gi-packed.js where it cannot run, or where the worker's URL
// ends in ?reader=js) and made ready for the GPU (readTextures), and the
// textures' buffers go back transferred, not copied. Every refusal is the
// page reader's, word for word. One load a worker; the page ends it.
import { giReader, parseGi } from './gi-format.js';
import { readTextures } from './gi-gpu.js';
import { wasmRebuild } from './gi-wasm.js';

const wasm = new URL(import.meta.url).searchParams.get('reader') === 'js' ? Promise.resolve(null) : wasmRebuild();
let reader = null;
const reply = (id, body, transfer = []) => self.postMessage({ id, ...body }, transfer);

self.onmessage = async ({ data }) => {
  const { id, op } = data;
  try {
    if (op === 'start') {
      reader = giReader({ maxBytes: data.maxBytes });
    } else if (op === 'push') {
      await reader.push(data.chunk);
    } else if (op === 'end') {
      const viaWasm = await wasm;
      let used = 'js'; // which rebuilt (an unpacked file: only the JavaScript checks ran)
      const rebuild = viaWasm && ((...args) => {
        const out = viaWasm(...args);
        used = out.reader ?? 'js';
        return out;
      });
      const read = await readTextures(reader, (bytes) => parseGi(bytes, rebuild || undefined));
      read.reader = used;
      const { header } = read;
      const buffers = new Set([header.columns.data, header.atlas, ...(header.sh ?? [])].map((a) => a.buffer));
      return reply(id, read, [...buffers]);
    }
    return reply(id, {});
  } catch (e) {
    return reply(id, { error: e.message });
  }
};
self.postMessage({ ready: true });
