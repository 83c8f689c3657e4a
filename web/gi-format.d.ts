// Types for gi-format.js (the package's 'vdbgi/format'): the .gi.gz reader, no three.js.

export const ENCODING_RGBM: 0;
export const ENCODING_RGB9E5: 1;
export const LAYOUT_SEED: 1;
export const LAYOUT_COMPACT: 2;
export const BASIS_SCALAR: 0;
export const BASIS_SH2: 2;
/** Each L2 term's largest ratio to L0 (docs/format.md, "Version 6"). */
export const SH2_RANGE: readonly number[];
/** What a volume may unpack to unless the caller says otherwise: 32 MiB. */
export const MAX_BYTES: number;

export type Vec3 = [number, number, number];

/** A .gi's header fields (docs/format.md), as every reader gives them. */
export interface GiInfo {
  version: number;
  layout: typeof LAYOUT_SEED | typeof LAYOUT_COMPACT;
  /** BASIS_SH2 when the file holds L2 terms (versions 6 to 8), else BASIS_SCALAR. */
  basis: typeof BASIS_SCALAR | typeof BASIS_SH2;
  /**
   * The L2 terms' bytes a texel on the GPU: SH_BYTES (24: versions 6 and 7, every term in
   * colour), SH_BYTES_LUMA2 (14: version 8, terms 4-8 one ratio for the three channels),
   * or 0 (no terms).
   */
  shBytes: number;
  encoding: typeof ENCODING_RGBM | typeof ENCODING_RGB9E5;
  rgbmRange: number;
  indDims: Vec3;
  atlasDims: Vec3;
  boxMin: Vec3;
  boxMax: Vec3;
  spacing: number;
  maxLevel: number;
  /** Bricks at levels 0..3. */
  bricks: [number, number, number, number];
  /** Probe values the file stores (versions 5 to 8; 0 before). */
  storedPoints: number;
}

/** A parsed .gi: its header fields and its textures' bytes. */
export interface GiData extends GiInfo {
  /** The 3D indirection, RGBA8, indDims texels. */
  indirection: Uint8Array;
  /** The atlas, RGBA8 (RGBM) or RGB9E5 words, atlasDims texels. */
  atlas: Uint8Array;
  /**
   * L2 terms, snorm textures the atlas's size: six RGBA8 (versions 6 and 7), or three
   * RGBA8 and one RG8 (version 8). termSlot says where each term byte is.
   */
  sh?: Int8Array[];
}

/** Term bytes a texel: versions 6 and 7. */
export const SH_BYTES: 24;
/** Term bytes a texel: version 8. */
export const SH_BYTES_LUMA2: 14;
/**
 * Where term byte j (3 term + channel, 0..23) of a texel lies in GiData.sh, for a
 * volume of shBytes term bytes a texel: [texture, component, components a texel].
 */
export function termSlot(shBytes: number, j: number): [number, number, number];

/** Milliseconds of each step, filled in by decodeGi. */
export interface GiTimings {
  fetch?: number;
  gunzip?: number;
  parse?: number;
  build?: number;
  upload?: number | null;
  firstFrame?: number;
  /** Which decoded a loadGi: its worker or the page. */
  decoder?: 'worker' | 'page';
  /** Which rebuilt its textures: the C reader as WebAssembly (the worker's) or the JavaScript one. */
  reader?: 'wasm' | 'js';
}

/** Texels a brick side, the border before its first probe, where a coarse probe stands. */
export function layoutGeometry(layout: number): { brick: number; pad: number; centre: number };
/** Parse an uncompressed .gi; the textures are views into `buf`. Throws on any damage. */
export function parseGi(buf: Uint8Array): GiData;
/** parseGi, giving the page back every 20 ms or so while a packed file's textures are rebuilt. */
export function parseGiSliced(buf: Uint8Array): Promise<GiData>;
/** The bytes a volume's textures take as the reader makes them. */
export function textureBytes(gi: GiInfo): number;
/** Check and parse a whole .gi.gz (or .gi) in memory. Throws an Error naming the problem. */
export function decodeGi(fileBytes: Uint8Array, timings?: GiTimings, options?: { maxBytes?: number }): Promise<GiData>;

/** A .gi or .gi.gz read as its bytes arrive, held to its header and a budget (gi-stream.js). */
export interface GiStreamReader {
  push(chunk: Uint8Array): Promise<void>;
  end(): Promise<Uint8Array>;
  cancel(reason?: unknown): void;
  readonly inflateMs: number;
}
export function giReader(options?: { maxBytes?: number; trailerSize?: number | null }): GiStreamReader;

/** The runtime's indirection as columns (docs/format.md): one RGBA8 2D texture. */
export function indirectionColumns(indirection: Uint8Array, indDims: Vec3): { data: Uint8Array; width: number; height: number };
