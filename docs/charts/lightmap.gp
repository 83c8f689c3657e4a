# lightmap.gp: memory against the error at surface receivers, lightmap against
# probe volume, on one world.
# gnuplot -e "lm='lightmap.csv'; mem='memory.csv'; out='PNG'; name='WORLD'" lightmap.gp
# lightmap.csv (gi-bench lightmap): 1 texel, 4 vram, 7 receiver RMSE.
# memory.csv (gi-bench memory): 1 spacing, 2 layout, 3 basis, 4 eps, 6 vram,
# 14 surface RMSE; the compact layout at the default eps 0.1, scalar and with L2
# terms, and the dense grid. Every error against the hemisphere truth.
set terminal pngcairo size 900,600 font "sans,10"
set output out
set datafile separator ","
set title name.": memory against the error at surface receivers, against the hemisphere truth"
set logscale xy
set grid
set key bottom right font ",9"
set xlabel "RMSE at surface receivers (% of mean)"
set ylabel "VRAM, MB (lightmap: 4 bytes a texel of its atlas)"
set xrange [2:2000]
set yrange [*:*]
# Rows of one method, through awk, so each draws as one connected line.
rows(l, c, e) = sprintf("< awk -F, '$2 == \"%s\" && $3 == \"%s\" && $4 == %g' %s", l, c, e, mem)
plot lm using (100 * $7):($4 / 1e6) with linespoints lc rgb "#d95f02" pt 7 lw 2 title "lightmap, a pass a bounce (texels 1, 0.5, 0.25, 0.125 m)", \
     lm using (100 * $7):($4 / 1e6):(sprintf("%g m", $1)) with labels offset 1.2, 0.8 font ",9" notitle, \
     rows("compact", "L2", 0.1) using (100 * $14):($6 / 1e6) with linespoints lc rgb "#1b9e77" pt 5 lw 2 title "probe volume with L2 terms, compact, eps 0.1 (spacing 0.25, 0.5, 1 m)", \
     rows("compact", "L2", 0.1) using (100 * $14):($6 / 1e6):(sprintf("%g m", $1)) with labels offset 2.5, 0 font ",9" tc rgb "#1b9e77" notitle, \
     rows("compact", "scalar", 0.1) using (100 * $14):($6 / 1e6) with linespoints lc rgb "#7570b3" pt 5 title "probe volume, scalar (seed 000), compact, eps 0.1", \
     rows("dense", "scalar", 0) using (100 * $14):($6 / 1e6) with linespoints lc rgb "#000000" pt 9 title "probe volume, dense RGBM grid, scalar"
