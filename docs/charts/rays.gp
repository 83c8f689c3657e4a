# rays.gp: error against a 16384-ray reference, and bake time, against rays per probe
# (gi-bench rays) or per texel (gi-bench texel-rays). Variables: csv (the table), out (the
# PNG), name (the chart's title), what (probe or texel; probe if not given).
if (!exists("what")) what = "probe"
set terminal pngcairo size 900,420 font "sans,10"
set output out
set datafile separator ","
set multiplot layout 1,2 title name.": error and time against rays per ".what
set logscale xy
set grid
set key top right
set xlabel "rays per ".what." (mean, for auto)"
set ylabel "RMSE against the 16384-ray bake (% of mean)"
plot csv using 2:(strcol(1) eq "fibonacci" ? 100*$5 : 1/0) with linespoints title "fibonacci (fixed set)", \
     csv using 2:(strcol(1) eq "random" ? 100*$5 : 1/0) with linespoints title "random rotation", \
     csv using 2:(strcol(1) eq "adaptive" ? 100*$5 : 1/0) with linespoints title "auto (noise 0.14 .. 0.018)", \
     csv using 2:(strcol(1) eq "oracle" ? 100*$5 : 1/0) with points pt 7 ps 1.5 title "best split of rays (oracle)"
set ylabel (what eq "texel" ? "one pass's seconds (2 cores)" : "bake seconds (2 cores)")
set xlabel "RMSE (% of mean)"
set key top right
plot csv using (strcol(1) eq "fibonacci" ? 100*$5 : 1/0):4 with linespoints title "fibonacci", \
     csv using (strcol(1) eq "random" ? 100*$5 : 1/0):4 with linespoints title "random", \
     csv using (strcol(1) eq "adaptive" ? 100*$5 : 1/0):4 with linespoints title "auto"
unset multiplot
