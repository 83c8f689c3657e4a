# size.gp: bytes against error over eps, for both criteria, max level 3, both encodings.
set terminal pngcairo size 900,420 font "sans,10"
set output out."/chart_size.png"
set datafile separator ","
set title "Bundled world, 0.5 m: gzip'd file against error over eps (0 .. 1.6), max level 3"
set logscale x
set grid
set key bottom left
set xlabel "RMSE of the bricks against the filled field (% of mean)"
set ylabel "MB"
dense = system("awk -F, 'NR == 2 { print $7 / 1e6 }' ".csv."/size.csv")
plot csv."/size.csv" using (strcol(1) eq "range" && $3 == 3 && strcol(4) eq "rgbm" ? 100*$8 : 1/0):($6/1e6) with linespoints title "range, RGBM", \
     csv."/size.csv" using (strcol(1) eq "interp" && $3 == 3 && strcol(4) eq "rgbm" ? 100*$8 : 1/0):($6/1e6) with linespoints title "interp, RGBM", \
     csv."/size.csv" using (strcol(1) eq "interp" && $3 == 3 && strcol(4) eq "rgb9e5" ? 100*$8 : 1/0):($6/1e6) with linespoints title "interp, RGB9E5", \
     csv."/size.csv" using (strcol(1) eq "interp" && $3 == 3 && strcol(4) eq "rgbm" ? 100*$8 : 1/0):($5/1e6) with linespoints dt 2 title "interp, RGBM, raw textures", \
     dense + 0 with lines lw 2 title "dense RGBA8 grid (raw)"
