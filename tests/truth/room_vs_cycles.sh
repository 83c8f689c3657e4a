#!/bin/sh
# room_vs_cycles.sh BIN OUTDIR [SAMPLES] [BOUNCES]: gi-bake --model physical
# against Cycles (Debian's blender), the lamp's part and the sky's part apart,
# at each of BOUNCES ("1 2 4 auto" unless given; auto is gi-bake's count until
# converged against Cycles at 64 bounces), at 20 lattice points of
# make_scenes.py --room. Prints a table (ours / Cycles: the ratio of the sums,
# and the RMSE over the points relative to Cycles' mean) and writes
# OUTDIR/room_vs_cycles.csv.
set -eu
BIN=$1
OUT=$2
SAMPLES=${3:-512}
BOUNCES=${4:-1 2 4 auto}
HERE=$(cd "$(dirname "$0")" && pwd)
ROOT=$(cd "$HERE/../.." && pwd)
command -v blender > /dev/null || { echo "room_vs_cycles: no blender (apt install blender)" >&2; exit 2; }
mkdir -p "$OUT"
python3 "$ROOT/data/make_scenes.py" --room "$OUT/room.glb"
# The points: on the 0.5 m lattice (its origin is the scene's corner plus half a step),
# inside the room, from the floor to near the ceiling.
python3 - "$OUT/points.json" << 'EOF'
import json, sys
pts = [[x, y, z] for x in (0.75, 2.25, 3.75, 5.25)
       for y, z in ((0.25, 0.75), (1.25, 2.25), (2.75, 3.75), (0.75, 3.25), (2.25, 1.25))]
json.dump({"points": pts}, open(sys.argv[1], "w"))
EOF
SKY=0.3,0.5,1.0
for part in lamp sky; do
    case $part in
    lamp) flags="--sun-color 0,0,0" ;;
    sky) flags="--sun-color 0,0,0 --lights off --sky $SKY" ;;
    esac
    for n in $BOUNCES; do
        deep=$n
        [ "$n" = auto ] && deep=64
        # shellcheck disable=SC2086
        "$BIN/gi-bake" "$OUT/room.glb" -o "$OUT/${part}_$n.vdb" -q --model physical --bounces $n \
            --rays 8192 --sampling random --spacing 0.5 $flags
        # The path tracer's sky is black for the lamp's part; its lamps are off for the sky's.
        blender -b --factory-startup -P "$HERE/cycles_probes.py" -- "$OUT/room.json" \
            "$OUT/points.json" "$OUT/cycles_${part}_$n.json" --bounces $deep --part $part \
            --sky $SKY --samples "$SAMPLES" --size 128 > "$OUT/cycles_${part}_$n.log" 2>&1
    done
done
/usr/bin/python3 - "$OUT" $BOUNCES << 'EOF'
import json, math, sys
import pyopenvdb as vdb
out = sys.argv[1]
pts = json.load(open(out + "/points.json"))["points"]
rows = ["part,bounces,ratio,rmse_rel"]
print("| part | bounces | ours / Cycles (sum over 20 points) | RMSE / Cycles' mean |")
print("|---|---:|---:|---:|")
for part in ("lamp", "sky"):
    for n in sys.argv[2:]:
        grid = vdb.read(out + "/%s_%s.vdb" % (part, n), "irradiance")
        acc = grid.getConstAccessor()
        ours = []
        for p in pts:
            ijk = grid.transform.worldToIndexCellCentered(tuple(p))
            at = grid.transform.indexToWorld(ijk)
            assert max(abs(at[k] - p[k]) for k in range(3)) < 1e-6, "%s is not a lattice point" % (p,)
            v, on = acc.probeValue(ijk)
            assert on, "no probe at %s" % (p,)
            ours.append(sum(v) / 3.0)
        cyc = [sum(m) / 3.0 for m in json.load(open(out + "/cycles_%s_%s.json" % (part, n)))["means"]]
        mean = sum(cyc) / len(cyc)
        ratio = sum(ours) / sum(cyc)
        rmse = math.sqrt(sum((a - b) ** 2 for a, b in zip(ours, cyc)) / len(cyc)) / mean
        rows.append("%s,%s,%.4f,%.4f" % (part, n, ratio, rmse))
        print("| %s | %s | %.4f | %.2f %% |" % (part, n, ratio, 100 * rmse))
open(out + "/room_vs_cycles.csv", "w").write("\n".join(rows) + "\n")
EOF
