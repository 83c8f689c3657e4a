# rays.gp: error against a 4096-ray reference, and bake time, against rays per probe.
set terminal pngcairo size 900,420 font "sans,10"
set output out."/chart_rays.png"
set datafile separator ","
set multiplot layout 1,2 title "Bundled world, 1 m probes: error and time against rays per probe"
set logscale xy
set grid
set key top right
set xlabel "rays per probe (mean, for adaptive)"
set ylabel "RMSE against the 4096-ray bake (% of mean)"
plot csv."/rays.csv" using 2:(strcol(1) eq "fibonacci" ? 100*$5 : 1/0) with linespoints title "fibonacci (fixed set)", \
     csv."/rays.csv" using 2:(strcol(1) eq "random" ? 100*$5 : 1/0) with linespoints title "random rotation", \
     csv."/rays.csv" using 2:(strcol(1) eq "adaptive" ? 100*$5 : 1/0) with linespoints title "auto (noise 0.1 .. 0.01)"
set ylabel "bake seconds (2 cores)"
set xlabel "RMSE (% of mean)"
set key top right
plot csv."/rays.csv" using (strcol(1) eq "fibonacci" ? 100*$5 : 1/0):4 with linespoints title "fibonacci", \
     csv."/rays.csv" using (strcol(1) eq "random" ? 100*$5 : 1/0):4 with linespoints title "random", \
     csv."/rays.csv" using (strcol(1) eq "adaptive" ? 100*$5 : 1/0):4 with linespoints title "auto"
unset multiplot
