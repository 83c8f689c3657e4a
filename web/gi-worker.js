// gi-worker.js: loadGi's decoding in a module worker, which vdbgi.js starts
// from beside itself (or from the script its `worker` option names). The page
// sends a .gi.gz's chunks as they arrive, each transferred; here they are
// checked and unpacked as gi-stream.js says (giReader), then parsed, rebuilt
// and made ready for the GPU (readTextures), and the textures' buffers go
// back transferred, not copied. Every refusal is the page reader's, word for
// word. One load a worker; the page ends it.
import { giReader, parseGi } from './gi-format.js';
import { readTextures } from './gi-gpu.js';

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
      const read = await readTextures(reader, parseGi);
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
