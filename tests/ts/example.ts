// A typed example of every entry point, checked by tsc --strict (tests/cli/web_types.sh):
// it is compiled, never run. A wrong name, a missing option or a changed signature fails it.
import * as THREE from 'three';
import { GiRuntime, loadGi, DebugView, MAX_BYTES, LOAD_TIMEOUT_MS, type GiVolume, type Knobs } from 'vdbgi';
import { GiRuntime as GpuRuntime, toNodeMaterial } from 'vdbgi/webgpu';
import { decodeGi, parseGi, giReader, textureBytes, LAYOUT_COMPACT, BASIS_SH2, type GiData } from 'vdbgi/format';
import { LayerCompositor } from 'vdbgi/lightmap-layers';
import { createElement, type ReactElement } from 'react';
import { GiLight, useGi } from 'vdbgi/react';
import { makeProbeGrid, occupiedBox, MAX_GRID_SIDE } from 'vdbgi/probe-grid';
import { LightProbeGridWebGL } from 'three/addons/lighting/LightProbeGridWebGL.js';

export async function lightWorld(renderer: THREE.WebGLRenderer, scene: THREE.Scene, hero: THREE.Mesh): Promise<GiVolume> {
  const gi = new GiRuntime();
  const volume = await loadGi('world.gi.gz', {
    renderer,
    timeout: LOAD_TIMEOUT_MS,
    maxBytes: 2 * MAX_BYTES,
    onProgress: ({ loaded, total }) => console.log(loaded, total ?? 'unknown'),
    signal: AbortSignal.timeout(60000),
  });
  gi.setVolume(volume);
  scene.traverse((o) => {
    if (o instanceof THREE.Mesh && o.material instanceof THREE.MeshStandardMaterial) o.material = gi.apply(o.material);
  });
  const standard: THREE.MeshStandardMaterial = gi.apply(new THREE.MeshStandardMaterial(), { set: 'character', perFragment: true });
  hero.material = standard;
  gi.addOccluder(hero, { capsules: [{ a: [0, 0.4, 0], b: new THREE.Vector3(0, 1.4, 0), radius: 0.3 }] });
  gi.updateOccluders();
  gi.debug = 'level';
  gi.debug = DebugView.BRICKS;
  const knobs: Knobs = gi.getKnobs('world');
  gi.setKnobs('character', { intensity: knobs.intensity * 1.5 });
  const [x0, , z0] = volume.info.boxMin;
  console.log(x0 + z0, volume.info.layout === LAYOUT_COMPACT, volume.info.basis === BASIS_SH2, volume.vramBytes,
    volume.timings.fetch, volume.sh?.length ?? 0);
  return volume;
}

export async function lightWithWebGpu(mesh: THREE.Mesh, bytes: ArrayBuffer): Promise<void> {
  const gi = new GpuRuntime();
  gi.setVolume(await loadGi(bytes));
  mesh.material = gi.apply(toNodeMaterial(new THREE.MeshLambertMaterial()), { volume: false });
  gi.enabled = false;
  gi.dispose();
}

export async function readHeader(file: Uint8Array): Promise<number> {
  const gi: GiData = await decodeGi(file, {}, { maxBytes: 1 << 20 });
  const reader = giReader();
  await reader.push(file);
  const again = parseGi(await reader.end());
  return textureBytes(gi) + again.indirection.length + (again.sh?.[0].length ?? 0);
}

export function layers(renderer: THREE.WebGLRenderer, map: THREE.Texture): THREE.Texture {
  const compositor = new LayerCompositor(renderer);
  const lit = compositor.target('atlas0', [{ name: 'sun', map, scale: 2 }]);
  compositor.setWeight('sun', 0.5);
  console.log(compositor.names().join());
  return lit;
}

export function LitWorld({ world }: { world: THREE.Object3D }): ReactElement {
  return createElement(GiLight, {
    url: 'world.gi.gz',
    perFragment: true,
    debug: 'level',
    position: [0, 1, 0],
    onLoad: (volume: GiVolume) => console.log(volume.info.indDims),
    onError: (error: Error) => console.error(error.message),
    children: createElement('primitive', { object: world }),
  });
}

export function Hero({ mesh }: { mesh: THREE.Mesh }): null {
  const gi = useGi();
  gi?.addOccluder(mesh);
  return null;
}

export function throughThreesGrid(scene: THREE.Scene, volume: GiVolume): number {
  const box = occupiedBox(volume);
  const grid: LightProbeGridWebGL = makeProbeGrid(volume, LightProbeGridWebGL, { box, spacing: 2 * volume.info.spacing });
  scene.add(grid);
  return grid.resolution.z * 7 <= MAX_GRID_SIDE ? grid.boundingBox.max.x : 0;
}
