// gi-format.js: read a vdbgi .gi.gz file (docs/format.md) into its header and
// the two texture byte arrays. No three.js here: the same code runs in a page,
// in a worker and in node (tests/js), and it refuses, with an Error naming the
// problem, every file docs/format.md says a reader must refuse, so no lookup
// can ever leave the textures. A version 5 file (the compact layout, each
// probe stored once) has its textures rebuilt by gi-packed.js; versions 6 to 8 add
// L2 terms, rebuilt there too into snorm textures (gi.sh): six RGBA8 (6 and 7), or
// three RGBA8 and one RG8 (8: the second band in luminance; gi.shBytes 14).
import { rebuildPacked, rebuildPackedSliced, ATLAS_TEXELS_PER_BRICK, termBytes } from './gi-packed.js';
import { GiStreamReader, MAX_BYTES, now, overBudget } from './gi-stream.js';

export { MAX_BYTES } from './gi-stream.js';
export { SH_BYTES, SH_BYTES_LUMA2, termSlot } from './gi-packed.js';

export const ENCODING_RGBM = 0;
export const ENCODING_RGB9E5 = 1;
// The layout numbers of the file's layout field, lib/vdbgi.h and the shaders.
export const LAYOUT_SEED = 1;
export const LAYOUT_COMPACT = 2;
// Version 2 files written before this numbering: 0 for the seed layout, 3 for the compact one.
const OLD_LAYOUT_SEED = 0, OLD_LAYOUT_COMPACT = 3;
const SPARSE_CELLS = 1 << 24; // indirection cells any volume may have, however sparse
const ATLAS_MAX = 1024; // a compact brick's first texel is 4 r + two bits of a: at most 1023

// Sanity bounds (docs/format.md): the RGBM range a file may say (the writer says 8), and
// the lattice's own limits (lib/core/lattice.h) that a box must keep to.
const RANGE_MIN = 1 / 65536, RANGE_MAX = 65504;
const MIN_SPACING = 1e-4, MAX_SPACING = 1e4, MAX_ORIGIN = 1e9, MAX_INDEX = 1 << 26;
const g = (x) => Number(x.toPrecision(6)); // a float32 field for a message, as C's %g

const HEADER_BYTES = 112;
// Versions 6 to 8: the basis field follows, and the term bytes of each stored point.
const HEADER_BYTES_V6 = 116;
export const BASIS_SCALAR = 0;
export const BASIS_SH2 = 2;
// Each L2 term's largest ratio to L0 (docs/format.md, "Version 6"): a term
// texel's snorm value times this, times its polynomial of the normal.
export const SH2_RANGE = Object.freeze([2, 2, 2, 1.875, 1.875, 0.625, 1.875, 0.9375]);

// Texels a brick side, the border before its first probe, and where a coarse
// probe stands inside its block (0.5: block centres, seed; 0: corners, compact).
export function layoutGeometry(layout) {
  return layout === LAYOUT_COMPACT ? { brick: 5, pad: 0, centre: 0 } : { brick: 6, pad: 1, centre: 0.5 };
}

// The box against the lattice it spans (docs/format.md, sanity bounds): a spacing the
// lattice may have, an extent of 4 x indDims spacings on every axis (to 1e-3, plus 2^-20 of
// the largest corner for the corners' rounding), corners its origin and index range reach.
function checkBox(gi) {
  const s = gi.spacing;
  if (!(s >= MIN_SPACING && s <= MAX_SPACING))
    throw new Error(`spacing ${g(s)} m is outside ${MIN_SPACING}..${MAX_SPACING}`);
  for (let k = 0; k < 3; k++) {
    const lo = gi.boxMin[k], hi = gi.boxMax[k];
    const corner = Math.max(Math.abs(lo), Math.abs(hi)), extent = hi - lo;
    const want = 4 * gi.indDims[k] * s;
    if (corner > MAX_ORIGIN + MAX_INDEX * s)
      throw new Error(`boxMin/boxMax reach ${g(corner)} m, past what a lattice of spacing ${g(s)} m can`);
    if (Math.abs(extent - want) > 1e-3 * want + 2 ** -20 * corner)
      throw new Error(`the box is ${g(extent)} m on ${'xyz'[k]}, where indDims (${gi.indDims[k]}) x 4 x spacing (${g(s)} m) is ${g(want)} m`);
  }
}

// Parse an uncompressed .gi. The returned textures are views into `buf`, or
// a packed file's, rebuilt by `rebuild` (gi-packed.js's, or gi-wasm.js's:
// the same bytes).
export function parseGi(buf, rebuild = rebuildPacked) {
  const { gi, headerSize, stored } = parseHeader(buf);
  if (buf.length !== headerSize + stored)
    throw new Error(`file holds ${buf.length} bytes, header says ${headerSize + stored}`);
  return parseBody(gi, buf, headerSize, rebuild);
}

// parseGi, giving the page back every 20 ms or so while a packed file's textures
// are rebuilt (decodeGi and loadGi use it: no long task while a volume loads).
export async function parseGiSliced(buf) {
  const { gi, headerSize, stored } = parseHeader(buf);
  if (buf.length !== headerSize + stored)
    throw new Error(`file holds ${buf.length} bytes, header says ${headerSize + stored}`);
  return parseBody(gi, buf, headerSize, (h, payload) => rebuildPackedSliced(h, payload));
}

// A .gi's header, every field checked (docs/format.md), from its first bytes:
// the header's fields, its size and the bytes that must follow it.
function parseHeader(buf) {
  if (buf.length < HEADER_BYTES) throw new Error('shorter than a .gi header');
  const dv = new DataView(buf.buffer, buf.byteOffset, buf.byteLength);
  if (new TextDecoder().decode(buf.subarray(0, 8)) !== 'vdbgi.gi') throw new Error('not a .gi file');
  const u32 = (o) => dv.getUint32(o, true);
  const f32 = (o) => dv.getFloat32(o, true);
  const vec = (o, get) => [get(o), get(o + 4), get(o + 8)];
  const version = u32(8);
  // Version 1 is seed 000's layout (6^3 texels a brick, the field reserved);
  // version 2 says which at byte 104; version 5 is the compact layout packed.
  // Versions 3 and 4 were older compact forms, no longer read.
  if (version === 3 || version === 4)
    throw new Error(`an older vdbgi's compact layout (.gi version ${version}): convert the .vdb again`);
  if (version < 1 || version > 8) throw new Error(`.gi version ${version}, this reader knows 1..8`);
  const field = u32(104);
  const isCompact = field === LAYOUT_COMPACT || field === OLD_LAYOUT_COMPACT;
  const isSeed = field === LAYOUT_SEED || field === OLD_LAYOUT_SEED;
  if (version === 1 ? field !== 0
    : version >= 5 ? field !== LAYOUT_COMPACT
      : !isSeed && !isCompact)
    throw new Error(`unknown layout ${field} for version ${version}`);
  const layout = isCompact ? LAYOUT_COMPACT : LAYOUT_SEED;
  const headerSize = u32(12);
  // Versions 6 to 8 say their basis: L2, the only one they hold.
  const terms = version >= 6;
  if (terms && buf.length < HEADER_BYTES_V6) throw new Error('shorter than a .gi header');
  if (terms && u32(112) !== BASIS_SH2) throw new Error(`unknown basis ${u32(112)}`);
  const gi = {
    version,
    layout,
    basis: terms ? BASIS_SH2 : BASIS_SCALAR,
    // The L2 terms' bytes a texel on the GPU: 24, 14 (version 8), or 0.
    shBytes: terms ? termBytes(version) : 0,
    encoding: u32(16),
    rgbmRange: f32(20),
    indDims: vec(24, u32),
    atlasDims: vec(36, u32),
    boxMin: vec(48, f32),
    boxMax: vec(60, f32),
    spacing: f32(72),
    maxLevel: u32(76),
    bricks: [u32(80), u32(84), u32(88), u32(92)],
  };
  const { brick } = layoutGeometry(layout);
  const compact = layout === LAYOUT_COMPACT;
  // The seed atlas is whole 6^3 slots, 256 an axis; the compact one's texels are free.
  const [step, lo, hi] = compact ? [1, brick, ATLAS_MAX] : [brick, brick, 256 * brick];
  if (headerSize < (terms ? HEADER_BYTES_V6 : HEADER_BYTES) || headerSize > 65536)
    throw new Error(`bad header size ${headerSize}`);
  if (gi.encoding > ENCODING_RGB9E5) throw new Error(`unknown encoding ${gi.encoding}`);
  if (!(gi.rgbmRange >= RANGE_MIN && gi.rgbmRange <= RANGE_MAX))
    throw new Error(`rgbm_range ${g(gi.rgbmRange)} is outside ${g(RANGE_MIN)}..${RANGE_MAX}`);
  for (let k = 0; k < 3; k++) {
    if (gi.indDims[k] < 1 || gi.indDims[k] > 2048) throw new Error('bad indirection size');
    if (gi.atlasDims[k] < lo || gi.atlasDims[k] > hi || gi.atlasDims[k] % step)
      throw new Error('bad atlas size');
    if (!Number.isFinite(gi.boxMin[k]) || !Number.isFinite(gi.boxMax[k]) || !(gi.boxMax[k] > gi.boxMin[k]))
      throw new Error(`boxMin/boxMax on ${'xyz'[k]}: not finite, or not ordered`);
  }
  if (gi.maxLevel > 3) throw new Error('bad max level');
  const indBytes = u32(96), atlasBytes = u32(100);
  const bytes = (d) => d[0] * d[1] * d[2] * 4;
  if (indBytes !== bytes(gi.indDims) || atlasBytes !== bytes(gi.atlasDims))
    throw new Error('texture sizes disagree with their dimensions');
  if (version < 5 && u32(108) !== 0) throw new Error('reserved header field is not 0');
  const packed = version >= 5;
  gi.storedPoints = packed ? u32(108) : 0;
  // Every brick stores inner points of its own (27 at levels 0 and 1, 8 at 2, 1 at 3):
  // the bricks are bounded by what the file holds.
  const least = 27 * (gi.bricks[0] + gi.bricks[1]) + 8 * gi.bricks[2] + gi.bricks[3];
  if (packed && least > gi.storedPoints)
    throw new Error(`the header's bricks need at least ${least} stored points, it has ${gi.storedPoints}`);
  // Past 16 M cells, at most 4096 for every cell a brick covers (the converter's
  // bound): 10^9 empty cells would unpack 1 GB of level bytes from a 1 MB file.
  const cells = indBytes / 4;
  const covered = gi.bricks[0] + 8 * gi.bricks[1] + 64 * gi.bricks[2] + 512 * gi.bricks[3];
  if (packed && cells > SPARSE_CELLS && cells > 4096 * covered)
    throw new Error(`${cells} cells of the indirection for ${covered} under bricks (more than 4096 a ` +
      `brick's cell, and more than ${SPARSE_CELLS}): too sparse a volume`);
  // The placement table's bound (gi-packed.js), from the header's counts: before the budget.
  const brickCount = gi.bricks.reduce((a, b) => a + b, 0);
  if (packed && atlasBytes / 4 > ATLAS_TEXELS_PER_BRICK * (brickCount + 1))
    throw new Error(`a ${gi.atlasDims.join('x')} atlas for ${brickCount} bricks (at most ${ATLAS_TEXELS_PER_BRICK} texels a brick)`);
  checkBox(gi);
  // Version 5 stores a level byte a cell, 6 bytes a brick (its place) and 4 a
  // stored point, not the textures; versions 6 to 8 the L2 terms' bytes more a point.
  const pointBytes = 4 + gi.shBytes;
  const stored = packed ? indBytes / 4 + 6 * brickCount + pointBytes * gi.storedPoints : indBytes + atlasBytes;
  return { gi, headerSize, stored };
}

// The textures after a checked header: rebuilt (packed, by rebuild(gi, payload,
// file), which may return a promise: then so does this) or checked in place.
function parseBody(gi, buf, headerSize, rebuild) {
  const { brick } = layoutGeometry(gi.layout);
  const compact = gi.layout === LAYOUT_COMPACT;
  const indBytes = 4 * gi.indDims[0] * gi.indDims[1] * gi.indDims[2];
  if (gi.version >= 5) {
    const take = ({ indirection, atlas, sh }) => {
      gi.indirection = indirection;
      gi.atlas = atlas;
      if (sh) gi.sh = sh;
      return gi;
    };
    const rebuilt = rebuild(gi, buf.subarray(headerSize), buf);
    return rebuilt instanceof Promise ? rebuilt.then(take) : take(rebuilt);
  }
  gi.indirection = buf.subarray(headerSize, headerSize + indBytes);
  gi.atlas = buf.subarray(headerSize + indBytes);
  // Every texel points at a whole brick inside the atlas with a level the file
  // allows: a seed slot, or a compact brick's first texel (docs/format.md).
  const ind = gi.indirection, d = gi.atlasDims;
  for (let i = 0; i < indBytes; i += 4) {
    const a = ind[i + 3];
    let inside = true, level;
    if (compact) {
      level = a & 3;
      for (let k = 0; k < 3; k++) inside &&= 4 * ind[i + k] + ((a >> (2 + 2 * k)) & 3) + brick <= d[k];
    } else {
      if (a === 0) continue;
      level = a - 1;
      for (let k = 0; k < 3; k++) inside &&= (ind[i + k] + 1) * brick <= d[k];
    }
    if (!inside || level > gi.maxLevel) throw new Error(`indirection texel ${i / 4} points outside the atlas`);
  }
  return gi;
}

// The bytes a volume's textures take as the reader makes them: the indirection
// as the header sizes it, the atlas, and for L2 six term textures its size (version 8's
// four are packed from those six).
export function textureBytes(gi) {
  const texels = (d) => d[0] * d[1] * d[2];
  return 4 * texels(gi.indDims) + 4 * texels(gi.atlasDims) * (gi.basis === BASIS_SH2 ? 7 : 1);
}

// The stream reader's view of a header: what must follow it and what it unpacks to.
function judgeHeader(first) {
  const { gi, headerSize, stored } = parseHeader(first);
  return { headerSize, stored, textureBytes: textureBytes(gi) };
}

// A reader for one .gi or .gi.gz arriving in chunks (loadGi's fetch): push() them,
// end() for the .gi's bytes, whole (parseGi or parseGiSliced them). Everything gi-stream.js says holds.
export function giReader({ maxBytes = MAX_BYTES, trailerSize = null } = {}) {
  return new GiStreamReader({ header: judgeHeader, headerBytes: HEADER_BYTES_V6, maxBytes, trailerSize });
}

// Check and parse a whole .gi.gz (or .gi) in memory; `timings`, if given, gets
// the milliseconds of each step (gunzip, parse). `maxBytes` bounds what it may
// unpack to (gi-stream.js's MAX_BYTES by default): a volume past it is refused
// from its header, before anything that size is allocated.
export async function decodeGi(fileBytes, timings = {}, { maxBytes = MAX_BYTES } = {}) {
  let t = now();
  // A .gi as it is (a server's Content-Encoding: gzip had the browser unpack it):
  // read in place, with every check.
  if (fileBytes.length >= 8 && new TextDecoder().decode(fileBytes.subarray(0, 8)) === 'vdbgi.gi') {
    const { gi, headerSize, stored } = parseHeader(fileBytes);
    const over = overBudget(headerSize + stored, textureBytes(gi), maxBytes);
    if (over) throw over;
    const parsed = await parseGiSliced(fileBytes);
    timings.gunzip = 0;
    timings.parse = now() - t;
    return parsed;
  }
  // Sizes before allocations (docs/format.md): the trailer says how much the
  // stream unpacks to; deflate expands at most about 1032:1, so more than 1100
  // times the file is a lie, refused before anything is unpacked. The header,
  // from the stream's first bytes, must then agree with the trailer.
  let trailerSize = null;
  if (fileBytes.length >= 2 && fileBytes[0] === 0x1f && fileBytes[1] === 0x8b) {
    if (fileBytes.length < 18) throw new Error('not a whole .gi.gz file (shorter than a gzip stream)');
    const tail = new DataView(fileBytes.buffer, fileBytes.byteOffset, fileBytes.byteLength);
    trailerSize = tail.getUint32(fileBytes.length - 4, true);
    if (trailerSize < HEADER_BYTES || trailerSize > 1100 * fileBytes.length)
      throw new Error(`not a whole .gi.gz file (its gzip trailer promises ${trailerSize} bytes, ` +
        `impossible from ${fileBytes.length})`);
  }
  const reader = giReader({ maxBytes, trailerSize });
  await reader.push(fileBytes);
  const buf = await reader.end();
  timings.gunzip = now() - t;
  t = now();
  const gi = await parseGiSliced(buf);
  timings.parse = now() - t;
  return gi;
}

// The runtime's indirection (docs/format.md "The runtime's indirection"): the
// 3D indirection is mostly empty cells, so the shaders read it as one 2D RGBA8
// texture instead. Column (x, z), c = x + X z, gets two texels: its run (the
// cells from the lowest to the highest that is not 0,0,0,0: ymin, count, 16
// bits each) and where the run starts in the list that follows (24 bits); then
// every run's texels, copied as they are. Texel i is at (i mod width,
// floor(i / width)). Any cell outside its column's run is 0,0,0,0 in the
// indirection too, so the lookup reads the same texel.
// At most 2048 x 2048 texels: WebGL2 guarantees 2D textures that size, and
// every texel index stays an integer float32 holds exactly.
const COLUMNS_ROW_MAX = 2048;

export function indirectionColumns(indirection, indDims) {
  const [X, Y, Z] = indDims;
  const columns = X * Z;
  const runs = new Uint32Array(2 * columns); // ymin, count per column
  let total = 2 * columns;
  for (let z = 0; z < Z; z++)
    for (let x = 0; x < X; x++) {
      let lo = -1, hi = -1;
      for (let y = 0; y < Y; y++) {
        const o = 4 * ((z * Y + y) * X + x);
        if (indirection[o] | indirection[o + 1] | indirection[o + 2] | indirection[o + 3]) {
          if (lo < 0) lo = y;
          hi = y;
        }
      }
      const c = x + X * z;
      if (lo >= 0) {
        runs[2 * c] = lo;
        runs[2 * c + 1] = hi - lo + 1;
        total += hi - lo + 1;
      }
    }
  if (total > COLUMNS_ROW_MAX * COLUMNS_ROW_MAX)
    throw new Error(`the runtime's indirection would need ${total} texels, more than 2048 x 2048`);
  const height = Math.ceil(total / COLUMNS_ROW_MAX), width = Math.ceil(total / height);
  const data = new Uint8Array(4 * width * height);
  let offset = 0;
  for (let c = 0; c < columns; c++) {
    const ymin = runs[2 * c], count = runs[2 * c + 1];
    data.set([ymin & 255, ymin >> 8, count & 255, count >> 8, offset & 255, (offset >> 8) & 255, offset >> 16, 0], 8 * c);
    const x = c % X, z = (c - x) / X;
    for (let k = 0; k < count; k++) {
      const o = 4 * ((z * Y + ymin + k) * X + x);
      data.set(indirection.subarray(o, o + 4), 4 * (2 * columns + offset + k));
    }
    offset += count;
  }
  return { data, width, height };
}
