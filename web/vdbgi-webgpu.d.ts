// Types for vdbgi-webgpu.js (the package's 'vdbgi/webgpu'): the runtime for WebGPURenderer, in TSL.
import type { Material } from 'three';
import type { ApplyOptions, GiRuntimeBase } from './vdbgi.js';

export {
  loadGi, GiVolume, DebugView, LEVEL_COLOURS, DEFAULT_KNOBS, ENCODING_RGBM, ENCODING_RGB9E5, LAYOUT_SEED,
  LAYOUT_COMPACT, MAX_OCCLUDERS,
} from './vdbgi.js';
export type { ApplyOptions, GiInfo, GiTimings, Knobs, KnobSet, LoadOptions, OccluderOptions } from './vdbgi.js';

/** The WebGPU runtime: apply() builds the lookup in TSL. */
export class GiRuntime extends GiRuntimeBase {
  /**
   * Add GI to a material: a MeshStandardMaterial, MeshPhysicalMaterial or MeshLambertMaterial
   * becomes its node counterpart; returns the material to use.
   */
  apply(material: Material, options?: ApplyOptions): Material;
  /** The irradiance node at a world position for a world normal (TSL nodes; the fragment's by default). */
  irradianceNode(pos?: unknown, normal?: unknown): unknown;
}

/** A MeshStandardMaterial or MeshLambertMaterial as its node counterpart, its maps carried over. */
export function toNodeMaterial(material: Material): Material;
