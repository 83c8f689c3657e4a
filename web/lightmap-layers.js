// lightmap-layers.js: seed 004's runtime compositing of gi-lightmap's per-light
// layers (--layers), for three.js's WebGL2 renderer. Each atlas gets a half-float
// render target holding sum_i weight_i * scale_i * layer_i (the layers are 8-bit
// sRGB maps of E / scale, decoded to linear by the sampler), drawn again only when
// a weight changes; materials take it as their lightMap at intensity 1.
import * as THREE from 'three';

export class LayerCompositor {
  constructor(renderer) {
    this.renderer = renderer;
    this.weights = new Map(); // layer name -> weight (1 by default)
    this.pages = new Map(); // atlas key -> { target, scene, material, layers }
    this.camera = new THREE.OrthographicCamera(-1, 1, 1, -1, 0, 1);
  }

  // The composite of one atlas's layers ([{ name, map, scale }]), made once per key.
  target(key, layers) {
    const known = this.pages.get(key);
    if (known) return known.target.texture;
    const { width, height } = layers[0].map.image;
    const target = new THREE.WebGLRenderTarget(width, height, {
      type: THREE.HalfFloatType, minFilter: THREE.LinearFilter, magFilter: THREE.LinearFilter,
      generateMipmaps: false, depthBuffer: false });
    target.texture.channel = 1; // TEXCOORD_1, as the maps it replaces
    const uniforms = {};
    layers.forEach((l, i) => {
      uniforms[`map${i}`] = { value: l.map };
      uniforms[`gain${i}`] = { value: l.scale };
      if (!this.weights.has(l.name)) this.weights.set(l.name, 1);
    });
    const material = new THREE.ShaderMaterial({
      uniforms, depthTest: false, depthWrite: false, toneMapped: false,
      vertexShader: 'out vec2 vUv; void main() { vUv = uv; gl_Position = vec4(position.xy, 0.0, 1.0); }',
      fragmentShader: layers.map((_, i) => `uniform sampler2D map${i}; uniform float gain${i};`).join('\n') +
        '\nin vec2 vUv;\nvoid main() {\n  vec3 e = vec3(0.0);\n' +
        layers.map((_, i) => `  e += gain${i} * texture(map${i}, vUv).rgb;`).join('\n') +
        '\n  gl_FragColor = vec4(e, 1.0);\n}',
    });
    const scene = new THREE.Scene();
    scene.add(new THREE.Mesh(new THREE.PlaneGeometry(2, 2), material));
    this.pages.set(key, { target, scene, material, layers });
    this.draw(this.pages.get(key));
    return target.texture;
  }

  names() { return [...this.weights.keys()]; }

  setWeight(name, weight) {
    this.weights.set(name, weight);
    for (const page of this.pages.values()) this.draw(page);
  }

  draw(page) {
    page.layers.forEach((l, i) => { page.material.uniforms[`gain${i}`].value = l.scale * this.weights.get(l.name); });
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
