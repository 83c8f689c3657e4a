#!/bin/sh
# frame_vs_cycles.sh BIN OUTDIR [SAMPLES]: what a player sees, against a
# converged path tracer (issue 45). make_scenes.py --room (a 6 x 4 x 3 m room,
# a window, a red wall, a 20 cd lamp; a blue sky) with a 0.4 m sphere on the
# floor that is not in the bake, seen by one camera: Cycles' frame (Debian's
# blender, diffuse only, 64 bounces, SAMPLES a pixel; kept in OUTDIR and
# reused) against the runtime's frame in headless Chromium (WebGL2, read
# back as linear floats) for each recipe below; bias and RMSE per region
# (tests/truth/frame_regions.py) into a table and OUTDIR/frame_vs_cycles.csv,
# and a picture of both frames and the error (OUTDIR/frame_*.png).
set -eu
BIN=$1
OUT=$2
SAMPLES=${3:-512}
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
command -v blender > /dev/null || { echo "frame_vs_cycles: no blender (apt install blender)" >&2; exit 2; }
mkdir -p "$OUT"
SKY=0.3,0.5,1.0
python3 "$ROOT/data/make_scenes.py" --room "$OUT/room.glb"
# The moving sphere (on the floor, 2.2 m from under the lamp, so that its lamp shadow
# reaches out from under it) and the view (from above the lamp's side, steeply, so that
# the shadow shows beyond the sphere; the red wall and the window in view).
python3 - "$OUT/room.json" "$OUT/frame.json" "$SKY" << 'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["spheres"] = [{"center": [1.5, 0.2, 1.6], "radius": 0.2, "albedo": [0.7, 0.7, 0.7]}]
scene["camera"] = {"position": [3.6, 2.7, 3.5], "target": [1.3, 0.2, 1.3], "fov": 60,
                   "width": 320, "height": 240}
scene["sky"] = [float(c) for c in sys.argv[3].split(",")]
json.dump(scene, open(sys.argv[2], "w"))
PY
if [ ! -f "$OUT/cycles.pfm" ]; then
    blender -b --factory-startup -P "$HERE/cycles_frame.py" -- "$OUT/frame.json" "$OUT/cycles.exr" \
        --bounces 64 --sky "$SKY" --samples "$SAMPLES" > "$OUT/cycles.log" 2>&1
fi
# The bakes. Everything at its default, with only --sky (the one thing a glTF cannot
# carry): the package README's split (the lightmap on the statics, the scalar volume for
# what moves) and the volume alone, read as light() chooses; the split docs/frame.md
# recommends (lightmap texels of 0.1 m, an L2 volume at 0.25 m), its lightmap also at 256
# rays a texel; and the seed model, the defaults before issue 45, read per vertex.
"$BIN/gi-lightmap" "$OUT/room.glb" -o "$OUT/default-lit.glb" -q --sky "$SKY"
"$BIN/gi-bake" "$OUT/room.glb" -o "$OUT/default.vdb" -q --sky "$SKY"
"$BIN/vdb-to-gi" "$OUT/default.vdb" -o "$OUT/default.gi.gz" -q
"$BIN/gi-lightmap" "$OUT/room.glb" -o "$OUT/lit.glb" -q --texel 0.1 --sky "$SKY"
"$BIN/gi-lightmap" "$OUT/room.glb" -o "$OUT/lit256.glb" -q --texel 0.1 --sky "$SKY" --rays 256
"$BIN/gi-bake" "$OUT/room.glb" -o "$OUT/l2.vdb" -q --basis sh2 --spacing 0.25 --sky "$SKY"
"$BIN/vdb-to-gi" "$OUT/l2.vdb" -o "$OUT/l2.gi.gz" -q
"$BIN/gi-bake" "$OUT/room.glb" -o "$OUT/seed.vdb" -q --model seed --sky "$SKY"
"$BIN/vdb-to-gi" "$OUT/seed.vdb" -o "$OUT/seed.gi.gz" -q
# task NAME LIGHTMAP GI PERFRAGMENT OCCLUDERS [GRID]: a frame of ours; GRID (JSON) lights it
# through three's own LightProbeGridWebGL instead (tests/web/render.mjs, the frame task).
task() {
    python3 - "$OUT/frame.json" "$OUT/$1.task.json" "$OUT/room.glb" "$2" "$3" "$4" "$5" "${6:-}" << 'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t = {"scene": sys.argv[3], "lightmap": sys.argv[4] or None, "gi": sys.argv[5] or None,
     "perFragment": {"1": True, "0": False}.get(sys.argv[6], sys.argv[6]), "occluders": sys.argv[7] == "1",
     "spheres": s["spheres"], "camera": s["camera"], "sky": s["sky"],
     "lamps": [{"position": l["position"], "color": l["color"], "intensity": l["intensity"]} for l in s["lamps"]]}
if sys.argv[8]:
    t["grid"] = json.loads(sys.argv[8])
json.dump(t, open(sys.argv[2], "w"))
PY
    node "$ROOT/tests/web/render_frame.mjs" "$OUT/$1.task.json" "$OUT/$1" 2> "$OUT/$1.log"
}
task defaults "$OUT/default-lit.glb" "$OUT/default.gi.gz" 1 1
task defaults_volume "" "$OUT/default.gi.gz" auto 0
task split "$OUT/lit.glb" "$OUT/l2.gi.gz" 1 1
task split_256_rays "$OUT/lit256.glb" "$OUT/l2.gi.gz" 1 1
task split_no_occluders "$OUT/lit256.glb" "$OUT/l2.gi.gz" 1 0
task seed_defaults "" "$OUT/seed.gi.gz" 0 0
# Three.js's own probe grid (three 0.187, issue 46) over the room at the L2 volume's 0.25 m:
# baked in the page as three's docs do, with 2 extra passes (3 bounces) and with 12; and
# filled from our L2 volume (makeProbeGrid), beside that volume read by our runtime.
ROOM_BOX='"box": {"min": [0, 0, 0], "max": [6, 3, 4]}, "spacing": 0.25'
task three_grid_3_passes "" "" 0 0 "{$ROOM_BOX, \"bounces\": 2}"
task three_grid_13_passes "" "" 0 0 "{$ROOM_BOX, \"bounces\": 12}"
task l2_volume "" "$OUT/l2.gi.gz" 1 0
task l2_through_three_grid "" "$OUT/l2.gi.gz" 1 0 "{$ROOM_BOX, \"fromVolume\": true}"
/usr/bin/python3 "$HERE/frame_regions.py" "$OUT" defaults defaults_volume split split_256_rays \
    split_no_occluders seed_defaults three_grid_3_passes three_grid_13_passes l2_volume l2_through_three_grid
# The time to a first lit frame: the volume's load, or the grid's bake or fill.
for f in defaults l2_volume three_grid_3_passes three_grid_13_passes l2_through_three_grid; do
    echo "$f: $(cat "$OUT/$f.json")"
done
