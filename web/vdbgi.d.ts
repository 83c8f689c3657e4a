// Types for vdbgi.js (the package's 'vdbgi'): the loader and the WebGL2 runtime.
import type { Data3DTexture, DataTexture, Material, Object3D, Texture, Vector3, WebGLRenderer } from 'three';
import type { GiInfo, GiTimings } from './gi-format.js';

export { ENCODING_RGBM, ENCODING_RGB9E5, LAYOUT_SEED, LAYOUT_COMPACT, MAX_BYTES } from './gi-format.js';
export type { GiInfo, GiTimings, Vec3 } from './gi-format.js';

/** Debug views: what a material with GI shows instead of its lit colour. */
export const DebugView: Readonly<{ OFF: 0; PROBE: 1; LEVEL: 2; BRICKS: 3; POSITION: 4; NORMAL: 5 }>;
export type DebugViewName = 'off' | 'probe' | 'level' | 'bricks' | 'position' | 'normal';
export type DebugViewValue = (typeof DebugView)[keyof typeof DebugView];
/** DebugView.LEVEL's colours, linear RGB: no brick, then levels 0..3. */
export const LEVEL_COLOURS: readonly (readonly [number, number, number])[];
/** Most occluder shapes a runtime takes, all objects together. */
export const MAX_OCCLUDERS: number;
/** (Distance / radius)^2 past which an occluder is skipped. */
export const OCCLUDER_REACH2: number;
/** The oldest three.js REVISION each back end draws with. */
export const THREE_OLDEST: Readonly<{ webgl: number; webgpu: number }>;
/** Throws, in one line, if a three REVISION ('187') is older than the back end needs; each GiRuntime calls it. */
export function checkThree(backend: 'webgl' | 'webgpu', revision: string): void;
/** How long a response may send nothing before loadGi gives up on it, by default (ms). */
export const LOAD_TIMEOUT_MS: number;
/** The knobs of seed 000: intensity, self, bleed. */
export interface Knobs { intensity: number; self: number; bleed: number }
export const DEFAULT_KNOBS: Readonly<Knobs>;
export type KnobSet = 'world' | 'character';

export interface LoadOptions {
  /** With a renderer (WebGL2), the textures are uploaded before loadGi returns. */
  renderer?: WebGLRenderer | { initTexture(texture: unknown): void } | null;
  /** Aborts as for fetch(): loadGi rejects with the signal's own reason. */
  signal?: AbortSignal;
  /** Milliseconds a response may send nothing (LOAD_TIMEOUT_MS; 0 for none). */
  timeout?: number;
  /** Each chunk of a URL's body: bytes so far and Content-Length (or null). */
  onProgress?: (progress: { loaded: number; total: number | null }) => void;
  /** The most a volume may unpack to (MAX_BYTES, 32 MiB, by default). */
  maxBytes?: number;
  /**
   * Where a URL's file is unpacked and rebuilt: 'auto' (the default: a module
   * worker, gi-worker.js beside vdbgi.js, unless vdbgi.js is inside a bundle),
   * false (the page, given back every 20 ms), or gi-worker.js's URL as the app
   * serves it. A worker that cannot start leaves the work to the page.
   */
  worker?: 'auto' | false | string | URL;
}

/** One world's textures and figures; made by loadGi(). */
export class GiVolume {
  private constructor();
  /** The file's header fields. */
  readonly info: Readonly<GiInfo>;
  /** The file's size as read (gzip'd, or as the server sent it). */
  readonly fileBytes: number;
  /** The indirection as columns: a 2D RGBA8 texture. */
  readonly columns: DataTexture;
  /** The atlas: RGBA8 (RGBM) or RGB9E5. */
  readonly atlas: Data3DTexture;
  /** L2 terms: six textures (versions 6 and 7) or four (version 8, info.shBytes 14), or null for a scalar volume. */
  readonly sh: Data3DTexture[] | null;
  readonly boxMin: Vector3;
  readonly boxMax: Vector3;
  /** What the GPU holds: the atlas (and terms) and the columns. */
  readonly vramBytes: number;
  readonly bricks: [number, number, number, number];
  timings: GiTimings;
  dispose(): void;
}

/**
 * Fetch (a URL) or take (an ArrayBuffer or typed array) a .gi.gz, check it and make
 * its textures. Rejects, making nothing, on a bad file; for a URL every message
 * begins with it.
 */
export function loadGi(source: string | URL | ArrayBuffer | ArrayBufferView, options?: LoadOptions): Promise<GiVolume>;

export interface OccluderOptions {
  /** Capsules in the object's own space (ends as Vector3 or [x, y, z]); default: its bounding sphere. */
  capsules?: { a: Vector3 | [number, number, number]; b?: Vector3 | [number, number, number]; radius: number }[] | null;
}

export interface ApplyOptions {
  /** Which knobs the material reads: 'world' (default) or 'character'. */
  set?: KnobSet;
  /** Look the volume up per fragment instead of per vertex. */
  perFragment?: boolean;
  /** false: no light from the volume, only the occluders' shadow (a lightmapped surface). */
  volume?: boolean;
}

/** What both back ends' runtimes share. */
export class GiRuntimeBase {
  constructor();
  /** The volume shown, or null. */
  readonly volume: GiVolume | null;
  /** The uniforms every material with GI reads. */
  readonly uniforms: Record<string, { value: unknown }>;
  enabled: boolean;
  /** A debug view (0: off); showing one, or going back to off, recompiles each material apply() gave. */
  get debug(): DebugViewValue;
  set debug(view: DebugViewValue | DebugViewName | Uppercase<DebugViewName>);
  /** Show a volume (null: none); the one shown before is disposed one call later. */
  setVolume(volume: GiVolume | null): void;
  setKnobs(set: KnobSet, knobs: Partial<Knobs>): void;
  getKnobs(set: KnobSet): Knobs;
  /**
   * Light every mesh under root with the volume: with perFragment 'auto' (the default),
   * per fragment where a mesh's triangles' mean edge is longer than the probe spacing,
   * per vertex elsewhere; true or false, every mesh one way. The volume must be set first.
   */
  light(root: Object3D, options?: { set?: KnobSet; perFragment?: boolean | 'auto' }):
    { perVertex: number; perFragment: number };
  /**
   * The split in one call, for a GLTFLoader result of a gi-lightmap .glb: meshes with a
   * lightmap take it and only the occluders' shadow, the others the volume as light()
   * chooses;
   * meshes under `moving` take the volume per fragment (character knobs), and each of
   * those objects becomes an occluder unless `occlude` is false.
   */
  lightScene(gltf: { scene: Object3D; parser: { getDependency(type: 'texture', index: number): Promise<Texture> } },
    options?: { moving?: Object3D[]; occlude?: boolean }): Promise<{ lightmapped: number; volume: number; moving: number }>;
  addOccluder<T extends Object3D>(object: T, options?: OccluderOptions): T;
  removeOccluder(object: Object3D): void;
  /** Once a frame, after the occluders moved. */
  updateOccluders(): void;
  dispose(): void;
}

/** The WebGL2 runtime: apply() patches three's own shaders. */
export class GiRuntime extends GiRuntimeBase {
  /** Add GI to a MeshStandardMaterial, MeshPhysicalMaterial or MeshLambertMaterial, in place. */
  apply<M extends Material>(material: M, options?: ApplyOptions): M;
}
