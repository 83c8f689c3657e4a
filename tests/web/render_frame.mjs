// render_frame.mjs TASK.json OUT: a player's view in headless Chromium (WebGL2),
// tests/web/render.html's frame task; the files TASK.json names (scene,
// lightmap, gi) are served from their folders. Writes OUT.pfm (linear
// radiance), OUT.pos.pfm (world positions) and OUT.mask.pfm (1 where a
// surface was drawn), rows from the bottom as PFM stores them, and OUT.json
// (the volume's load and a probe grid's making, in ms).
import { readFileSync, writeFileSync } from 'node:fs';
import { basename, dirname, resolve } from 'node:path';
import { withPage } from './browser.mjs';

const [taskPath, out] = process.argv.slice(2);
const task = JSON.parse(readFileSync(taskPath, 'utf8'));
const mounts = {};
const serveAs = (file, i) => {
  if (!file) return null;
  mounts[`/f${i}`] = dirname(resolve(file));
  return `/f${i}/${basename(file)}`;
};
task.scene = serveAs(task.scene, 0);
task.lightmap = serveAs(task.lightmap, 1);
task.gi = serveAs(task.gi, 2);
const pfm = (path, rgba, w, h, pick) => {
  const head = Buffer.from(`PF\n${w} ${h}\n-1.0\n`, 'ascii');
  const body = new Float32Array(w * h * 3);
  for (let i = 0; i < w * h; i++) for (let k = 0; k < 3; k++) body[3 * i + k] = pick(rgba, i, k);
  writeFileSync(path, Buffer.concat([head, Buffer.from(body.buffer)]));
};
const r = await withPage(mounts, ({ run }) => run({ kind: 'frame', ...task }));
const { width: w, height: h } = task.camera;
pfm(`${out}.pfm`, r.radiance, w, h, (a, i, k) => a[4 * i + k]);
pfm(`${out}.pos.pfm`, r.pos, w, h, (a, i, k) => a[4 * i + k]);
pfm(`${out}.mask.pfm`, r.pos, w, h, (a, i) => a[4 * i + 3]);
// The milliseconds the volume took to load, and a probe grid's (task.grid) to make, and its probes.
writeFileSync(`${out}.json`, JSON.stringify({ loadMs: r.loadMs, gridMs: r.gridMs, gridProbes: r.gridProbes }));
