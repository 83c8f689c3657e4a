#!/bin/sh
# chart.sh: `make chart`. Sweep rays, eps and spacing on the bundled world (gi-bench sweep),
# keep the CSV tables in docs/data/ and draw docs/img/chart_*.png with gnuplot; run the
# long stability cases (tests/test_stability.c --full) into docs/data/stability.csv.
set -eu
BUILD=${BUILD:-build/release}
OUT=build/chart
mkdir -p "$OUT" docs/data docs/img
"$BUILD/bin/gi-bench" sweep data/world.glb --out "$OUT"
for g in rays size spacing; do
    gnuplot -e "csv='$OUT'; out='docs/img'" "docs/charts/$g.gp"
    cp "$OUT/$g.csv" "docs/data/$g.csv"
done
if ! "$BUILD/tests/test_stability" --full >"$OUT/stability.log"; then
    grep -v '^# ' "$OUT/stability.log" >&2
    exit 1
fi
{
    echo "case,metric,value"
    sed -n 's/^# //p' "$OUT/stability.log"
} >"$OUT/stability.csv"
cp "$OUT/stability.csv" docs/data/stability.csv
echo "chart: docs/img/chart_rays.png, chart_size.png, chart_spacing.png (tables in docs/data/, stability.csv among them)"
