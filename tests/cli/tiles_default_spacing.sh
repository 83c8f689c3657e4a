# run: early (among the slowest, so started first)
# Tiles equal the whole bake at the default spacing (issue 41): the bundled world at 0.5 m
# with L2 terms in 2, 5 and 8 tiles, with rays by each probe's spread (auto: 32 or 64
# here) in 3, and the 200 m world in 4, merged by gi-merge and
# compared with the one-machine bake grid by grid, bit for bit, in pyopenvdb. Placement
# alone is checked for 2 to 8 tiles in test_band.
set -e
tiled() { # SCENE N NAME [bake options]: bake NAME-whole.vdb's scene in N tiles, merge to NAME-N.vdb
    scene=$1 n=$2 name=$3
    shift 3
    files=""
    for i in $(seq 1 "$n"); do
        "$BIN/gi-bake" "$scene" -q -o "$name-$i-of-$n.vdb" --tile "$i/$n" --threads $((1 + i % 2)) "$@"
        files="$files $name-$i-of-$n.vdb"
    done
    # shellcheck disable=SC2086
    "$BIN/gi-merge" $files -q -o "$name-$n.vdb"
    rm -f $files
    echo "$name in $n tiles:"
    /usr/bin/python3 "$ROOT/tests/cli/same_vdb.py" "$name-whole.vdb" "$name-$n.vdb"
}
set -- --rays 8 --sampling random --basis sh2
"$BIN/gi-bake" "$DATA/world.glb" -q -o world-whole.vdb "$@"
for n in 2 5 8; do
    tiled "$DATA/world.glb" $n world "$@"
done
set -- --rays auto --max-rays 64 --noise 0.15
"$BIN/gi-bake" "$DATA/world.glb" -q -o auto-whole.vdb "$@"
tiled "$DATA/world.glb" 3 auto "$@"
python3 "$ROOT/data/make_scenes.py" --world 200 w200.glb
"$BIN/gi-bake" w200.glb -q -o w200-whole.vdb --rays 1
tiled w200.glb 4 w200 --rays 1
