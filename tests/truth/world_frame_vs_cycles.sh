#!/bin/sh
# world_frame_vs_cycles.sh BIN OUTDIR [SAMPLES]: the bundled outdoor world's frame
# against a converged path tracer (issue 45, item 4), as frame_vs_cycles.sh does for
# the room: Cycles (Debian's blender, its glTF importer, diffuse only, 64 bounces,
# SAMPLES a pixel; the bakers' default sun, a black sky) against the runtime's frame in
# headless Chromium (WebGL2, the sun a three.js DirectionalLight with a shadow map, read
# back as linear floats) for each recipe below; bias and RMSE over every surface pixel,
# those in the sun and those in its shadow (where Cycles' direct light, rendered apart,
# is under 2 % of its whole), into a table, OUTDIR/frame_vs_cycles.csv and pictures.
set -eu
BIN=$1
OUT=$2
SAMPLES=${3:-512}
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
command -v blender > /dev/null || { echo "world_frame_vs_cycles: no blender (apt install blender)" >&2; exit 2; }
mkdir -p "$OUT"
WORLD=$ROOT/data/world.glb
# From over the south end down the canyon: the buildings, the trees, the blue wall, their
# shadows on the grass, and a canyon wall.
cat > "$OUT/frame.json" << 'EOF'
{"camera": {"position": [0, 12, 22], "target": [0, 0, -2], "fov": 60, "width": 320, "height": 240},
 "sun": {"direction": [0.4, 0.8, 0.3], "color": [1, 1, 1]}, "sky": [0, 0, 0]}
EOF
cycles() {
    blender -b --factory-startup -P "$HERE/cycles_gltf_frame.py" -- "$WORLD" "$OUT/frame.json" "$OUT/$1.exr" \
        --bounces "$2" --samples "$SAMPLES" --sun 0.4,0.8,0.3 --sun-color 1,1,1 > "$OUT/$1.log" 2>&1
}
[ -f "$OUT/cycles.pfm" ] || cycles cycles 64
[ -f "$OUT/cycles_direct.pfm" ] || cycles cycles_direct 1
# Everything at its default: the package README's split (the lightmap on the statics)
# and the volume alone as light() reads it; the same two under the seed model, the
# defaults before issue 45 (its volume per vertex, as then); the volume alone with L2 terms
# (--basis sh2); and no bounce light at all.
"$BIN/gi-lightmap" "$WORLD" -o "$OUT/default-lit.glb" -q
"$BIN/gi-bake" "$WORLD" -o "$OUT/default.vdb" -q
"$BIN/vdb-to-gi" "$OUT/default.vdb" -o "$OUT/default.gi.gz" -q
"$BIN/gi-bake" "$WORLD" -o "$OUT/l2.vdb" -q --basis sh2
"$BIN/vdb-to-gi" "$OUT/l2.vdb" -o "$OUT/l2.gi.gz" -q
"$BIN/gi-lightmap" "$WORLD" -o "$OUT/seed-lit.glb" -q --model seed
"$BIN/gi-bake" "$WORLD" -o "$OUT/seed.vdb" -q --model seed
"$BIN/vdb-to-gi" "$OUT/seed.vdb" -o "$OUT/seed.gi.gz" -q
# task NAME LIGHTMAP GI PERFRAGMENT: a frame of ours.
task() {
    python3 - "$OUT/frame.json" "$OUT/$1.task.json" "$WORLD" "$2" "$3" "$4" << 'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t = {"scene": sys.argv[3], "lightmap": sys.argv[4] or None, "gi": sys.argv[5] or None,
     "perFragment": {"1": True, "0": False}.get(sys.argv[6], sys.argv[6]), "occluders": False,
     "spheres": [], "lamps": [], "camera": s["camera"], "sky": s["sky"], "sun": s["sun"]}
json.dump(t, open(sys.argv[2], "w"))
PY
    node "$ROOT/tests/web/render_frame.mjs" "$OUT/$1.task.json" "$OUT/$1" 2> "$OUT/$1.log"
}
task defaults "$OUT/default-lit.glb" "$OUT/default.gi.gz" 1
task defaults_volume "" "$OUT/default.gi.gz" auto
task l2_volume "" "$OUT/l2.gi.gz" auto
task seed_split "$OUT/seed-lit.glb" "$OUT/seed.gi.gz" 1
task seed_volume "" "$OUT/seed.gi.gz" 0
task no_bounce "" "" 0
/usr/bin/python3 "$HERE/frame_regions.py" "$OUT" defaults defaults_volume l2_volume seed_split seed_volume \
    no_bounce
