"""A frame of a glTF scene from Cycles, the truth a player's view is held to: run inside Blender.

  blender -b --factory-startup -P cycles_gltf_frame.py -- SCENE.glb VIEW.json OUT.exr
          --bounces N --sun X,Y,Z --sun-color R,G,B [--sky R,G,B] [--samples S]

For scenes that make_scenes.py's JSON does not describe (the bundled world:
an embedded texture, vertex colours, instanced nodes): Blender's own glTF
importer reads SCENE.glb, and every material becomes a diffuse BSDF of the
albedo the importer wires into its base colour (factor x texture x vertex
colour), as the bakers read it. The sun is the bakers': --sun is the direction
towards it in glTF's y-up axes, --sun-color its colour as the bakers take it
(E / pi), so a Cycles sun of strength pi x the colour. VIEW.json holds
"camera" as cycles_frame.py takes it. OUT.exr gets the linear radiance, and
OUT.pfm the same.
"""
import json
import math
import os
import sys

import addon_utils
import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_common import diffuse, render_view, reset, y_up  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
scene_path, view_path, out_path = args[:3]
opts = dict(zip(args[3::2], args[4::2]))
bounces = int(opts["--bounces"])
vec = lambda key, default: [float(c) for c in opts.get(key, default).split(",")]  # noqa: E731
sky, sun, sun_color = vec("--sky", "0,0,0"), vec("--sun", "0.4,0.8,0.3"), vec("--sun-color", "1,1,1")
samples = int(opts.get("--samples", "512"))


def diffuse_only():
    """Each material a diffuse BSDF fed by what fed its Principled BSDF's base colour."""
    for m in bpy.data.materials:
        if not m.use_nodes:
            continue
        nodes, links = m.node_tree.nodes, m.node_tree.links
        pbr = next((n for n in nodes if n.type == "BSDF_PRINCIPLED"), None)
        out = next((n for n in nodes if n.type == "OUTPUT_MATERIAL"), None)
        if pbr is None or out is None:
            continue
        bsdf = nodes.new("ShaderNodeBsdfDiffuse")
        bsdf.inputs["Roughness"].default_value = 0.0
        base = pbr.inputs["Base Color"]
        if base.is_linked:
            links.new(base.links[0].from_socket, bsdf.inputs["Color"])
        else:
            bsdf.inputs["Color"].default_value = base.default_value
        links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])


def main():
    sc = reset(samples, bounces, sky)
    addon_utils.enable("io_scene_gltf2", default_set=True)
    # Debian's Blender 3.4 importer still says np.bool, an alias NumPy 1.24 removed.
    if not hasattr(np, "bool"):
        np.bool = bool
    bpy.ops.import_scene.gltf(filepath=os.path.abspath(scene_path))
    for ob in bpy.data.objects:
        if ob.type == "MESH" and not ob.data.materials:
            ob.data.materials.append(diffuse("white", (1.0, 1.0, 1.0)))
    diffuse_only()
    # The sun: its light travels along -Z of its object, so +Z points towards it.
    li = bpy.data.lights.new("sun", "SUN")
    peak = max(sun_color)
    li.energy = math.pi * peak
    li.color = [c / peak for c in sun_color] if peak > 0 else (1.0, 1.0, 1.0)
    li.angle = 0.0
    ob = bpy.data.objects.new("sun", li)
    ob.rotation_euler = Vector(y_up(sun)).normalized().to_track_quat("Z", "Y").to_euler()
    sc.collection.objects.link(ob)
    with open(view_path) as f:
        render_view(sc, json.load(f)["camera"], out_path, clip_end=1000.0)
    print("cycles_gltf_frame: %s, %d bounces, %d samples" % (out_path, bounces, samples), flush=True)


main()
