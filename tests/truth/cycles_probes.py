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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_common import add_lamp, add_mesh, intensity_per_watt, render, reset, y_up  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
scene_path, points_path, out_path = args[:3]
opts = dict(zip(args[3::2], args[4::2]))
bounces = int(opts["--bounces"])
part = opts.get("--part", "all")
sky = [float(c) for c in opts.get("--sky", "0,0,0").split(",")]
samples = int(opts.get("--samples", "256"))
width = int(opts.get("--size", "128"))
scratch = tempfile.mkdtemp(prefix="vdbgi-cycles-")


def main():
    per_watt = intensity_per_watt(scratch)
    with open(scene_path) as f:
        scene = json.load(f)
    with open(points_path) as f:
        points = json.load(f)["points"]
    sc = reset(samples, bounces, sky)
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
