"""What the Cycles truths share: run inside Blender (cycles_probes.py, cycles_frame.py).

A scene of diffuse triangles (make_scenes.py --room's .json: glTF's y-up
metres, an albedo a mesh), point lamps in candela calibrated against Cycles'
watts, and a uniform world; Cycles with diffuse bounces only, no clamps, no
light threshold, no denoising, a fixed seed.
"""
import math
import os
import struct

import bpy
from mathutils import Vector


def reset(samples, bounces, sky):
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


def render_view(sc, c, out_path, clip_end=None):
    """Render sc seen from camera c ({"position", "target", "fov" (vertical, degrees),
    "width", "height"}, glTF's y-up metres, as three.js takes them) into out_path (32-bit
    EXR), and the same pixels as a .pfm beside it (Blender's rows run from the bottom, as
    PFM's), for readers without an EXR library. clip_end: the camera's far limit, metres
    (None: Blender's own)."""
    cam = bpy.data.cameras.new("view")
    cam.sensor_fit = "VERTICAL"
    cam.angle_y = math.radians(c["fov"])
    cam.clip_start = 0.01
    if clip_end is not None:
        cam.clip_end = clip_end
    ob = bpy.data.objects.new("view", cam)
    ob.location = y_up(c["position"])
    look = Vector(y_up(c["target"])) - Vector(ob.location)
    ob.rotation_euler = look.to_track_quat("-Z", "Y").to_euler()
    sc.collection.objects.link(ob)
    sc.camera = ob
    sc.render.resolution_x, sc.render.resolution_y = c["width"], c["height"]
    sc.render.resolution_percentage = 100
    sc.render.filepath = out_path
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(out_path)
    w, h = img.size
    px = img.pixels[:]
    with open(os.path.splitext(out_path)[0] + ".pfm", "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(struct.pack("<%df" % (3 * w * h), *(px[4 * i + k] for i in range(w * h) for k in range(3))))


def intensity_per_watt(scratch):
    """Cycles' point lamp of 1 W, 2 m over a white plane: I from L = I / (pi h^2)."""
    sc = reset(16, 1, (0.0, 0.0, 0.0))
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


