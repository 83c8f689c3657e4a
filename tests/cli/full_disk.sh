# A full disk: every kind of output fails with exit 1 and one line saying so, an
# existing file keeps its bytes, and no temporary file is left (a small tmpfs).
[ "$(id -u)" = 0 ] || { echo "needs root to mount a tmpfs"; exit 77; }
mkdir disk
mount -t tmpfs -o size=512k,nr_inodes=64 tmpfs disk 2>/dev/null || { echo "cannot mount a tmpfs here"; exit 77; }
trap 'umount disk' EXIT
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --basis ambient-cube --rays 16 >/dev/null || echo "bake failed"
# Older outputs of each kind: their magic, then "good".
printf ' BDVgood' > disk/a.vdb
printf '\037\213good' > disk/a.gi.gz
printf '\253KTXgood' > disk/a.ktx2
printf '\211PNGgood' > disk/a.png
printf '{good' > disk/a.json
mkdir disk/sl
cat /dev/zero > disk/filler 2>/dev/null # no block left
run() {
    "$@" >/dev/null 2>err
    echo "$? $(sed 's/\.tmp-[A-Za-z0-9-]*//' err)"
}
run "$BIN/gi-bake" -q "$DATA/room.obj" -o disk/a.vdb --rays 16
run "$BIN/vdb-to-gi" -q room.vdb -o disk/a.gi.gz
run "$BIN/vdb-to-gi" -q room.vdb --bevy disk/a.ktx2
run "$BIN/vdb-to-gi" -q room.vdb --bevy-baked-gi disk/a.png
run "$BIN/vdb-to-gi" -q room.vdb -o b.gi.gz --stats disk/a.json
run "$BIN/vdb-to-gi" -q room.vdb -o c.gi.gz --slices disk/sl
for f in a.vdb a.gi.gz a.ktx2 a.png a.json; do echo "$f: $(tail -c 4 "disk/$f")"; done
ls disk disk/sl
