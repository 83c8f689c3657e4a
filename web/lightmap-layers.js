// lightmap-layers.js: seed 004's runtime compositing of gi-lightmap's per-light
// layers (--layers), for three.js's WebGL2 and WebGPU renderers. Each atlas gets a
// half-float render target holding sum_i weight_i * scale_i * layer_i (the layers
// are 8-bit sRGB maps of E / scale, decoded to linear by the sampler), drawn again
// only when a weight changes; materials take it as their lightMap at intensity 1.
import * as THREE from 'three';

export class LayerCompositor {
  // renderer: a WebGLRenderer; or a WebGPURenderer with gpu = { webgpu, tsl }, the
  // modules 'three/webgpu' and 'three/tsl'.
  constructor(renderer, gpu = null) {
    this.renderer = renderer;
    this.gpu = gpu;
    this.weights = new Map(); // layer name -> weight (1 by default)
    this.pages = new Map(); // atlas key -> { target, scene, material, layers, gains }
    // Looking at the quad (z = 0) from z = 0.5: WebGPU draws it through the camera; GLSL ignores it.
    this.camera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
    this.camera.position.z = 0.5;
    this.camera.updateMatrixWorld();
  }

  // The composite of one atlas's layers ([{ name, map, scale }]), made once per key.
  target(key, layers) {
    const known = this.pages.get(key);
    if (known) return known.target.texture;
    const { width, height } = layers[0].map.image;
    const options = { type: THREE.HalfFloatType, minFilter: THREE.LinearFilter, magFilter: THREE.LinearFilter,
      generateMipmaps: false, depthBuffer: false };
    const target = this.gpu ? new this.gpu.webgpu.RenderTarget(width, height, options)
                            : new THREE.WebGLRenderTarget(width, height, options);
    target.texture.channel = 1; // TEXCOORD_1, as the maps it replaces
    for (const l of layers) if (!this.weights.has(l.name)) this.weights.set(l.name, 1);
    const { material, gains } = this.gpu ? this.nodeSum(layers) : this.glslSum(layers);
    const scene = new THREE.Scene();
    scene.add(new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material));
    const page = { target, scene, material, layers, gains };
    this.pages.set(key, page);
    this.draw(page);
    return target.texture;
  }

  // WebGL2: one GLSL pass, a sampler and a gain a layer; gains are the uniforms.
  glslSum(layers) {
    const uniforms = {};
    layers.forEach((l, i) => {
      uniforms[`map${i}`] = { value: l.map };
      uniforms[`gain${i}`] = { value: l.scale };
    });
    const material = new THREE.ShaderMaterial({
      uniforms, depthTest: false, depthWrite: false, toneMapped: false,
      vertexShader: 'out vec2 vUv; void main() { vUv = uv; gl_Position = vec4(position.xy, 0.0, 1.0); }',
      fragmentShader: layers.map((_, i) => `uniform sampler2D map${i}; uniform float gain${i};`).join('\n') +
        '\nin vec2 vUv;\nvoid main() {\n  vec3 e = vec3(0.0);\n' +
        layers.map((_, i) => `  e += gain${i} * texture(map${i}, vUv).rgb;`).join('\n') +
        '\n  gl_FragColor = vec4(e, 1.0);\n}',
    });
    return { material, gains: layers.map((_, i) => uniforms[`gain${i}`]) };
  }

  // WebGPU: the same sum as a TSL node; gains are uniform nodes (a .value each).
  nodeSum(layers) {
    const { texture, uniform, uv, vec2, vec4, float } = this.gpu.tsl;
    const gains = layers.map((l) => uniform(l.scale));
    // A WebGPU target's first row is the top of the quad (clip y = +1), WebGL's the
    // bottom: read each layer at 1 - v so the target's rows match the layers'.
    const at = vec2(uv().x, float(1).sub(uv().y));
    let e = vec4(0, 0, 0, 0).rgb;
    layers.forEach((l, i) => { e = e.add(texture(l.map, at).rgb.mul(gains[i])); });
    const material = new this.gpu.webgpu.MeshBasicNodeMaterial({ depthTest: false, depthWrite: false, toneMapped: false });
    material.colorNode = vec4(e, float(1));
    return { material, gains };
  }

  names() { return [...this.weights.keys()]; }

  setWeight(name, weight) {
    this.weights.set(name, weight);
    for (const page of this.pages.values()) this.draw(page);
  }

  draw(page) {
    page.layers.forEach((l, i) => { page.gains[i].value = l.scale * this.weights.get(l.name); });
    const previous = this.renderer.getRenderTarget();
    this.renderer.setRenderTarget(page.target);
    this.renderer.render(page.scene, this.camera);
    this.renderer.setRenderTarget(previous);
  }

  dispose() {
    for (const page of this.pages.values()) {
      page.target.dispose();
      page.material.dispose();
      page.scene.children[0].geometry.dispose();
    }
    this.pages.clear();
    this.weights.clear();
  }
}
