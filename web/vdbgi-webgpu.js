// vdbgi-webgpu.js: the same lookup and shading as vdbgi.js, in TSL, for
// three.js's WebGPURenderer (and its WebGL2 fallback), with the same API:
//
//   import { GiRuntime, loadGi } from 'vdbgi/webgpu';
//   const gi = new GiRuntime();
//   gi.setVolume(await loadGi('world.gi.gz'));
//   mesh.material = gi.apply(mesh.material);          // per vertex, as seed 000
//
// The runtime's uniform objects are shared by reference, so setVolume(),
// setKnobs(), `enabled` and `debug` reach every material without a rebuild.
import { MeshStandardNodeMaterial, MeshLambertNodeMaterial } from 'three/webgpu';
import {
  uniform, texture3D, textureLoad, ivec2, vec3, vec4, float, floor, exp2, max, min, mod, clamp, dot, mix, select,
  fwidth, step, positionWorld, normalView, normalLocal, modelNormalMatrix, cameraWorldMatrix, inverseSqrt, Fn, varying,
  output, diffuseColor, materialEmissive, materialAO, If, Loop, Break, sqrt, acos, atan,
} from 'three/tsl';
import * as TSL from 'three/tsl';
import * as WEBGPU from 'three/webgpu';
import { GiRuntimeBase, DebugView, LAYOUT_COMPACT, LEVEL_COLOURS, OCCLUDER_REACH2, MAX_OCCLUDERS, checkThree } from './vdbgi.js';
import { SH2_RANGE } from './gi-format.js';

export {
  loadGi, GiVolume, DebugView, LEVEL_COLOURS, DEFAULT_KNOBS, ENCODING_RGBM, ENCODING_RGB9E5, LAYOUT_SEED, LAYOUT_COMPACT,
  MAX_OCCLUDERS,
} from './vdbgi.js';

// A runtime's nodes: its uniforms, the texture nodes of every lookup made (re-pointed
// by setVolume), the lookup and the bounce.
function giNodes(runtime) {
  const u = runtime.uniforms;
  const textures = runtime._textureNodes;
  const n = {
    boxMin: uniform(u.giBoxMin.value),
    boxSize: uniform(u.giBoxSize.value),
    indDims: uniform(u.giIndDims.value),
    atlasDims: uniform(u.giAtlasDims.value),
    columnsDims: uniform(u.giColumnsDims.value),
    layout: uniform(u.giLayout.value),
    rgbmRange: uniform(0).onRenderUpdate(() => u.giRgbmRange.value),
    on: uniform(0).onRenderUpdate(() => u.giOn.value),
    debug: uniform(0, 'int').onRenderUpdate(() => u.giDebug.value),
    basis: uniform(0).onRenderUpdate(() => u.giBasis.value),
    world: uniform(u.world.value),
    character: uniform(u.character.value),
    // The occluders (see GiRuntimeBase.addOccluder): the runtime's vectors copied into a
    // float texture by updateOccluders(), shape i's ends at (i, 0) and (i, 1), so that the
    // loop reads shape i by index. (three 0.187's uniformArray of vec4 read NaN here on
    // SwiftShader; a uniform a shape, picked by sixteen (i == j) factors, cost most of a
    // frame with sixteen shapes.)
    occ: runtime._occTexture,
    occCount: uniform(0, 'int').onRenderUpdate(() => u.giOccCount.value),
    // Each lookup gets its own texture nodes; a new volume re-points them all.
    texture: (which, at) => {
      const t = which === 'ind' ? textureLoad(u.giColumns.value, at)
        : texture3D(which === 'atlas' ? u.giAtlas.value : u.giSh.value[Number(which.slice(2))], at);
      textures[which].push(new WeakRef(t));
      return t;
    },
  };
  // Seed 000's volumeIrradiance(), as vdbgi.js's GLSL: returns irradiance,
  // level (-1: no brick) and the position inside the brick (0..1). With L2
  // terms, read half a spacing off the surface along its world normal nrm,
  // and evaluated for it (docs/format.md, "Version 6").
  n.lookup = (pos0, nrm0) => {
    // Every choice below but the normal's is arithmetic on 0/1 factors (step, mix): three's
    // select() becomes an if/else, and a node first built inside one branch is built
    // again in every other, which repeated the whole lookup, texture reads and all,
    // about seven times a fragment (76 reads where it needs 10).
    const nn = dot(nrm0, nrm0);
    // A zero normal (a mesh without normals, per vertex) reads L0 alone, as does a NaN
    // one (a zero normal normalised): l2 = basis > 0 and |n|^2 > 0.25, the float after
    // 0.25 the least |n|^2 that passes (a NaN passes no step). The normal is a select(),
    // the one here: a NaN times 0 would stay NaN, and nothing built later is in it.
    const l2 = float(1).sub(step(n.basis, 0)).mul(step(0.25000003, nn));
    const nrm = select(l2.greaterThan(0.5), nrm0.mul(inverseSqrt(max(nn, 0.25))), vec3(0));
    const pos = pos0.add(nrm.mul(n.boxSize.x.div(n.indDims.x.mul(4)).mul(0.5)));
    const p = pos.sub(n.boxMin).div(n.boxSize).mul(n.indDims.mul(4)).sub(0.5);
    const baseBrick0 = floor(p.div(4));
    // The cell's indirection texel from its column's run, as the GLSL (docs/format.md):
    // a row's edge a division may miss steps back, by step(w, col) + step(0, col) - 1.
    const columnsTexel = (i) => {
      const w = n.columnsDims.x;
      const first = floor(i.add(0.5).div(w));
      const col = i.sub(first.mul(w));
      const row = first.add(step(w, col)).add(step(0, col)).sub(1);
      return floor(n.texture('ind', ivec2(i.sub(row.mul(w)), row)).mul(255).add(0.5));
    };
    const cell = clamp(baseBrick0, vec3(0), n.indDims.sub(1));
    const column = cell.x.add(n.indDims.x.mul(cell.z));
    const run = columnsTexel(column.mul(2)), at = columnsTexel(column.mul(2).add(1));
    const ymin = run.r.add(run.g.mul(256)), count = run.b.add(run.a.mul(256));
    // Compact: below the run, its lowest brick at its bottom plane (the lift).
    const compact = float(1).sub(step(0.5, n.layout.x.sub(LAYOUT_COMPACT).abs()));
    const lift = compact.mul(step(0.5, count));
    const baseBrick = vec3(baseBrick0.x, mix(baseBrick0.y, max(baseBrick0.y, ymin), lift), baseBrick0.z);
    const k = mix(cell.y.sub(ymin), max(cell.y.sub(ymin), 0), lift);
    const entry = n.indDims.x.mul(n.indDims.z).mul(2).add(at.r).add(at.g.mul(256)).add(at.b.mul(65536)).add(max(k, 0));
    // In the run: 0 <= k < count (whole numbers).
    const inRun = step(0, k).mul(float(1).sub(step(count, k)));
    const ind = columnsTexel(min(entry, n.columnsDims.x.mul(n.columnsDims.y).sub(1))).mul(inRun);
    // Seed: rgb the slot, a the level + 1. Compact: a holds the level in bits
    // 0-1 and the first texel mod 4 per axis above; rgb its texel / 4.
    const level = mix(max(ind.a.sub(1), 0), mod(ind.a, 4), compact);
    const span = exp2(level);
    const originCell = floor(baseBrick.div(span)).mul(span).mul(4);
    const q0 = p.sub(originCell).add(n.layout.z).div(span).sub(n.layout.z);
    const q = vec3(q0.x, mix(q0.y, max(q0.y, 0), compact), q0.z);
    const low = mod(floor(vec3(ind.a).div(vec3(4, 16, 64))), 4);
    const first = mix(ind.rgb.mul(6).add(n.layout.y), ind.rgb.mul(4).add(low), compact);
    const texel = first.add(q);
    const uvw = texel.add(0.5).div(n.atlasDims);
    const s = n.texture('atlas', uvw);
    const l0 = mix(s.rgb, s.rgb.mul(s.a).mul(n.rgbmRange), step(1e-30, n.rgbmRange));
    // Term byte j = 3 term + channel in texture j / 4, component j mod 4, as q + 128;
    // version 8 (basis 3) has terms 4-8 (j = 3..7) at byte 6 + j, for all three channels.
    const c = [];
    for (let i = 0; i < 6; i++) {
      const t = max(n.texture(`sh${i}`, uvw).mul(255).sub(128).div(127), -1);
      c.push(t.x, t.y, t.z, t.w);
    }
    const poly = [nrm.x, nrm.y, nrm.z, nrm.x.mul(nrm.y), nrm.y.mul(nrm.z), nrm.z.mul(nrm.z).mul(3).sub(1),
      nrm.x.mul(nrm.z), nrm.x.mul(nrm.x).sub(nrm.y.mul(nrm.y))];
    const luma2 = step(2.5, n.basis);
    let sum = vec3(1);
    for (let j = 0; j < 8; j++) {
      const rgb = vec3(c[3 * j], c[3 * j + 1], c[3 * j + 2]);
      sum = sum.add((j < 3 ? rgb : mix(rgb, vec3(c[6 + j]), luma2)).mul(SH2_RANGE[j]).mul(poly[j]));
    }
    // mix(a, b, 0) is a exactly: L0 alone where there are no terms to read.
    const irradiance = mix(l0, max(l0.mul(sum), 0), l2);
    const empty = float(1).sub(step(0.5, ind.r.add(ind.g).add(ind.b).add(ind.a)));
    const levelOut = mix(ind.a.sub(1), mix(level, float(-1), empty), compact);
    return { irradiance, level: levelOut, inBrick: p.sub(originCell).div(span.mul(4)) };
  };
  // The occluders' share of the light at p over unit normal nrm, as vdbgiVisibility() in
  // vdbgi.js: each capsule as the sphere at its segment's point nearest p (the horizon-
  // clipped form only where the horizon cuts it). A loop that stops at the count, as the
  // GLSL's does: sixteen If blocks on it cost a SwiftShader frame more than the volume's
  // lookup, every branch run for every fragment whatever the count (docs/web.md).
  n.visibility = Fn(([p, nrm]) => {
    const v = float(1).toVar();
    Loop({ start: 0, end: MAX_OCCLUDERS, type: 'int', condition: '<' }, ({ i }) => {
      If(i.greaterThanEqual(n.occCount), () => { Break(); });
      const A = textureLoad(n.occ, ivec2(i, 0)), B = textureLoad(n.occ, ivec2(i, 1));
      const a = A.xyz, ab = B.xyz.sub(a), r = A.w, r2 = r.mul(r);
      const len2 = dot(ab, ab);
      const t = clamp(dot(p.sub(a), ab).div(max(len2, 1e-20)), 0, 1).mul(step(1e-30, len2));
      const d = a.add(ab.mul(t)).sub(p);
      const l2 = dot(d, d), dn = dot(nrm, d);
      // As the GLSL: not from inside, wholly below the horizon, or past 22 radii.
      If(l2.greaterThan(r2.mul(1.002)).and(dn.greaterThan(r.negate())).and(l2.lessThan(r2.mul(OCCLUDER_REACH2))),
        () => {
          const l = sqrt(l2), nl = dn.div(l);
          const h2 = l2.div(r2), k2 = float(1).sub(h2.mul(nl).mul(nl));
          const occ = max(nl, 0).div(h2).toVar();
          If(k2.greaterThan(1e-4), () => {
            const h1 = max(h2.sub(1), 1e-20);
            const x = clamp(nl.negate().mul(sqrt(h1.div(max(float(1).sub(nl.mul(nl)), 1e-20)))), -1, 1);
            occ.assign(nl.mul(acos(x)).sub(sqrt(max(k2.mul(h1), 0))).div(h2).add(atan(sqrt(k2.div(h1))))
              .div(Math.PI));
          });
          v.mulAssign(float(1).sub(clamp(occ, 0, 1)));
        });
    });
    return v;
  });
  // The seed's knobs: see vdbgiBounce() in vdbgi.js.
  // Plain node arithmetic: an inline Fn() with a return makes three warn once per material.
  n.bounce = (irradiance, albedo, knobs) => {
    const ownHue = albedo.sub(dot(albedo, vec3(1 / 3)));
    const hue = irradiance.sub(dot(irradiance, vec3(1 / 3)));
    const len2 = dot(ownHue, ownHue);
    const along = select(len2.greaterThan(1e-8), max(dot(hue, ownHue), 0).div(max(len2, 1e-8)), 0);
    const e = max(irradiance.sub(float(1).sub(knobs.y).mul(along).mul(ownHue)), 0);
    return e.mul(mix(albedo, vec3(1), knobs.z)).mul(knobs.x);
  };
  return n;
}

// The albedo a standard material's diffuse light sees, (1 - metalness) x its
// colour: diffuseContribution from three 0.183 on (exported by three/tsl from
// 0.186, only in three/webgpu's TSL object before); until 0.182 diffuseColor
// held it. Namespace imports, so that an absent name is no link error.
const standardDiffuse = () => TSL.diffuseContribution ?? WEBGPU.TSL?.diffuseContribution ?? diffuseColor.rgb;

// The WebGPU runtime: apply() builds the lookup in TSL.
export class GiRuntime extends GiRuntimeBase {
  constructor() {
    checkThree('webgpu', WEBGPU.REVISION);
    super();
    this._textureNodes = { ind: [], atlas: [], sh0: [], sh1: [], sh2: [], sh3: [], sh4: [], sh5: [] };
    const occ = new WEBGPU.DataTexture(new Float32Array(4 * MAX_OCCLUDERS * 2), MAX_OCCLUDERS, 2,
      WEBGPU.RGBAFormat, WEBGPU.FloatType);
    occ.minFilter = occ.magFilter = WEBGPU.NearestFilter;
    occ.needsUpdate = true;
    this._occTexture = occ;
    this._nodes = giNodes(this);
  }

  dispose() {
    super.dispose();
    this._occTexture.dispose();
  }

  updateOccluders() {
    super.updateOccluders();
    const u = this.uniforms, data = this._occTexture.image.data;
    for (let i = 0; i < u.giOccCount.value; i++) {
      u.giOccA.value[i].toArray(data, 4 * i);
      u.giOccB.value[i].toArray(data, 4 * (MAX_OCCLUDERS + i));
    }
    this._occTexture.needsUpdate = true;
  }

  setVolume(volume) {
    super.setVolume(volume);
    const u = this.uniforms;
    const now = { ind: u.giColumns.value, atlas: u.giAtlas.value };
    u.giSh.value.forEach((t, i) => { now[`sh${i}`] = t; });
    for (const [which, refs] of Object.entries(this._textureNodes))
      for (const ref of refs) {
        const t = ref.deref();
        if (t) t.value = now[which];
      }
  }

  // The irradiance node at world position `pos` for world normal `normal` (default: the fragment's).
  irradianceNode(pos = positionWorld, normal = fragmentNormal()) {
    return this._nodes.lookup(pos, normal).irradiance;
  }

  // Add GI to a material, as vdbgi.js's apply(): a MeshStandardMaterial,
  // MeshPhysicalMaterial or MeshLambertMaterial becomes its node counterpart
  // (toNodeMaterial), and a MeshStandardNodeMaterial or MeshLambertNodeMaterial
  // is changed in place; returns the material to use. The bounce x albedo goes
  // into the emissive term (added after lighting, as the seed's
  // indirectLight), looked up per vertex (varying) or per fragment; the debug
  // views replace the output. Any other material is returned as it was, with
  // one warning; a material given twice is returned as it is.
  apply(material, { set = 'world', perFragment = false, volume = true } = {}) {
    this._set(set);
    if (!material.isNodeMaterial && (material.isMeshStandardMaterial || material.isMeshLambertMaterial))
      material = toNodeMaterial(material);
    const supported = material.isMeshStandardNodeMaterial || material.isMeshLambertNodeMaterial;
    if (!this._admits(material, supported, ' and their node forms')) return material;
    return applyNodes(material, this._nodes, { set, perFragment, volume, debugOn: this.debug !== DebugView.OFF });
  }

  // The debug views' output while one is shown, the material's own otherwise (an
  // output node set since apply() is the one to go back to).
  _showDebug(m, shown) {
    if (!m.vdbgiOutput) return;
    if (shown && m.outputNode !== m.vdbgiOutput.debug) m.vdbgiOutput.plain = m.outputNode ?? null;
    m.outputNode = shown ? m.vdbgiOutput.debug : m.vdbgiOutput.plain;
  }
}

// The fragment's world normal, from its view normal in the fragment stage (flat
// shading's derivatives included): three 0.175's normalWorld is a varying, made
// in the vertex stage, where a flat-shaded material's derivatives do not exist.
// The camera's world matrix turns view directions to world ones (transformDirection
// multiplies on the left: the view matrix here gave the normal turned the wrong way,
// which the occluders' test caught).
const fragmentNormal = () => normalView.transformDirection(cameraWorldMatrix);
// A vertex's world normal (instancing already in normalLocal), or zero for a mesh
// without normals (normalLocal would warn there): the lookup then reads L0.
const vertexNormal = () =>
  Fn((builder) => (builder.geometry?.hasAttribute?.('normal') ? modelNormalMatrix.mul(normalLocal) : vec3(0)))();

function applyNodes(material, n, { set, perFragment, volume, debugOn }) {
  const here = n.lookup(positionWorld, fragmentNormal());
  const irradiance = perFragment || !volume ? here.irradiance
    : varying(n.lookup(positionWorld, vertexNormal()).irradiance);
  const albedo = material.isMeshStandardNodeMaterial ? standardDiffuse() : diffuseColor.rgb;
  // The occluders take their share of the volume's bounce (added as emission) and, as
  // ambient occlusion, of the lighting model's indirect light (a lightmap's among it).
  const visible = n.visibility(positionWorld, fragmentNormal().normalize());
  const bounce = n.bounce(irradiance, albedo, n[set]).mul(n.on).mul(visible);
  if (volume) material.emissiveNode = (material.emissiveNode ?? materialEmissive).add(bounce);
  const ao = material.aoNode ?? (material.aoMap ? materialAO : null);
  material.aoNode = ao ? ao.mul(visible) : visible;
  // The debug views as one select chain (no Fn() with a return, which three warns about).
  const levelColour = (() => {
    const l = here.level, c = LEVEL_COLOURS.map((rgb) => vec3(...rgb));
    return select(l.lessThan(0), c[0], select(l.lessThan(0.5), c[1],
      select(l.lessThan(1.5), c[2], select(l.lessThan(2.5), c[3], c[4]))));
  })();
  const boundaries = (() => {
    const b = here.inBrick, w = fwidth(b);
    // A line where the surface crosses a brick's face: an axis along which the position
    // does not move across the pixel (a floor read in a face's plane) crosses none.
    const d1 = min(b, b.oneMinus()).div(max(w, vec3(1e-6)));
    const d0 = vec3(select(w.x.lessThan(1e-6), float(1e6), d1.x), select(w.y.lessThan(1e-6), float(1e6), d1.y),
      select(w.z.lessThan(1e-6), float(1e6), d1.z));
    // Below its column's lowest brick (the lift): no face there, so y draws no line.
    const d = vec3(d0.x, select(b.y.lessThan(0), float(1e6), d0.y), d0.z);
    const edge = clamp(min(d.x, min(d.y, d.z)).sub(0.5), 0, 1).oneMinus();
    return mix(here.irradiance, vec3(0), edge);
  })();
  const view = (id) => n.debug.equal(id);
  // In the material only while a view is shown (GiRuntime._debugChanged): the chain's
  // branches ran for every fragment on SwiftShader.
  material.vdbgiOutput = { plain: material.outputNode ?? null,
    debug: select(view(DebugView.PROBE), vec4(irradiance, 1),
      select(view(DebugView.LEVEL), vec4(levelColour, 1),
        select(view(DebugView.BRICKS), vec4(boundaries, 1),
          select(view(DebugView.POSITION), vec4(positionWorld, 1),
            select(view(DebugView.NORMAL), vec4(fragmentNormal().normalize(), 1), output))))) };
  material.outputNode = debugOn ? material.vdbgiOutput.debug : material.vdbgiOutput.plain;
  material.needsUpdate = true;
  return material;
}

// The properties a glTF's MeshStandardMaterial or MeshLambertMaterial carries
// over to its node counterpart.
const CARRIED = ['name', 'color', 'map', 'emissive', 'emissiveMap', 'emissiveIntensity', 'roughness', 'metalness',
  'roughnessMap', 'metalnessMap', 'normalMap', 'normalScale', 'aoMap', 'aoMapIntensity', 'alphaMap', 'vertexColors',
  'side', 'transparent', 'opacity', 'alphaTest', 'flatShading', 'lightMap', 'lightMapIntensity'];

export function toNodeMaterial(material) {
  if (material.isNodeMaterial) return material;
  const out = material.isMeshLambertMaterial ? new MeshLambertNodeMaterial() : new MeshStandardNodeMaterial();
  for (const key of CARRIED) {
    if (!(key in material) || !(key in out)) continue;
    const v = material[key];
    if (v && typeof v.clone === 'function' && !v.isTexture) out[key] = v.clone();
    else out[key] = v;
  }
  return out;
}
