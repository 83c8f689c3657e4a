"""What a probe reads, from Cycles: run inside Blender.

  blender -b --factory-startup -P cycles_probes.py -- SCENE.json POINTS.json OUT.json
          --bounces N --part lamp|sky|all --sky R,G,B [--samples S] [--size W]

SCENE.json is make_scenes.py --room's: triangles with an albedo each, and
point lamps (candela). At each point of POINTS.json ({"points": [[x,y,z],...]},
glTF's y-up metres) Cycles renders an equirectangular panorama (W x W/2) of
linear radiance, and OUT.json gets its mean over the sphere, weighted by solid
angle: the scalar a gi-bake probe stores. N bounces counts every source
alike, as the bakers do: a lamp's and the sky's light reach the point after
at most N reflections (Cycles' diffuse bounces: N - 1 after the first hit).

The lamp's power is calibrated in the same run: a white plane 2 m under a
1 W point lamp, one reflection, read straight down, gives the lamp's
intensity per watt (E = I / h^2, L = E / pi); the scene's lamps then get
intensity / (intensity per watt) watts.
"""
import json
import math
import os
import sys
import tempfile

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
scene_path, points_path, out_path = args[:3]
opts = dict(zip(args[3::2], args[4::2]))
bounces = int(opts["--bounces"])
part = opts.get("--part", "all")
sky = [float(c) for c in opts.get("--sky", "0,0,0").split(",")]
samples = int(opts.get("--samples", "256"))
width = int(opts.get("--size", "128"))
scratch = tempfile.mkdtemp(prefix="vdbgi-cycles-")


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    cy = sc.cycles
    cy.device = "CPU"
    cy.samples = samples
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.max_bounces = max(bounces - 1, 0)
    cy.diffuse_bounces = max(bounces - 1, 0)
    cy.glossy_bounces = cy.transmission_bounces = cy.volume_bounces = 0
    cy.transparent_max_bounces = 0
    cy.sample_clamp_direct = cy.sample_clamp_indirect = 0.0
    cy.light_sampling_threshold = 0.0
    cy.filter_width = 0.01
    cy.seed = 1
    sc.render.film_transparent = False
    sc.render.image_settings.file_format = "OPEN_EXR"
    sc.render.image_settings.color_depth = "32"
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*sky, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    sc.world = world
    return sc


def diffuse(name, albedo):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes = m.node_tree.nodes
    nodes.clear()
    bsdf = nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (*albedo, 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    out = nodes.new("ShaderNodeOutputMaterial")
    m.node_tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return m


def y_up(p):
    """glTF's (x, y, z), y up, as Blender's (x, -z, y), z up."""
    return (p[0], -p[2], p[1])


def add_mesh(sc, name, positions, indices, albedo):
    me = bpy.data.meshes.new(name)
    tris = [tuple(indices[i:i + 3]) for i in range(0, len(indices), 3)]
    me.from_pydata([y_up(p) for p in positions], [], tris)
    me.materials.append(diffuse(name, albedo))
    ob = bpy.data.objects.new(name, me)
    sc.collection.objects.link(ob)


def add_lamp(sc, at, watts, color):
    li = bpy.data.lights.new("lamp", "POINT")
    li.energy = watts
    li.shadow_soft_size = 0.0
    li.color = color
    ob = bpy.data.objects.new("lamp", li)
    ob.location = at
    sc.collection.objects.link(ob)


def render(sc, path):
    sc.render.filepath = path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(path)
    w, h = img.size
    px = list(img.pixels)
    bpy.data.images.remove(img)
    os.remove(path)
    return w, h, px


def intensity_per_watt():
    """Cycles' point lamp of 1 W, 2 m over a white plane: I from L = I / (pi h^2)."""
    sc = reset()
    sc.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    add_mesh(sc, "plane", [(-50, 0, 50), (50, 0, 50), (50, 0, -50), (-50, 0, -50)],
             [0, 1, 2, 0, 2, 3], (1.0, 1.0, 1.0))
    add_lamp(sc, (0.0, 0.0, 2.0), 1.0, (1.0, 1.0, 1.0))
    cam = bpy.data.cameras.new("cam")
    cam.type = "ORTHO"
    cam.ortho_scale = 0.01
    ob = bpy.data.objects.new("cam", cam)
    ob.location = (0.0, 0.0, 1.0)  # looks down -z
    sc.collection.objects.link(ob)
    sc.camera = ob
    sc.render.resolution_x = sc.render.resolution_y = 4
    sc.cycles.samples = 16
    w, h, px = render(sc, os.path.join(scratch, "calibrate.exr"))
    L = sum(px[4 * i] for i in range(w * h)) / (w * h)
    return L * math.pi * 2.0 * 2.0


def main():
    per_watt = intensity_per_watt()
    with open(scene_path) as f:
        scene = json.load(f)
    with open(points_path) as f:
        points = json.load(f)["points"]
    sc = reset()
    if part == "lamp":
        sc.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    for m in scene["meshes"]:
        add_mesh(sc, m["name"], m["positions"], m["indices"], m["albedo"])
    if part != "sky":
        for lamp in scene["lamps"]:
            add_lamp(sc, y_up(lamp["position"]), lamp["intensity"] / per_watt, lamp["color"])
    cam = bpy.data.cameras.new("pano")
    cam.type = "PANO"
    cam.cycles.panorama_type = "EQUIRECTANGULAR"
    ob = bpy.data.objects.new("pano", cam)
    ob.rotation_euler = (math.pi / 2, 0.0, 0.0)  # the poles on +-z (Blender's up)
    sc.collection.objects.link(ob)
    sc.camera = ob
    sc.render.resolution_x, sc.render.resolution_y = width, width // 2
    sc.render.resolution_percentage = 100
    means = []
    for i, p in enumerate(points):
        ob.location = y_up(p)
        w, h, px = render(sc, os.path.join(scratch, "probe.exr"))
        total = [0.0, 0.0, 0.0]
        weight = 0.0
        for y in range(h):
            wy = math.sin(math.pi * (y + 0.5) / h)  # solid angle of a row, rows from a pole
            for x in range(w):
                o = 4 * (y * w + x)
                for k in range(3):
                    total[k] += wy * px[o + k]
            weight += wy * w
        means.append([t / weight for t in total])
        print("cycles_probes: point %d/%d: %s" % (i + 1, len(points), means[-1]), flush=True)
    with open(out_path, "w") as f:
        json.dump({"intensity_per_watt": per_watt, "bounces": bounces, "part": part,
                   "samples": samples, "size": width, "means": means}, f)


main()
os.rmdir(scratch)
