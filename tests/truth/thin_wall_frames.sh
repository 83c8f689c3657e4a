#!/bin/sh
# thin_wall_frames.sh BIN OUTDIR: light through a thin wall, in frames (issue 46). Two
# closed rooms sharing a 10 cm wall, a 20 cd lamp in one (make_scenes.py --two-rooms),
# seen from a corner of each room in headless Chromium (WebGL2; tests/web/render.mjs's
# frame task, the lamp live with its shadow map): lit by three.js's own probe grid baked
# in the page (2 extra passes) and by our L2 volume per fragment, at 0.5 and 0.25 m.
# Nothing reaches the dark room but through the wall, so its frame's light is the leak:
# its mean and 99th percentile against the lit room's frame's mean.
set -eu
BIN=$1
OUT=$2
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
mkdir -p "$OUT"
python3 "$ROOT/data/make_scenes.py" --two-rooms "$OUT/two.glb"
for s in 0.5 0.25; do
    "$BIN/gi-bake" -q "$OUT/two.glb" -o "$OUT/two_$s.vdb" --basis sh2 --spacing $s
    "$BIN/vdb-to-gi" -q "$OUT/two_$s.vdb" -o "$OUT/two_$s.gi.gz"
done
# frame NAME ROOM GI GRID: ROOM lit (its corner at x 0.3) or dark (x 7.8); GRID (JSON) or none.
frame() {
    python3 - "$OUT/$1.task.json" "$OUT/two.glb" "$2" "$3" "${4:-}" << 'PY'
import json, sys
lit = sys.argv[3] == "lit"
t = {"scene": sys.argv[2], "gi": sys.argv[4] or None, "perFragment": True, "sky": [0, 0, 0],
     "lamps": [{"position": [2.0, 2.2, 2.0], "color": [1, 1, 1], "intensity": 20.0}],
     "camera": {"position": [0.3, 1.5, 0.3] if lit else [7.8, 1.5, 0.3],
                "target": [3.5, 1.0, 3.5] if lit else [4.6, 1.0, 3.5], "fov": 75, "width": 240, "height": 180}}
if sys.argv[5]:
    t["grid"] = json.loads(sys.argv[5])
json.dump(t, open(sys.argv[1], "w"))
PY
    node "$ROOT/tests/web/render_frame.mjs" "$OUT/$1.task.json" "$OUT/$1" 2> "$OUT/$1.log"
}
for s in 0.5 0.25; do
    grid="{\"box\": {\"min\": [0, 0, 0], \"max\": [8.1, 3, 4]}, \"spacing\": $s, \"bounces\": 2}"
    for room in lit dark; do
        frame "three_${s}_$room" $room "" "$grid"
        frame "ours_${s}_$room" $room "$OUT/two_$s.gi.gz"
    done
done
/usr/bin/python3 - "$OUT" << 'PY'
import os, sys
import numpy as np
out = sys.argv[1]
def frame(name):
    with open(os.path.join(out, name + ".pfm"), "rb") as f:
        f.readline(); w, h = (int(v) for v in f.readline().split()); f.readline()
        rgb = np.frombuffer(f.read(), dtype="<f4").reshape(h, w, 3)
    with open(os.path.join(out, name + ".mask.pfm"), "rb") as f:
        f.readline(); f.readline(); f.readline()
        mask = np.frombuffer(f.read(), dtype="<f4").reshape(h, w, 3)[..., 0] > 0.5
    return rgb.mean(-1)[mask]
print("| light | spacing | lit room's frame, mean | dark room's, mean | its 99th percentile |")
print("|---|---:|---:|---:|---:|")
for who, label in (("three", "three's grid, baked in the page"), ("ours", "our L2 volume")):
    for s in ("0.5", "0.25"):
        lit, dark = frame(f"{who}_{s}_lit"), frame(f"{who}_{s}_dark")
        m = lit.mean()
        print(f"| {label} | {s} m | {m:.4f} | {100 * dark.mean() / m:.3f} % | {100 * np.percentile(dark, 99) / m:.3f} % |")
PY
