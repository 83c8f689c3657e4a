# Inputs that are not regular files are refused before any library reads them:
# a FIFO (which would block forever), a directory, and a texture that is a device.
mkfifo scene.obj
mkdir dir.obj
run() {
    timeout 10 "$@" 2>err >/dev/null
    echo "$? $(cat err)"
}
run "$BIN/gi-bake" scene.obj -o a.vdb
run "$BIN/gi-bake" dir.obj -o a.vdb
run "$BIN/vdb-to-gi" scene.obj -o a.gi.gz
run "$BIN/gi-inspect" scene.obj
printf 'newmtl z\nmap_Kd /dev/zero\n' > z.mtl
printf 'mtllib z.mtl\nv 0 0 0\nv 1 0 0\nv 1 0 -1\nvt 0 0\nvt 1 0\nvt 1 1\nusemtl z\nf 1/1 2/2 3/3\n' > z.obj
run "$BIN/gi-bake" z.obj -o z.vdb --spacing 2 --rays 8
ls *.vdb
