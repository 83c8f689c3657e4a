// check_textures.mjs FILE.gi.gz TEXTURES.gi: the JavaScript reader rebuilds,
// byte for byte, the runtime textures the C reader rebuilds from a packed
// (version 5) file; TEXTURES.gi is what `gi-inspect FILE --textures` wrote.
import { readFile } from 'node:fs/promises';
import { decodeGi, parseGi } from '../../web/gi-format.js';

const [file, textures] = process.argv.slice(2);
const timings = {};
const gi = await decodeGi(new Uint8Array(await readFile(file)), timings);
const want = parseGi(new Uint8Array(await readFile(textures)));
const differing = (a, b) => {
  if (a.length !== b.length) return `${a.length} bytes against ${b.length}`;
  let n = 0;
  for (let i = 0; i < a.length; i++) n += a[i] !== b[i];
  return n;
};
const ind = differing(gi.indirection, want.indirection), atlas = differing(gi.atlas, want.atlas);
const ok = gi.version === 5 && ind === 0 && atlas === 0;
console.log(`version ${gi.version}, ${gi.storedPoints} stored points -> ` +
            `${gi.indirection.length} + ${gi.atlas.length} texture bytes: ` +
            (ok ? 'identical to the C reader\'s' : `indirection ${ind}, atlas ${atlas} bytes differ`));
if (process.env.VERBOSE) console.log(`gunzip ${timings.gunzip.toFixed(0)} ms, parse and rebuild ${timings.parse.toFixed(0)} ms`);
process.exit(ok ? 0 : 1);
