// Types for gi-probe-grid.js (the package's 'vdbgi/probe-grid'): a volume through three's own light probe grid.
import type { Box3, Light, Vector3 } from 'three';
import type { GiVolume } from './vdbgi.js';

/** The largest side of the grid's atlas (nx, ny, or 7 (nz + 2) slices) makeProbeGrid builds. */
export const MAX_GRID_SIDE: number;

/** What makeProbeGrid needs of three's LightProbeGridWebGL (WebGL2) or LightProbeGrid (WebGPU), three r187 or later. */
export interface ProbeGridLike extends Light {
  width: number;
  height: number;
  depth: number;
  readonly resolution: Vector3;
  readonly boundingBox: Box3;
  getProbePosition(ix: number, iy: number, iz: number, target: Vector3): Vector3;
  updateBoundingBox(): void;
  dispose(): void;
}

export interface BoxLike { min: ArrayLike<number> | Vector3; max: ArrayLike<number> | Vector3 }

/** The box of the volume's cells that hold bricks, in metres; null when it holds none. */
export function occupiedBox(volume: GiVolume): { min: number[]; max: number[] } | null;

/** Fill a placed and sized grid from the volume (a half-float atlas, 56 bytes a probe); returns the grid. */
export function fillProbeGrid<G extends ProbeGridLike>(grid: G, volume: GiVolume): G;

/**
 * A grid of class Grid over box (occupiedBox() by default, grown to the volume's lattice) at spacing
 * (the volume's by default), filled from the volume. Add it to the scene; materials need no change.
 */
export function makeProbeGrid<G extends ProbeGridLike>(
  volume: GiVolume,
  Grid: new (width: number, height: number, depth: number, nx: number, ny: number, nz: number) => G,
  options?: { box?: Box3 | BoxLike | null; spacing?: number },
): G;
