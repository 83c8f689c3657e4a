# lights.gp: the interior's error against rays per probe, one curve per bounce count,
# against 8 bounces of 4096 rays (gi-bench lights), and against bake seconds.
set terminal pngcairo size 900,420 font "sans,10"
set output out."/chart_lights.png"
set datafile separator ","
set multiplot layout 1,2 title "Interior, physical model with a sky map: error against rays and bounces"
set logscale x
set grid
set key top right
set xlabel "rays per probe"
set ylabel "RMSE against 8 bounces of 4096 rays (% of mean)"
set yrange [0:*]
plot for [b in "1 2 3 4 6"] csv."/lights.csv" using 2:(column(1) == b+0 ? 100*$3 : 1/0) \
     with linespoints title b." bounce".(b eq "1" ? "" : "s")
set xlabel "seconds for 400 probes (2 cores)"
plot for [b in "1 2 3 4 6"] csv."/lights.csv" using 5:(column(1) == b+0 ? 100*$3 : 1/0) \
     with linespoints title b." bounce".(b eq "1" ? "" : "s")
unset multiplot
