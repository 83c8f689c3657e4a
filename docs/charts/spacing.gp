# spacing.gp: probes, bytes and the error receivers see, against probe spacing.
set terminal pngcairo size 900,420 font "sans,10"
set output out."/chart_spacing.png"
set datafile separator ","
set multiplot layout 1,2 title "Bundled world: what spacing costs and buys (default bake and conversion)"
set logscale xy
set grid
set xlabel "probe spacing (m)"
set key top right
set ylabel "MB, or seconds"
plot csv."/spacing.csv" using 1:($5/1e6) with linespoints title "gzip'd .gi", \
     csv."/spacing.csv" using 1:($13/1e6) with linespoints title "gzip'd .gi, compact layout", \
     csv."/spacing.csv" using 1:($6/1e6) with linespoints title "dense RGBA8 grid", \
     csv."/spacing.csv" using 1:3 with linespoints title "bake seconds"
unset logscale y
set ylabel "surface RMSE against the hemisphere truth (% of mean)"
set key bottom left
# The scalar volume read at a surface: one colour a probe, whose error grows as the
# lattice nears the surfaces (docs/directional.md).
plot csv."/spacing.csv" using 1:(100*$8) with linespoints title "RMSE, scalar volume (defaults)", \
     csv."/spacing.csv" using 1:(100*$10) with linespoints dashtype 2 title "RMSE, --fill mean"
unset multiplot
