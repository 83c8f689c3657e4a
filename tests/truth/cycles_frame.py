"""A frame from Cycles, the truth a player's view is held to: run inside Blender.

  blender -b --factory-startup -P cycles_frame.py -- SCENE.json OUT.exr
          --bounces N --sky R,G,B [--samples S]

SCENE.json is make_scenes.py --room's (triangles, an albedo a mesh, point
lamps in candela), and may add "spheres" ([{"center": [x, y, z], "radius": r,
"albedo": [r, g, b]}]: the moving objects, not in the bake) and must hold a
"camera" ({"position", "target", "fov" (vertical, degrees), "width",
"height"}), all in glTF's y-up metres, as three.js takes them. OUT.exr gets
the frame's linear radiance, 32-bit float, and OUT.pfm the same. N bounces: every source's light after at most N
reflections, as the bakers count them.
"""
import json
import math
import os
import sys
import tempfile

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cycles_common import add_lamp, add_mesh, intensity_per_watt, render_view, reset, y_up  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:]
scene_path, out_path = args[:2]
opts = dict(zip(args[2::2], args[3::2]))
bounces = int(opts["--bounces"])
sky = [float(c) for c in opts.get("--sky", "0,0,0").split(",")]
samples = int(opts.get("--samples", "512"))


def sphere(center, radius, segments=96, rings=48):
    """A UV sphere's triangles, fine enough that its facets are well under a pixel."""
    pos = []
    for j in range(rings + 1):
        t = math.pi * j / rings
        for i in range(segments):
            p = 2.0 * math.pi * i / segments
            pos.append([center[0] + radius * math.sin(t) * math.cos(p), center[1] + radius * math.cos(t),
                        center[2] + radius * math.sin(t) * math.sin(p)])
    idx = []
    for j in range(rings):
        for i in range(segments):
            a, b = j * segments + i, j * segments + (i + 1) % segments
            c, d = a + segments, b + segments
            idx += [a, c, b, b, c, d]
    return pos, idx


def main():
    scratch = tempfile.mkdtemp(prefix="vdbgi-cycles-")
    per_watt = intensity_per_watt(scratch)
    os.rmdir(scratch)
    with open(scene_path) as f:
        scene = json.load(f)
    sc = reset(samples, bounces, sky)
    for m in scene["meshes"]:
        add_mesh(sc, m["name"], m["positions"], m["indices"], m["albedo"])
    for i, s in enumerate(scene.get("spheres", [])):
        pos, idx = sphere(s["center"], s["radius"])
        add_mesh(sc, "sphere%d" % i, pos, idx, s["albedo"])
        bpy.ops.object.select_all(action="DESELECT")
    for lamp in scene["lamps"]:
        add_lamp(sc, y_up(lamp["position"]), lamp["intensity"] / per_watt, lamp["color"])
    render_view(sc, scene["camera"], out_path)
    print("cycles_frame: %s, %d bounces, %d samples" % (out_path, bounces, samples), flush=True)


main()
