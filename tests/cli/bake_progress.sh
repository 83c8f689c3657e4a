# On a terminal, a bake over a second shows a \r progress line (done, rate, time left);
# -q silences it, and without a terminal there is none. script(1) provides the terminal.
script -qec "'$BIN/gi-bake' '$DATA/world.glb' -o a.vdb --rays 100 --threads 1 >/dev/null" /dev/null >tty.txt
tr '\r' '\n' <tty.txt | grep -m 1 -o 'gi-bake: baking *[0-9]*%  [0-9]*/[0-9]* probes  [0-9.]*k probes/s  [0-9]* s left' |
    sed 's/[0-9][0-9.]*/N/g; s/  */ /g'
script -qec "'$BIN/gi-bake' -q '$DATA/world.glb' -o b.vdb --rays 100 --threads 1 >/dev/null" /dev/null >quiet.txt
echo "quiet: $(wc -c <quiet.txt) bytes"
"$BIN/gi-bake" "$DATA/world.glb" -o c.vdb --rays 100 --threads 1 2>notty.txt >/dev/null
echo "no terminal: $(wc -c <notty.txt) bytes"
