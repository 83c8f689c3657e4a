# Bad scenes and outputs: one line naming the problem, exit 1, no output file.
printf 'not a model\n' > garbage.glb
printf '# no faces\nv 0 0 0\n' > empty.obj
printf 'v nan 0 0\nv 1 0 0\nv 1 0 -1\nf 1 2 3\n' > nan.obj
touch file
run() {
    "$BIN/gi-bake" "$@" 2>err >/dev/null
    echo "$? $(cat err)"
}
run missing.glb -o out.vdb
run garbage.glb -o out.vdb
run empty.obj -o out.vdb
run nan.obj -o out.vdb
run "$DATA/room.obj" -o file/out.vdb
run "$DATA/room.obj" -o no/such/dir/out.vdb
run "$DATA/room.obj" -o out.vdb --max-probes 100
run "$DATA/room.obj" -o out.vdb --spacing 0.001
ls
