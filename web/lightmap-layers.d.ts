// Types for lightmap-layers.js (the package's 'vdbgi/lightmap-layers'): gi-lightmap --layers at run time.
import type { Texture } from 'three';

export interface LightmapLayer { name: string; map: Texture; scale: number }

/** Composites gi-lightmap's per-light layers into one lightmap per atlas, drawn again when a weight changes. */
export class LayerCompositor {
  /** A WebGLRenderer; or a WebGPURenderer with gpu = { webgpu, tsl }, the modules 'three/webgpu' and 'three/tsl'. */
  constructor(renderer: unknown, gpu?: { webgpu: unknown; tsl: unknown } | null);
  /** Layer name -> weight (1 by default). */
  readonly weights: Map<string, number>;
  /** The composite of one atlas's layers, made once per key. */
  target(key: string, layers: LightmapLayer[]): Texture;
  /** The layers' names, in the order first met. */
  names(): string[];
  /** A layer's weight; every atlas holding it is drawn again. */
  setWeight(name: string, weight: number): void;
  dispose(): void;
  private glslSum;
  private nodeSum;
  private draw;
}
