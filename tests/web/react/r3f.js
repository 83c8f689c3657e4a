// r3f.js: the same frame from React Three Fiber and vdbgi/react: <GiLight> around
// a glTF that loads (suspends) on its own, and useGi() reaching the runtime. WebGPU
// as R3F's docs make it: a WebGPURenderer from the Canvas's gl factory.
import { createElement as h, Suspense, useEffect } from 'react';
import { createRoot } from 'react-dom/client';
import { Canvas, useLoader, useThree } from '@react-three/fiber';
import { WebGPURenderer } from 'three/webgpu';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { GiLight, useGi } from '../../../web/vdbgi-react.js';
import { CAMERA, GL, SIZE, WEBGPU } from './view.js';

let volumeLoaded = false, sceneMounted = null;
function World() {
  const gltf = useLoader(GLTFLoader, 'world.glb');
  return h('primitive', { object: gltf.scene });
}
// Mounts after World (the same Suspense boundary): the world is in the scene.
function Ready() {
  const state = useThree();
  const gi = useGi();
  useEffect(() => { sceneMounted = { state, gi }; }, [state, gi]);
  return null;
}
const gl = WEBGPU ? async (props) => {
  const r = new WebGPURenderer({ ...props, ...GL });
  await r.init();
  return r;
} : GL;
const div = Object.assign(document.createElement('div'), { style: `width:${SIZE.width}px;height:${SIZE.height}px` });
document.body.appendChild(div);
// shadows as an object: R3F's default sets PCFSoftShadowMap, which three 0.187's
// WebGPURenderer no longer has (and says so in the console).
createRoot(div).render(h(Canvas, { gl, dpr: 1, flat: true, frameloop: 'demand', camera: CAMERA,
  shadows: { enabled: false } },
  h(GiLight, { url: 'world.gi.gz', onLoad: () => { volumeLoaded = true; } },
    h(Suspense, { fallback: null }, h(World), h(Ready)))));

await new Promise((done) => {
  const wait = () => (volumeLoaded && sceneMounted?.gi ? done() : setTimeout(wait, 20));
  wait();
});
window.frame = async (enabled = true) => {
  const { state, gi } = sceneMounted;
  gi.enabled = enabled;
  state.gl.render(state.scene, state.camera);
};
