# vdb-to-gi never replaces its input (by name, symlink or hard link), never writes
# one file as two outputs, never replaces a file of another kind, and leaves all
# of its outputs or none: -o is not committed when --slices fails.
"$BIN/gi-bake" -q "$DATA/room.obj" -o in.vdb --rays 16
ln -s in.vdb sym.vdb
ln in.vdb hard.vdb
echo '{"keep": 1}' > keep.json
echo 'newmtl x' > scene.mtl
run() {
    "$BIN/vdb-to-gi" -q "$@" 2>err >/dev/null
    echo "$? $(cat err)"
}
run in.vdb -o in.vdb
run in.vdb -o sym.vdb
run in.vdb -o hard.vdb
run in.vdb -o a.gi.gz --stats a.gi.gz
run in.vdb -o a.gi.gz --stats scene.mtl
run in.vdb -o b.gi.gz --stats keep.json --slices /proc/no/such/dir
cat keep.json
run in.vdb -o c.gi.gz --stats keep.json
head -c 1 keep.json; echo
"$BIN/gi-bake" -q "$DATA/room.obj" -o scene.mtl --rays 16 2>&1; echo "bake over a material: $?"
cat scene.mtl
cmp -s in.vdb hard.vdb && echo "input intact"
ls
