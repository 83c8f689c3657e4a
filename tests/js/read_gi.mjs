// read_gi.mjs FILE: what the JavaScript reader (web/gi-format.js) makes of a
// .gi or .gi.gz: "read B0/B1/B2/B3" (its bricks a level), or "refused: " and
// the reader's message.
import { readFileSync } from 'node:fs';
import { loadGi } from './gi_loader.mjs';

try {
  const gi = await loadGi(readFileSync(process.argv[2]));
  console.log('read', gi.bricks.join('/'));
} catch (e) {
  console.log('refused:', e.message);
}
