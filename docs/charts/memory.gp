# memory.gp: memory against the error a player sees (gi-bench memory), one world.
# gnuplot -e "csv='DIR/memory.csv'; out='PNG'; name='WORLD'" memory.gp
# Columns: 1 spacing, 2 layout, 3 basis, 4 eps, 6 vram, 7 file, 14 surface RMSE,
# 16 character RMSE, both against the hemisphere truth. Each line is one method at
# one spacing over eps (dense: one point a spacing); point shapes tell the spacings apart.
set terminal pngcairo size 1100,760 font "sans,10"
set output out
set datafile separator ","
set multiplot layout 2,2 title name.": memory against the error a player sees, against the hemisphere truth (0.25, 0.5, 1 m; eps 0.05 .. 0.4)"
set logscale xy
set grid
set key top right font ",9"
methods = "dense,scalar seed,scalar compact,scalar dense,L2 compact,L2 compact,L2-8bit"
label(m) = m eq "dense,scalar" ? "dense RGBM grid, scalar" : m eq "seed,scalar" ? "seed layout, scalar" : \
           m eq "compact,scalar" ? "compact, scalar" : m eq "dense,L2" ? "dense grid, L2" : \
           m eq "compact,L2" ? "compact, L2 (terms 6 bits)" : "compact, L2 (terms 8 bits)"
colour(i) = word("#000000 #d95f02 #1b9e77 #7570b3 #e7298a #66a61e", i)
pick(m, s) = (strcol(2).",".strcol(3) eq m && $1 == s)
spacings = "0.25 0.5 1"
do for [panel = 1:4] {
    col = panel <= 2 ? 16 : 14
    ycol = panel % 2 ? 6 : 7
    set xlabel (col == 16 ? "character layer RMSE, six normals (% of mean)" \
                          : "surface RMSE, each with its normal (% of mean)")
    set ylabel (ycol == 6 ? "VRAM, MB" : "gzip'd file, MB")
    set yrange [*:*]
    if (panel > 1) { unset key }
    plot for [i = 1:6] for [j = 1:3] csv using (pick(word(methods, i), word(spacings, j) + 0) ? 100 * column(col) : 1/0):(column(ycol) / 1e6) \
         with linespoints lc rgb colour(i) pt (j == 1 ? 7 : j == 2 ? 5 : 9) ps 0.8 \
         title (j == 1 ? label(word(methods, i)) : "")
}
unset multiplot
