// check_loader.mjs FILE.gi.gz INSPECT.txt: the JavaScript loader agrees with
// the C sampler. INSPECT.txt holds gi-inspect's "at X,Y,Z -> R G B" lines.
import { readFile } from 'node:fs/promises';
import { loadGi, sampleGi } from './gi_loader.mjs';
import { indirectionColumns } from '../../web/gi-format.js';

// NORMAL (x,y,z, optional): every point read facing it, normalised as gi-inspect does.
const [file, inspect, normalArg] = process.argv.slice(2);
let normal = null;
if (normalArg) {
  const n = normalArg.split(',').map((v) => Math.fround(Number(v)));
  const len = Math.sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  normal = n.map((v) => Math.fround(v / len));
}
const gi = await loadGi(await readFile(file));
console.log(`header: ${gi.indDims.join('x')} cells, ${gi.atlasDims.join('x')} texels, ` +
            `encoding ${gi.encoding === 1 ? 'rgb9e5' : 'rgbm'}, layout ${gi.layout === 2 ? 'compact' : 'seed'}, ` +
            `bricks ${gi.bricks.join('/')}${gi.sh ? ', L2 terms' : ''}`);
// The runtime's indirection as JavaScript builds it: gi-inspect's "runtime" line says C's.
const columns = indirectionColumns(gi.indirection, gi.indDims);
console.log(`columns: ${columns.width}x${columns.height} texels, ${columns.data.length} bytes`);
let count = 0, worst = 0, bad = 0, nonzero = 0;
for (const line of (await readFile(inspect, 'utf8')).split('\n')) {
  const m = line.match(/^at\s+(\S+),(\S+),(\S+) -> (\S+) (\S+) (\S+)$/);
  if (!m) continue;
  const pos = m.slice(1, 4).map(Number), want = m.slice(4, 7).map(Number);
  const got = sampleGi(gi, pos, null, normal);
  for (let k = 0; k < 3; k++) {
    // gi-inspect prints 6 significant digits; float32 rounding differs in the last bits.
    const diff = Math.abs(got[k] - want[k]);
    worst = Math.max(worst, diff);
    if (diff > 1e-5 + 1e-5 * Math.abs(want[k])) bad++;
  }
  nonzero += want.some((v) => v > 0);
  count++;
}
console.log(bad === 0 && count > 0 ? `${count} points agree (${nonzero} lit)` :
            `${bad} channels of ${count} points disagree (worst ${worst})`);
process.exit(bad === 0 && count > 0 ? 0 : 1);
