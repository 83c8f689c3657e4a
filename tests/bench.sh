#!/bin/sh
# bench.sh: `make bench`. Bake throughput against a bare Embree loop over the same rays,
# on the bundled world and on a generated 200 x 200 m world; writes build/bench/bench.md.
set -eu
BUILD=${BUILD:-build/release}
OUT=build/bench
mkdir -p "$OUT"
[ -f "$OUT/world200.glb" ] || python3 data/make_scenes.py --world 200 "$OUT/world200.glb"
{
    echo "## gi-bench bake, $(date -u +%Y-%m-%d), $(nproc) cores: $(sed -n 's/^model name\t: //p' /proc/cpuinfo | head -n 1)"
    echo
    "$BUILD/bin/gi-bench" bake data/world.glb --repeat 3
    "$BUILD/bin/gi-bench" bake "$OUT/world200.glb" --repeat 1
} | tee "$OUT/bench.md"
echo "bench: results in $OUT/bench.md"
