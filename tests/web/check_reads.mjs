// check_reads.mjs L2.gi.gz SCALAR.gi.gz: the WebGPU runtime's lookup reads each texture
// once a fragment. A standard material lit per fragment holds, beyond the plain
// material's texture reads, the three reads of the indirection's columns (run, offset,
// entry), the atlas's and the six term textures', and the occluders' loop's two (a
// shape's ends): 12, for either basis (one node graph for both, so that setVolume()
// never rebuilds a material). TSL's
// select() is an if/else whose branches each rebuild what they use, and the lookup
// written with it held 76 (issue 46, item 3).
import { copyFileSync, mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { withPage } from './browser.mjs';

const dir = mkdtempSync(join(tmpdir(), 'vdbgi-reads-'));
const files = process.argv.slice(2);
files.forEach((f, i) => copyFileSync(f, join(dir, `v${i}.gi.gz`)));
let failed = 0;
try {
  await withPage({ '/files': dir }, async ({ fresh }) => {
    for (const [i, want, what] of [[0, 12, 'L2 terms'], [1, 12, 'scalar']]) {
      const { page, run } = await fresh();
      const r = await run({ kind: 'reads', gi: `/files/v${i}.gi.gz` });
      await page.close();
      // The material's program is the one with the most reads (a render may make others, the clear's).
      const added = Math.max(...r.lit) - Math.max(...r.plain);
      const ok = added === want;
      if (!ok) failed++;
      console.log(`${ok ? 'ok' : 'FAILED'}: WebGPU, ${what}: the volume per fragment adds ${added} texture reads to a standard ` +
        `material's fragment shader (${want} expected)`);
    }
  });
} finally {
  rmSync(dir, { recursive: true, force: true });
}
process.exit(failed ? 1 : 0);
