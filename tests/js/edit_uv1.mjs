// edit_uv1.mjs IN.glb OUT.glb outside|overlap|onetexel: spoil a .glb's second UV set
// (TEXCOORD_1 of its first primitive) in place: one corner at u = 2, the second
// triangle laid on the first, or every corner squeezed into one texel (of any atlas up
// to 8192). For gi-lightmap's test of when a scene's own UV set is kept.
import { readFileSync, writeFileSync } from 'node:fs';

const [input, output, how] = process.argv.slice(2);
const b = readFileSync(input);
const jsonLength = b.readUInt32LE(12);
const json = JSON.parse(b.subarray(20, 20 + jsonLength));
const bin = 20 + jsonLength + 8; // the BIN chunk's data
const prim = json.meshes[0].primitives[0];
const acc = json.accessors[prim.attributes.TEXCOORD_1];
const view = json.bufferViews[acc.bufferView];
const index = json.accessors[prim.indices], indexView = json.bufferViews[index.bufferView];
const vertex = (k) => b.readUInt32LE(bin + indexView.byteOffset + 4 * k); // unindexed: k
const at = (v, c) => bin + view.byteOffset + 8 * v + 4 * c;
if (how === 'outside') {
  b.writeFloatLE(2.0, at(vertex(0), 0));
} else if (how === 'onetexel') {
  for (let v = 0; v < acc.count; v++)
    for (let c = 0; c < 2; c++) b.writeFloatLE(0.50001 + 0.00001 * b.readFloatLE(at(v, c)), at(v, c));
} else {
  for (let k = 0; k < 3; k++)
    for (let c = 0; c < 2; c++) b.writeFloatLE(b.readFloatLE(at(vertex(k), c)), at(vertex(3 + k), c));
}
writeFileSync(output, b);
