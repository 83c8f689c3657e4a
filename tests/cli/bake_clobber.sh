# A failed bake never replaces an existing output; a good one does; the scene is never the output.
cp "$DATA/room.obj" "$DATA/room.mtl" "$DATA/floor.png" .
printf ' BDV precious' > out.vdb # an older .vdb's magic, then its data
"$BIN/gi-bake" room.obj -o out.vdb --max-probes 10 2>/dev/null
echo "failed: $? $(tail -c 8 out.vdb)"
"$BIN/gi-bake" room.obj -o room.obj 2>&1
echo "self: $? $(head -c 6 room.obj)"
"$BIN/gi-bake" -q room.obj -o out.vdb >/dev/null
echo "good: $? magic $(head -c 8 out.vdb | od -An -tx1 | tr -d ' ')"
vdb_print out.vdb >/dev/null && echo "vdb_print reads it"
ls
