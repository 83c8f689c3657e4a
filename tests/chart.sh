#!/bin/sh
# chart.sh: `make chart`. Sweep rays, eps and spacing on the bundled world (gi-bench sweep),
# keep the CSV tables in docs/data/ and draw docs/img/chart_*.png with gnuplot.
set -eu
BUILD=${BUILD:-build/release}
OUT=build/chart
mkdir -p "$OUT" docs/data docs/img
"$BUILD/bin/gi-bench" sweep data/world.glb --out "$OUT"
for g in rays size spacing; do
    gnuplot -e "csv='$OUT'; out='docs/img'" "docs/charts/$g.gp"
    cp "$OUT/$g.csv" "docs/data/$g.csv"
done
echo "chart: docs/img/chart_rays.png, chart_size.png, chart_spacing.png (tables in docs/data/)"
