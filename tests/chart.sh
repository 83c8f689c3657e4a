#!/bin/sh
# chart.sh: `make chart`. Sweep rays, eps and spacing on the bundled world (gi-bench sweep),
# rays on the interior too (and with ALL=1 the bundled world under the physical model
# and the 200 m world: gi-bench rays), rays a texel on both (gi-bench texel-rays),
# keep the CSV tables in docs/data/ and draw docs/img/chart_*.png with gnuplot; run the
# long stability cases (tests/test_stability.c --full) into docs/data/stability.csv;
# then memory against the error a player sees (gi-bench memory) on the bundled
# world, and with ALL=1 on the 200 m world and the town too (about 40 minutes
# on 2 cores), into docs/data/memory_*.csv and docs/img/chart_memory_*.png; and
# lightmap against probe volume at surface receivers (gi-bench lightmap), on the bundled world
# and the interior (with ALL=1 the 200 m world and the town too); and the interior's
# error against rays and bounces (gi-bench lights).
set -eu
BUILD=${BUILD:-build/release}
OUT=build/chart
mkdir -p "$OUT" docs/data docs/img
"$BUILD/bin/gi-bench" sweep data/world.glb --out "$OUT"
for g in size spacing; do
    gnuplot -e "csv='$OUT'; out='docs/img'" "docs/charts/$g.gp"
    cp "$OUT/$g.csv" "docs/data/$g.csv"
done
cp "$OUT/rays.csv" docs/data/rays.csv
gnuplot -e "csv='docs/data/rays.csv'; out='docs/img/chart_rays.png'; name='Bundled world, 1 m probes'" \
    docs/charts/rays.gp
if ! "$BUILD/tests/test_stability" --full >"$OUT/stability.log"; then
    grep -v '^# ' "$OUT/stability.log" >&2
    exit 1
fi
{
    echo "case,metric,value"
    sed -n 's/^# //p' "$OUT/stability.log"
} >"$OUT/stability.csv"
cp "$OUT/stability.csv" docs/data/stability.csv
"$BUILD/bin/gi-bench" memory data/world.glb --out "$OUT"
cp "$OUT/memory.csv" docs/data/memory_world.csv
# Lightmap against probe volume at the same surface receivers (docs/lightmap.md).
"$BUILD/bin/gi-bench" lightmap data/world.glb --repeat 1 --out "$OUT" >/dev/null
cp "$OUT/lightmap.csv" docs/data/lightmap_world.csv
# The interior, lit by its lamps and window: the physical model, three bounces (the
# lightmap three passes), both for the methods and for the truth.
[ -f build/bench/interior.glb ] || python3 data/make_scenes.py --interior build/bench/interior.glb
"$BUILD/bin/gi-bench" memory build/bench/interior.glb --model physical --bounces 3 --out "$OUT" >/dev/null
cp "$OUT/memory.csv" docs/data/memory_interior.csv
"$BUILD/bin/gi-bench" lightmap build/bench/interior.glb --model physical --bounces 3 --repeat 1 \
    --out "$OUT" >/dev/null
cp "$OUT/lightmap.csv" docs/data/lightmap_interior.csv
# Rays where they pay (docs/performance.md): the interior's probes at 0.5 m, three bounces.
"$BUILD/bin/gi-bench" rays build/bench/interior.glb --model physical --bounces 3 --spacing 0.5 \
    --out "$OUT" >/dev/null
cp "$OUT/rays.csv" docs/data/rays_interior.csv
gnuplot -e "csv='docs/data/rays_interior.csv'; out='docs/img/chart_rays_interior.png'; name='Interior, 0.5 m probes, physical, 3 bounces'" \
    docs/charts/rays.gp
# Rays a texel (docs/lightmap.md): one pass of 0.5 m texels, the bundled world and the interior.
for w in world interior; do
    scene=data/world.glb
    [ $w = interior ] && scene=build/bench/interior.glb
    "$BUILD/bin/gi-bench" texel-rays $scene --model physical --out "$OUT" >/dev/null
    cp "$OUT/texel_rays.csv" docs/data/texel_rays_$w.csv
    gnuplot -e "csv='docs/data/texel_rays_$w.csv'; out='docs/img/chart_texel_rays_$w.png'; name='$w, 0.5 m texels, physical, one pass'; what='texel'" \
        docs/charts/rays.gp
done
# The scene's own light: error against rays and bounces on the interior (docs/lights.md).
"$BUILD/bin/gi-bench" lights build/bench/interior.glb --repeat 1 --out "$OUT" >/dev/null
cp "$OUT/lights.csv" docs/data/lights.csv
gnuplot -e "csv='docs/data'; out='docs/img'" docs/charts/lights.gp
if [ "${ALL:-0}" = 1 ]; then
    [ -f build/bench/world200.glb ] || python3 data/make_scenes.py --world 200 build/bench/world200.glb
    [ -f build/bench/town.glb ] || python3 data/make_scenes.py --town build/bench/town.glb
    "$BUILD/bin/gi-bench" memory build/bench/world200.glb --out "$OUT"
    cp "$OUT/memory.csv" docs/data/memory_world200.csv
    : >"$OUT/memory_town.csv"
    for s in 0.25 0.5 1; do
        "$BUILD/bin/gi-bench" memory build/bench/town.glb --out "$OUT" --spacing $s
        if [ -s "$OUT/memory_town.csv" ]; then tail -n +2 "$OUT/memory.csv"; else cat "$OUT/memory.csv"; fi \
            >>"$OUT/memory_town.csv"
    done
    cp "$OUT/memory_town.csv" docs/data/memory_town.csv
    "$BUILD/bin/gi-bench" rays data/world.glb --model physical --bounces 3 --out "$OUT" >/dev/null
    cp "$OUT/rays.csv" docs/data/rays_world_physical.csv
    gnuplot -e "csv='docs/data/rays_world_physical.csv'; out='docs/img/chart_rays_world_physical.png'; name='Bundled world, 1 m probes, physical, 3 bounces'" \
        docs/charts/rays.gp
    "$BUILD/bin/gi-bench" rays build/bench/world200.glb --spacing 2 --out "$OUT" >/dev/null
    cp "$OUT/rays.csv" docs/data/rays_world200.csv
    gnuplot -e "csv='docs/data/rays_world200.csv'; out='docs/img/chart_rays_world200.png'; name='Generated 200 m world, 2 m probes'" \
        docs/charts/rays.gp
    for w in world200 town; do
        "$BUILD/bin/gi-bench" lightmap build/bench/$w.glb --repeat 1 --out "$OUT" >/dev/null
        cp "$OUT/lightmap.csv" docs/data/lightmap_$w.csv
    done
fi
for w in world:"Bundled 48 m world" world200:"Generated 200 m world" town:"Town, 200 x 60 x 200 m" \
    interior:"Interior, two rooms (physical model, 3 bounces)"; do
    f=docs/data/memory_${w%%:*}.csv
    [ -f "$f" ] && gnuplot -e "csv='$f'; out='docs/img/chart_memory_${w%%:*}.png'; name='${w#*:}'" docs/charts/memory.gp
    l=docs/data/lightmap_${w%%:*}.csv
    # The town's memory rows hold 0.25, 0.5 and 1 m in one file, as the others do.
    [ -f "$f" ] && [ -f "$l" ] && gnuplot -e "lm='$l'; mem='$f'; out='docs/img/chart_lightmap_${w%%:*}.png'; name='${w#*:}'" docs/charts/lightmap.gp
done
echo "chart: docs/img/chart_rays*.png, chart_size.png, chart_spacing.png, chart_memory_*.png, chart_lightmap_*.png (tables in docs/data/, stability.csv among them)"
