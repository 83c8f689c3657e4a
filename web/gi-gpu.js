// gi-gpu.js: a parsed .gi's arrays as the GPU takes them, on whichever thread
// decodes (vdbgi.js on the page, gi-worker.js in a worker): the indirection as
// columns (docs/format.md, "The runtime's indirection"), and the L2 terms as
// unorm bytes. No three.js: the textures themselves are made on the page.
import { indirectionColumns } from './gi-format.js';
import { now } from './gi-stream.js';

// gi (parseGi's result) with `columns` ({ data, width, height }) in place of
// `indirection`, and its signed term bytes q, as unsigned ones, turned into
// q + 128 in place: q ^ 0x80,
// four bytes at a time (WebGL2 and WebGPU both filter RGBA8 unorm; the shader
// reads (255 t - 128) / 127). A mapping copy took 1.4 s for the bundled world.
export function prepareTextures(gi) {
  gi.columns = indirectionColumns(gi.indirection, gi.indDims);
  delete gi.indirection;
  if (gi.sh) gi.sh = gi.sh.map((q) => {
    const u = new Uint8Array(q.buffer, q.byteOffset, q.byteLength);
    if (q.byteOffset % 4 === 0 && q.byteLength % 4 === 0) {
      const words = new Uint32Array(q.buffer, q.byteOffset, q.byteLength / 4);
      for (let i = 0; i < words.length; i++) words[i] ^= 0x80808080;
    } else {
      for (let i = 0; i < u.length; i++) u[i] ^= 0x80;
    }
    return u;
  });
  return gi;
}

// A giReader's .gi once every chunk is in: parsed (parseGi in the worker,
// parseGiSliced on the page, which gives the page back) and prepared, with the
// milliseconds the inflating and the parse took: { header, inflateMs, parseMs }.
export async function readTextures(reader, parse) {
  const bytes = await reader.end();
  const t = now();
  const header = prepareTextures(await parse(bytes));
  return { header, inflateMs: reader.inflateMs, parseMs: now() - t };
}
