// check_ktx2.mjs FILE.ktx2 RX RY RZ: an independent reader (the npm package ktx-parse)
// accepts the file and finds Bevy's (Rx, 2Ry, 3Rz) texture in it, one level, one face.
import { readFile } from 'node:fs/promises';
import { read } from 'ktx-parse';

const [file, rx, ry, rz] = process.argv.slice(2);
const c = read(new Uint8Array(await readFile(file)));
const formats = { 97: 'R16G16B16A16_SFLOAT', 123: 'E5B9G9R9_UFLOAT_PACK32' };
const texel = c.vkFormat === 97 ? 8 : 4;
const dims = [c.pixelWidth, c.pixelHeight, c.pixelDepth];
const want = [Number(rx), 2 * Number(ry), 3 * Number(rz)];
const dfd = c.dataFormatDescriptor[0];
console.log(`${formats[c.vkFormat] ?? c.vkFormat}: ${dims.join('x')} texels, ` +
            `${c.levels.length} level, ${c.faceCount} face, ${dfd.samples.length} samples, ` +
            `writer '${c.keyValue.KTXwriter.replace(/[0-9.]+$/, 'N')}'`);
const ok = dims.every((d, k) => d === want[k]) &&
           c.levels[0].levelData.byteLength === dims[0] * dims[1] * dims[2] * texel &&
           dfd.colorModel === 1 && dfd.transferFunction === 1;
console.log(ok ? 'dimensions and level size agree' : `expected ${want.join('x')}`);
process.exit(ok ? 0 : 1);
