// Types for vdbgi-react.js (the package's 'vdbgi/react'): React Three Fiber bindings.
import type { ReactElement, ReactNode } from 'react';
import type { ThreeElements } from '@react-three/fiber';
import type { DebugViewName, DebugViewValue, GiRuntimeBase, GiVolume, KnobSet } from './vdbgi.js';

export interface GiLightProps extends Omit<ThreeElements['group'], 'children' | 'ref'> {
  /** The .gi.gz to load (vdb-to-gi's output); a new url loads and shows the new volume. */
  url: string;
  /** The knob set the materials under it take ('world' by default), when each is first lit. */
  set?: KnobSet;
  /** Per fragment or per vertex, for materials not yet lit; 'auto' (the default) chooses per mesh,
   * per fragment where its triangles are longer than the volume's probe spacing. */
  perFragment?: boolean | 'auto';
  /** The volume's light on (the default) or off. */
  enabled?: boolean;
  /** A debug view of the volume ('off' by default). */
  debug?: DebugViewValue | DebugViewName;
  /** The volume, once loaded and shown. */
  onLoad?: (volume: GiVolume) => void;
  /** A failed load; without it the error is thrown to the nearest error boundary. */
  onError?: (error: Error) => void;
  onProgress?: (progress: { loaded: number; total: number | null }) => void;
  /** As loadGi's options. */
  maxBytes?: number;
  timeout?: number;
  children?: ReactNode;
}

/**
 * A group whose meshes take the volume's light, those that mount later too; the
 * runtime (WebGL2, or WebGPU for a WebGPURenderer) and its volume are disposed with it.
 */
export function GiLight(props: GiLightProps): ReactElement;

/** The runtime of the nearest <GiLight> above, or null outside one (or while it starts). */
export function useGi(): GiRuntimeBase | null;
