# vdb-to-gi writes the same bytes at any thread count: the packing's bands of
# planes and ranges of bricks, at 1, 2 and 7 threads, both layouts and encodings.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --rays 16 >/dev/null
for run in rgbm,compact rgb9e5,compact rgbm,seed; do
    for t in 1 2 7; do
        "$BIN/vdb-to-gi" -q world.vdb -o t$t.gi.gz --encoding ${run%,*} --layout ${run#*,} --threads $t
    done
    cmp t1.gi.gz t2.gi.gz && cmp t1.gi.gz t7.gi.gz && echo "$run: identical at 1, 2 and 7 threads"
done
