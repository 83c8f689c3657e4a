#!/bin/sh
# bench.sh: `make bench`. On the bundled world and a generated 200 x 200 m world:
# bake throughput against a bare Embree loop over the same rays, then conversion
# size, error and time against reading the .vdb; then gi-lightmap against a
# bare loop over its rays, per pass, and its packing against potpack; then what each method
# gives a surface against the hemisphere truth (gi-bench truth); then the scene's own light on
# the interior (gi-bench lights, truth under the physical model, and Cycles where blender is
# installed: tests/truth/room_vs_cycles.sh, and the frame a player sees against
# Cycles', tests/truth/frame_vs_cycles.sh, and the bundled world's,
# tests/truth/world_frame_vs_cycles.sh); then where the bytes of the
# default volume go on those two and the town (tests/breakdown.py, Debian's
# python3); then the browser runtime's load and frame times in headless
# Chromium (tests/web/bench_web.mjs, docs/web.md), and three.js's own probe grid
# beside ours (tests/web/bench_probe_grid.mjs, tests/truth/thin_wall_frames.sh;
# the room's frame with it against Cycles' is frame_vs_cycles.sh's). Writes
# build/bench/bench.md.
set -eu
BUILD=${BUILD:-build/release}
OUT=build/bench
mkdir -p "$OUT"
[ -f "$OUT/world200.glb" ] || python3 data/make_scenes.py --world 200 "$OUT/world200.glb"
[ -f "$OUT/town.glb" ] || python3 data/make_scenes.py --town "$OUT/town.glb"
[ -f "$OUT/interior.glb" ] || python3 data/make_scenes.py --interior "$OUT/interior.glb"
{
    echo "## gi-bench, $(date -u +%Y-%m-%d), $(nproc) cores: $(sed -n 's/^model name\t: //p' /proc/cpuinfo | head -n 1)"
    echo
    "$BUILD/bin/gi-bench" bake data/world.glb --repeat 3
    "$BUILD/bin/gi-bench" bake "$OUT/world200.glb" --repeat 1
    "$BUILD/bin/gi-bake" -q data/world.glb -o "$OUT/world.vdb" >/dev/null
    "$BUILD/bin/gi-bake" -q "$OUT/world200.glb" -o "$OUT/world200.vdb" >/dev/null
    "$BUILD/bin/gi-bench" convert "$OUT/world.vdb" --repeat 3
    "$BUILD/bin/gi-bench" convert "$OUT/world200.vdb" --repeat 3
    # The L2 terms' conversion against the scalar one of the same probes (docs/directional.md).
    "$BUILD/bin/gi-bake" -q data/world.glb -o "$OUT/world_sh2.vdb" --basis sh2 >/dev/null
    "$BUILD/bin/gi-bench" convert "$OUT/world_sh2.vdb" --repeat 3
    "$BUILD/bin/gi-bake" -q "$OUT/world200.glb" -o "$OUT/world200_sh2.vdb" --basis sh2 >/dev/null
    "$BUILD/bin/gi-bench" convert "$OUT/world200_sh2.vdb" --repeat 1
    # The L2 volumes the browser's load is timed on below.
    "$BUILD/bin/vdb-to-gi" -q "$OUT/world_sh2.vdb" -o "$OUT/world_sh2.gi.gz"
    # and as .gi version 8, the second band in luminance (the default keeps this world's colour)
    "$BUILD/bin/vdb-to-gi" -q "$OUT/world_sh2.vdb" -o "$OUT/world_sh2_v8.gi.gz" --gi-version 8
    "$BUILD/bin/vdb-to-gi" -q "$OUT/world200_sh2.vdb" -o "$OUT/world200_sh2.gi.gz"
    rm -f "$OUT/world_sh2.vdb" "$OUT/world200_sh2.vdb"
    # The 200 m world's L2 volume within issue 39's budget (2x the scalar's VRAM, 21 MB),
    # as --budget chooses it (docs/directional.md, "A budget"), for the load below.
    "$BUILD/bin/gi-bake" -q "$OUT/world200.glb" -o "$OUT/world200_21mb.vdb" --budget 21
    "$BUILD/bin/vdb-to-gi" -q "$OUT/world200_21mb.vdb" -o "$OUT/world200_21mb.gi.gz" --budget 21
    rm -f "$OUT/world200_21mb.vdb"
    "$BUILD/bin/gi-bake" -q "$OUT/town.glb" -o "$OUT/town.vdb" >/dev/null
    echo "### Lightmaps: gi-lightmap against a bare Embree loop, and packing (docs/lightmap.md)"
    echo
    "$BUILD/bin/gi-bench" lightmap data/world.glb --repeat 3 --out "$OUT/lightmap"
    node tests/js/potpack.mjs "$OUT/lightmap/lightmap_boxes.json"
    echo
    "$BUILD/bin/gi-bench" lightmap "$OUT/world200.glb" --repeat 1
    node tests/js/potpack.mjs build/chart/lightmap_boxes.json
    echo
    echo "### What a surface receives, against the hemisphere truth (docs/directional.md)"
    echo
    "$BUILD/bin/gi-bench" truth data/world.glb --out "$OUT/truth"
    echo
    "$BUILD/bin/gi-bench" truth "$OUT/world200.glb" --spacing 0.5 --out "$OUT/truth200"
    echo
    echo "### The scene's own light: cost, bounces and rays (docs/lights.md)"
    echo
    "$BUILD/bin/gi-bench" lights "$OUT/interior.glb" --repeat 2 --out "$OUT/lights"
    echo
    echo "### Every source's light counted alike: against Cycles (docs/lights.md)"
    echo
    if command -v blender > /dev/null; then
        sh tests/truth/room_vs_cycles.sh "$BUILD/bin" "$OUT/cycles"
        echo
        echo "### What a player sees: the runtime's frame against Cycles' (docs/frame.md)"
        sh tests/truth/frame_vs_cycles.sh "$BUILD/bin" "$OUT/frame" 2048
        echo
        echo "### The bundled world's frame against Cycles' (docs/frame.md)"
        sh tests/truth/world_frame_vs_cycles.sh "$BUILD/bin" "$OUT/world_frame" 1024
    else
        echo "(no blender: apt install blender to compare with Cycles)"
    fi
    echo
    "$BUILD/bin/gi-bench" truth "$OUT/interior.glb" --model physical --bounces 3 --spacing 0.25 \
        --rays 1024 --out "$OUT/truth_interior"
    echo
    echo "### Where the bytes go (default conversion; docs/converter.md, section 10)"
    echo
    /usr/bin/python3 -c 'import sys; sys.path.insert(0, "tests"); import breakdown; print(breakdown.HEADER)'
    for w in world world200 town; do
        "$BUILD/bin/vdb-to-gi" -q "$OUT/$w.vdb" -o "$OUT/$w.gi.gz"
        /usr/bin/python3 tests/breakdown.py --row "$w" "$OUT/$w.vdb" "$OUT/$w.gi.gz"
    done
    echo
    echo "### The worker's rebuild: the C reader as WebAssembly against the JavaScript one, in node (docs/web.md)"
    echo
    node tests/web/bench_reader.mjs "bundled, scalar=$OUT/world.gi.gz" "bundled, L2=$OUT/world_sh2.gi.gz" \
        "bundled, L2 version 8=$OUT/world_sh2_v8.gi.gz" "200 m, L2 in 21 MB=$OUT/world200_21mb.gi.gz"
    echo
    echo "### Browser runtime: load and frame time in headless Chromium, SwiftShader (docs/web.md)"
    echo
    if [ -x "${CHROMIUM:-/usr/bin/chromium}" ] && [ -d web/node_modules/puppeteer-core ]; then
        "$BUILD/bin/vdb-to-gi" -q "$OUT/world200.vdb" -o "$OUT/world200.seed.gi.gz" --layout seed
        node tests/web/bench_web.mjs data/world.glb "$OUT/world.gi.gz" \
            "200 m, seed=$OUT/world200.seed.gi.gz" "200 m, compact=$OUT/world200.gi.gz" \
            "bundled, L2=$OUT/world_sh2.gi.gz" "bundled, L2 version 8=$OUT/world_sh2_v8.gi.gz" \
            "200 m, L2=$OUT/world200_sh2.gi.gz" \
            "200 m, L2 in 21 MB=$OUT/world200_21mb.gi.gz"
        echo
        echo "What 16 occluders cost a frame (docs/web.md)"
        echo
        node tests/web/bench_occluders.mjs data/world.glb "$OUT/world.gi.gz"
        echo
        echo "The viewer, as a user sees it: from the volume's load to its first lit frame"
        echo
        node tests/web/bench_viewer.mjs "bundled=data/world.glb,$OUT/world.gi.gz" \
            "200 m=$OUT/world200.glb,$OUT/world200.gi.gz"
        echo
        echo "Our bake through three's own light probe grid (makeProbeGrid), against our runtime (docs/web.md)"
        echo
        "$BUILD/bin/gi-bake" -q "$OUT/interior.glb" -o "$OUT/interior_sh2.vdb" --basis sh2 >/dev/null
        "$BUILD/bin/vdb-to-gi" -q "$OUT/interior_sh2.vdb" -o "$OUT/interior_sh2.gi.gz"
        "$BUILD/bin/vdb-to-gi" -q "$OUT/interior_sh2.vdb" -o "$OUT/interior_v7.gi.gz" --gi-version 7
        "$BUILD/bin/vdb-to-gi" -q "$OUT/interior_sh2.vdb" -o "$OUT/interior_l0.gi.gz" --basis scalar
        # The same probes without their terms: what the L2 terms cost a frame, beside L0's lookup.
        node tests/web/bench_probe_grid.mjs "interior=$OUT/interior.glb,$OUT/interior_sh2.gi.gz" \
            "interior, version 7=$OUT/interior.glb,$OUT/interior_v7.gi.gz" \
            "interior, L0 only=$OUT/interior.glb,$OUT/interior_l0.gi.gz" \
            "world=data/world.glb,$OUT/world_sh2.gi.gz" "200 m world=-,$OUT/world200_sh2.gi.gz"
        echo
        echo "Light through a thin wall in frames: three's own probe grid against our L2 volume (docs/frame.md)"
        echo
        sh tests/truth/thin_wall_frames.sh "$BUILD/bin" "$OUT/thin_wall"
    else
        echo "(skipped: chromium or web/node_modules missing; make deps installs both)"
    fi
    echo
} | tee "$OUT/bench.md"
echo "bench: results in $OUT/bench.md"
