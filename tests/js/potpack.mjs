// potpack.mjs BOXES.json: seed 004's packer (npm potpack, the library it uses) on
// the chart boxes gi-bench lightmap wrote, against how vdbgi packed the same
// boxes (stb_rect_pack's skyline into fixed atlases). Prints a Markdown table:
// for each chart set and packer, the atlas area it took (the rectangle around
// what it placed, or potpack's bin) and the share of it triangles cover.
import { readFileSync } from 'node:fs';
import potpack from 'potpack';

const { scene, sets } = JSON.parse(readFileSync(process.argv[2], 'utf8'));
console.log(`| ${scene}: charts, packer | charts | atlas area, texels | covered by triangles |`);
console.log('|---|---:|---:|---:|');
for (const set of sets) {
  const boxes = set.boxes.map(([w, h]) => ({ w, h }));
  const { w, h } = potpack(boxes);
  const pct = (area) => `${(100 * set.samples / area).toFixed(1)} %`;
  console.log(`| ${set.name} | ${set.charts} | ${set.used_area} | ${pct(set.used_area)} |`);
  console.log(`| ${set.name.replace(/stb_rect_pack$/, 'potpack')} | ${set.charts} | ${w * h} | ${pct(w * h)} |`);
}
