// plain.js: the frame as a three.js page draws it with the volume alone (docs/web.md:
// gi.light(), per fragment where a mesh's triangles are large).
import * as THREE from 'three';
import { WebGPURenderer } from 'three/webgpu';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';
import { GiRuntime as GlRuntime, loadGi } from '../../../web/vdbgi.js';
import { GiRuntime as GpuRuntime } from '../../../web/vdbgi-webgpu.js';
import { CAMERA, GL, SIZE, WEBGPU } from './view.js';

const renderer = WEBGPU ? new WebGPURenderer(GL) : new THREE.WebGLRenderer(GL);
if (WEBGPU) await renderer.init();
renderer.setPixelRatio(1);
renderer.setSize(SIZE.width, SIZE.height);
document.body.appendChild(renderer.domElement);
const camera = new THREE.PerspectiveCamera(CAMERA.fov, SIZE.width / SIZE.height, CAMERA.near, CAMERA.far);
camera.position.set(...CAMERA.position);
camera.lookAt(0, 0, 0);
const scene = new THREE.Scene();
const gi = WEBGPU ? new GpuRuntime() : new GlRuntime();
const [gltf, volume] = await Promise.all([new GLTFLoader().loadAsync('world.glb'),
  loadGi('world.gi.gz', { renderer })]);
gi.setVolume(volume);
gi.light(gltf.scene);
scene.add(gltf.scene);
window.frame = () => renderer.render(scene, camera);
