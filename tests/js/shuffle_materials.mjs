// shuffle_materials.mjs IN.glb OUT.glb: put an unused emitting material, of strength
// 50, first in a .glb's materials (every primitive's index moves up one). Assimp
// numbers materials as meshes first use them and drops unused ones, so the file's
// order is not assimp's: gi-lightmap's test that each emitter keeps its own
// KHR_materials_emissive_strength.
import { readFileSync, writeFileSync } from 'node:fs';

const [input, output] = process.argv.slice(2);
const b = readFileSync(input);
const jsonLength = b.readUInt32LE(12);
const json = JSON.parse(b.subarray(20, 20 + jsonLength));
const bin = b.subarray(20 + jsonLength); // the BIN chunk, header included
json.materials.unshift({ name: 'unused', emissiveFactor: [0.2, 0.2, 0.2],
  extensions: { KHR_materials_emissive_strength: { emissiveStrength: 50 } } });
for (const mesh of json.meshes) for (const p of mesh.primitives) p.material += 1;
let text = JSON.stringify(json);
while (text.length % 4) text += ' ';
const head = Buffer.alloc(20);
head.writeUInt32LE(0x46546c67, 0); // glTF
head.writeUInt32LE(2, 4);
head.writeUInt32LE(20 + text.length + bin.length, 8);
head.writeUInt32LE(text.length, 12);
head.writeUInt32LE(0x4e4f534a, 16); // JSON
writeFileSync(output, Buffer.concat([head, Buffer.from(text), bin]));
