// check_api.mjs: the two back ends' GiRuntime have one API (the same methods
// and options; the WebGPU one overrides setVolume as a subclass, it patches
// nothing), apply() leaves an unsupported material as it was with one
// warning for many, returns a material given twice as it is, and `debug`
// takes a view's name or its number and refuses others. Runs in node: no
// renderer is needed to apply GI to a material.
import * as THREE from '../../web/node_modules/three/build/three.module.js';
import * as webgl from '../../web/vdbgi.js';

const webgpu = await import('../../web/vdbgi-webgpu.js');
const warnings = [];
console.warn = (message) => warnings.push(message);
const methods = (o) => {
  const names = new Set();
  for (let p = Object.getPrototypeOf(o); p && p !== Object.prototype; p = Object.getPrototypeOf(p))
    for (const n of Object.getOwnPropertyNames(p)) if (n !== 'constructor' && !n.startsWith('_')) names.add(n);
  return [...names].sort();
};
const shared = [];
for (const [name, mod] of [['WebGL2', webgl], ['WebGPU', webgpu]]) {
  const gi = new mod.GiRuntime();
  shared.push(methods(gi).filter((m) => m !== 'irradianceNode'));
  const before = warnings.length;
  const unlit = new THREE.MeshBasicMaterial();
  const kept = gi.apply(unlit) === unlit && gi.apply(new THREE.MeshBasicMaterial()) !== unlit;
  console.log(`${name}: an unlit material is returned as it was: ${kept}; warnings for two: ${warnings.length - before}`);
  const lit = gi.apply(new THREE.MeshStandardMaterial(), { set: 'character', perFragment: true });
  console.log(`${name}: a standard material becomes ${lit.type}; given twice, the same: ${gi.apply(lit) === lit}`);
  gi.debug = 'level';
  const byName = gi.debug === mod.DebugView.LEVEL;
  gi.debug = mod.DebugView.BRICKS;
  console.log(`${name}: debug by name: ${byName}, by number: ${gi.debug === mod.DebugView.BRICKS}`);
  for (const bad of ['nope', 7]) {
    try {
      gi.debug = bad;
      console.log(`${name}: debug ${bad} accepted`);
    } catch (e) {
      console.log(`${name}: ${e.message}`);
    }
  }
  try {
    gi.apply(new THREE.MeshStandardMaterial(), { set: 'hero' });
  } catch (e) {
    console.log(`${name}: ${e.message}`);
  }
  console.log(`${name}: setVolume is the runtime's own: ${Object.hasOwn(gi, 'setVolume') === false}`);
  // lightScene() with a mover that shares its material with a lightmapped static (glTF
  // exporters share materials): each keeps its own way of lighting, the lightmap stays off the mover.
  const map = new THREE.Texture();
  const material = new THREE.MeshStandardMaterial();
  material.userData.vdbgi_lightmap = { texture: 0, texCoord: 1, scale: 2 };
  const world = new THREE.Mesh(new THREE.BufferGeometry(), material);
  const hero = new THREE.Mesh(new THREE.BufferGeometry(), material);
  const gltf = { scene: new THREE.Group().add(world), parser: { getDependency: async () => map } };
  const counts = await gi.lightScene(gltf, { moving: [hero], occlude: false });
  console.log(`${name}: lightScene with a shared material: ${JSON.stringify(counts)}; ` +
    `the static's lightmap ${world.material.lightMap === map ? 'on' : 'off'} at ${world.material.lightMapIntensity}, ` +
    `the mover's ${hero.material.lightMap ? 'on' : 'off'}, two materials: ${world.material !== hero.material}`);
  // light(): per fragment where a mesh's triangles are long against the probe spacing (a
  // room's two-triangle floor; a small quad scaled up), per vertex where they are short; a
  // material shared by both ways becomes two. Only the volume's spacing is read, so a
  // stand-in with that one figure serves.
  try {
    gi.light(new THREE.Group());
  } catch (e) {
    console.log(`${name}: ${e.message}`);
  }
  gi.volume = { info: { spacing: 0.5 } };
  const common = new THREE.MeshStandardMaterial();
  const floor = new THREE.Mesh(new THREE.PlaneGeometry(4, 4), common);
  const fine = new THREE.Mesh(new THREE.PlaneGeometry(4, 4, 32, 32), common);
  const scaled = new THREE.Mesh(new THREE.PlaneGeometry(0.4, 0.4), new THREE.MeshStandardMaterial());
  scaled.scale.setScalar(10);
  const room = new THREE.Group().add(floor, fine, new THREE.Group().add(scaled));
  const ways = gi.light(room);
  const vertex = (m) => (name === 'WebGL2' ? 'VDBGI_PER_VERTEX' in m.defines : 'in its nodes');
  console.log(`${name}: light() at 0.5 m: ${JSON.stringify(ways)}; per vertex: floor ${vertex(floor.material)}, ` +
    `fine ${vertex(fine.material)}, scaled ${vertex(scaled.material)}; the shared material split: ` +
    `${floor.material !== fine.material}; forced: ${JSON.stringify(gi.light(new THREE.Group().add(
      new THREE.Mesh(new THREE.PlaneGeometry(4, 4), new THREE.MeshStandardMaterial())), { perFragment: false }))}`);
  // Across calls: a coarse floor lit after a fine one sharing its material gets its own
  // per-fragment copy; an instanced 0.2 m quad at 50 times its size reads per fragment.
  const sharedLater = new THREE.MeshStandardMaterial();
  const fineFirst = new THREE.Mesh(new THREE.PlaneGeometry(4, 4, 32, 32), sharedLater);
  const coarseLater = new THREE.Mesh(new THREE.PlaneGeometry(4, 4), sharedLater);
  gi.light(fineFirst);
  const later = gi.light(coarseLater);
  const instanced = new THREE.InstancedMesh(new THREE.PlaneGeometry(0.2, 0.2), new THREE.MeshStandardMaterial(), 2);
  instanced.setMatrixAt(1, new THREE.Matrix4().makeScale(50, 50, 50));
  console.log(`${name}: light() in two calls: ${JSON.stringify(later)}, its own material: ` +
    `${coarseLater.material !== fineFirst.material}, per vertex: fine ${vertex(fineFirst.material)}, ` +
    `coarse ${vertex(coarseLater.material)}; an instanced quad scaled 50 times: ${JSON.stringify(gi.light(instanced))}`);
  const multi = new THREE.Mesh(new THREE.PlaneGeometry(4, 4),
    [new THREE.MeshStandardMaterial(), new THREE.MeshLambertMaterial()]);
  gi.light(multi);
  console.log(`${name}: light() on a mesh of two materials: ${multi.material.map((m) => m.type).join(', ')}, ` +
    `per vertex: ${multi.material.map(vertex).join(', ')}`);
  gi.volume = null;
}
console.log(`the same methods: ${JSON.stringify(shared[0]) === JSON.stringify(shared[1])} (${shared[0].join(', ')})`);
console.log(`WebGPU adds: irradianceNode: ${typeof new webgpu.GiRuntime().irradianceNode === 'function'}`);
// three's version, as each runtime's constructor checks it (with the real REVISION, which passes).
for (const [backend, revision] of [['webgl', '164'], ['webgl', '165'], ['webgpu', '174'], ['webgpu', '175']]) {
  let said = 'accepted';
  try {
    webgl.checkThree(backend, revision);
  } catch (e) {
    said = e.message;
  }
  console.log(`${backend} r${revision}: ${said}`);
}
