// craft_packed.mjs GOOD.gi.gz DIR: from a good packed (version 5) file, write
// into DIR one file for each inconsistency docs/format.md says a reader must
// refuse, each gzip'd whole (so only the reader's checks can catch it), and
// print their names. Needs a file with a level-1 brick and two level-0 bricks
// side by side first.
import { readFileSync, writeFileSync } from 'node:fs';
import { gunzipSync, gzipSync } from 'node:zlib';

const [good, dir] = process.argv.slice(2);
const raw = new Uint8Array(gunzipSync(readFileSync(good)));
const dv = new DataView(raw.buffer);
const u32 = (o) => dv.getUint32(o, true);
if (u32(8) !== 5) throw new Error(`${good} is version ${u32(8)}, not a packed file`);
const d = [u32(24), u32(28), u32(32)], cells = d[0] * d[1] * d[2], H = u32(12), maxLevel = u32(76);
const at = (x, y, z) => H + (z * d[1] + y) * d[0] + x;
// The first level-1 brick whose 2^3 block lies inside the indirection, and the first level-0 cell.
let coarse = null, fine = null;
for (let z = 0; z + 1 < d[2]; z++)
  for (let y = 0; y + 1 < d[1]; y++)
    for (let x = 0; x + 1 < d[0]; x++) {
      const b = raw[at(x, y, z)];
      if (!coarse && b === 2 && x % 2 === 0 && y % 2 === 0 && z % 2 === 0) coarse = [x, y, z];
      if (!fine && b === 1 && x % 2 === 1) fine = [x, y, z];
    }
if (!coarse || !fine) throw new Error('no level-1 brick or no odd level-0 cell to damage');
// The placement table: u16 x of every brick, then y, then z.
const count = u32(80) + u32(84) + u32(88) + u32(92), table = H + cells;
const setOrigin = (v, b, o) => o.forEach((t, k) => v.setUint16(table + 2 * (k * count + b), t, true));
const origin = (b) => [0, 1, 2].map((k) => dv.getUint16(table + 2 * (k * count + b), true));

function write(name, edit, extra = 0) {
  const b = new Uint8Array(raw.length + extra);
  b.set(raw);
  edit(b, new DataView(b.buffer));
  writeFileSync(`${dir}/${name}.gi.gz`, gzipSync(b));
  console.log(name);
}
write('level-above-max', (b) => { b[at(...fine)] = maxLevel + 2; });
write('block-with-a-cell-of-another-level', (b) => { b[at(coarse[0] + 1, coarse[1], coarse[2])] = 1; });
write('coarse-cell-outside-its-block', (b) => { b[at(...fine)] = 2; });
write('one-brick-fewer', (b) => { b[at(...fine)] = 0; });
write('header-counts-another-brick', (b, v) => { v.setUint32(80, u32(80) + 1, true); }, 6);
write('more-bricks-than-stored-points-allow', (b, v) => { v.setUint32(84, u32(108), true); });
write('one-stored-point-more', (b, v) => { v.setUint32(108, u32(108) + 1, true); }, 4);
write('stored-points-without-their-bytes', (b, v) => { v.setUint32(108, u32(108) + 1, true); });
// 50 MB of zeros after the payload (a small file that unpacks large): the header,
// read first, says less than the gzip trailer, so neither reader unpacks the rest.
write('fifty-megabytes-of-zeros-after-it', () => {}, 50 << 20);
write('packed-in-the-seed-layout', (b, v) => { v.setUint32(104, 1, true); });
write('textures-with-a-point-count', (b, v) => { v.setUint32(8, 2, true); });
write('atlas-too-large-for-its-bricks', (b, v) => {
  v.setUint32(36, 1000, true), v.setUint32(40, 1000, true), v.setUint32(44, 1000, true);
  v.setUint32(100, 4 * 1000 * 1000 * 1000, true);
});
write('brick-outside-the-atlas', (b, v) => { setOrigin(v, 0, [u32(36) - 4, origin(0)[1], origin(0)[2]]); });
write('brick-between-layers', (b, v) => { setOrigin(v, 0, [origin(0)[0], origin(0)[1] + 1, origin(0)[2]]); });
write('brick-over-the-block-of-zeros', (b, v) => { setOrigin(v, 0, [0, 0, 0]); });
write('brick-over-another-bricks-points', (b, v) => { setOrigin(v, 1, origin(0)); });
write('older-compact-version-4', (b, v) => { v.setUint32(8, 4, true); });
write('older-compact-version-3', (b, v) => { v.setUint32(8, 3, true); v.setUint32(104, 1, true); });
write('newer-version-9', (b, v) => { v.setUint32(8, 9, true); });
write('version-7-without-l2-terms', (b, v) => { v.setUint32(8, 7, true); });
write('unknown-layout-4', (b, v) => { v.setUint32(104, 4, true); });
write('packed-with-the-old-compact-number-3', (b, v) => { v.setUint32(104, 3, true); });
// 33.5 M cells of the indirection (512 x 512 x 128), empty but for the good file's few
// bricks: 33 MB of level bytes that gzip to 33 kB, then a 134 MB texture.
{
  const wide = [512, 512, 128], many = wide[0] * wide[1] * wide[2];
  const b = new Uint8Array(raw.length - cells + many);
  b.set(raw.subarray(0, H));
  b.set(raw.subarray(H + cells), H + many);
  const v = new DataView(b.buffer);
  wide.forEach((n, k) => v.setUint32(24 + 4 * k, n, true));
  v.setUint32(96, 4 * many, true);
  writeFileSync(`${dir}/thirty-million-empty-cells.gi.gz`, gzipSync(b));
  console.log('thirty-million-empty-cells');
}
