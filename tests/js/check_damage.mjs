// check_damage.mjs FILE.gi.gz: the JavaScript loader refuses damaged files with an
// Error, as the C reader does: every prefix of the gzip'd file, a flip of every byte
// of it, and (gzipped again, so that the header and not the CRC is what catches it)
// a flip of every byte of the .gi's first 512 bytes and of 500 more. A file that
// still loads must point every cell inside the atlas and sample to finite colours.
// Prints the counts; exits 1 on any deviation.
import { readFile } from 'node:fs/promises';
import { gunzipSync, gzipSync } from 'node:zlib';
import { loadGi, sampleGi } from './gi_loader.mjs';

const good = new Uint8Array(await readFile(process.argv[2]));
const raw = new Uint8Array(gunzipSync(good));
let loaded = 0, refused = 0, bad = 0;

async function attempt(bytes, what) {
  let gi;
  try {
    gi = await loadGi(bytes);
  } catch (e) {
    if (e instanceof Error) refused++;
    else if (bad++ < 5) console.log(`${what}: threw a non-Error ${e}`);
    return;
  }
  loaded++;
  // What docs/format.md promises a reader that loaded: every brick pointer inside the atlas.
  const compact = gi.layout === 2, b = compact ? 5 : 6;
  for (let t = 0; t < gi.indirection.length; t += 4) {
    const [x, y, z, a] = gi.indirection.subarray(t, t + 4);
    // Seed: slot (x, y, z), level a - 1 (a = 0: empty). Compact: first texel 4 (x, y, z) + a's bits.
    const first = compact ? [x, y, z].map((v, k) => 4 * v + ((a >> (2 + 2 * k)) & 3)) : [x * b, y * b, z * b];
    const level = compact ? a & 3 : a - 1;
    if ((compact || a) && (first.some((v, k) => v + b > gi.atlasDims[k]) || level > gi.maxLevel)) {
      if (bad++ < 5) console.log(`${what}: loaded with a brick pointer outside the atlas`);
      return;
    }
  }
  for (let i = 0; i < 64; i++) {
    const pos = [0, 1, 2].map((k) => gi.boxMin[k] + ((i * (k + 3)) % 17) / 16 * (gi.boxMax[k] - gi.boxMin[k]));
    if (!sampleGi(gi, pos).every(Number.isFinite)) {
      if (bad++ < 5) console.log(`${what}: loaded, but samples to a non-finite colour`);
      return;
    }
  }
}

for (let n = 0; n < good.length; n++) await attempt(good.subarray(0, n), `prefix ${n}`);
const cuts = refused;
for (let i = 0; i < good.length; i++) {
  const b = good.slice();
  b[i] ^= 0x5a;
  await attempt(b, `flip ${i}`);
}
let x = 12345;
for (let k = 0; k < 512 + 500; k++) {
  const i = k < 512 ? k : (x = (x * 1103515245 + 12345) % 2147483648) % raw.length;
  const b = raw.slice();
  b[i] ^= 1 + (k % 255);
  await attempt(new Uint8Array(gzipSync(b)), `.gi flip ${i}`);
}
const junk = new Uint8Array(good.length + 1);
junk.set(good);
const before = refused;
await attempt(junk, 'a byte after the gzip stream');
if (refused === before) bad++, console.log('a byte after the gzip stream: loaded');
console.log(`${cuts === good.length ? 'every prefix refused' : `${good.length - cuts} prefixes loaded`}; ` +
            `${bad === 0 ? 'no damaged file loaded wrong' : `${bad} damaged files loaded wrong`}`);
process.exit(cuts === good.length && bad === 0 ? 0 : 1);
