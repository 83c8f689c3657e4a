// check_gltf.mjs FILE.glb: the Khronos glTF validator (npm gltf-validator) finds no
// error in a gi-lightmap output, and every primitive carries the second UV set and
// a material with its map (lightmap extras, or the core occlusionTexture) on it.
import { readFileSync } from 'node:fs';
import validator from 'gltf-validator';

const file = process.argv[2];
const bytes = new Uint8Array(readFileSync(file));
const report = await validator.validateBytes(bytes, { maxIssues: 100 });
const { numErrors, numWarnings } = report.issues;
for (const m of report.issues.messages.filter((m) => m.severity === 0).slice(0, 5))
  console.log(`  error ${m.code}: ${m.message} (${m.pointer ?? ''})`);
// The JSON chunk: its length at byte 12, the JSON from byte 20.
const json = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + new DataView(bytes.buffer).getUint32(12, true))));
let missing = 0;
for (const mesh of json.meshes)
  for (const p of mesh.primitives) {
    const mat = json.materials[p.material];
    const map = mat.occlusionTexture ?? mat.extras?.vdbgi_lightmap;
    if (p.attributes.TEXCOORD_1 === undefined || !map || map.texCoord !== 1) missing++;
  }
const kind = json.materials.some((m) => m.occlusionTexture) ? 'occlusionTexture' : 'lightmap extras';
console.log(`${numErrors} errors, ${numWarnings > 0 ? 'some' : 'no'} warnings; ` +
            `${missing === 0 ? 'every' : `${missing} without a`} primitive with TEXCOORD_1 and its map (${kind})`);
process.exit(numErrors === 0 && missing === 0 ? 0 : 1);
