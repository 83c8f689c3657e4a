#!/bin/sh
# same_outputs.sh OLD_BIN NEW_BIN [DIR]: whether two builds of vdbgi make the same outputs
# (issue 38: a change of structure changes no output byte). Bakes the bundled world, the
# 200 m world, the town and the interior with each build, converts each bake (scalar and L2)
# and lightmaps each scene, then compares: .gi.gz, .json statistics less their timings,
# .glb and slices byte for byte; .vdb grid by grid, bit for bit (tests/cli/same_vdb.py),
# and their metadata less bake_seconds (the JSON's peak memory, summed as threads allocate,
# is left out too). SCENES="world interior" compares fewer; all four take about a quarter
# of an hour on 2 cores. Prints one line a comparison, "same" or "DIFFERENT", and exits 1
# if any differs.
set -eu
old=$(cd "$1" && pwd) new=$(cd "$2" && pwd)
dir=${3:-build/same-outputs}
root=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$dir"
cd "$dir"
[ -f w200.glb ] || python3 "$root/data/make_scenes.py" --world 200 w200.glb
[ -f town.glb ] || python3 "$root/data/make_scenes.py" --town town.glb
[ -f interior.glb ] || python3 "$root/data/make_scenes.py" --interior interior.glb
cp "$root/data/world.glb" world.glb
status=0
verdict() { # NAME: 0 (same) or not
    if [ "$2" = 0 ]; then echo "same       $1"; else echo "DIFFERENT  $1"; status=1; fi
}
meta() {
    /usr/bin/python3 -c '
import sys, pyopenvdb as vdb
for g in vdb.readAllGridMetadata(sys.argv[1]):
    print(sorted((k, str(v)) for k, v in g.metadata.items() if k != "bake_seconds"))' "$1"
}
for scene in ${SCENES:-world interior w200 town}; do
    case $scene in w200 | town) rays="--rays 32" ;; *) rays="" ;; esac
    for side in old new; do
        eval "bin=\$$side"
        # shellcheck disable=SC2154,SC2086
        {
            "$bin/gi-bake" -q $scene.glb -o $scene-$side.vdb $rays
            "$bin/gi-bake" -q $scene.glb -o $scene-sh2-$side.vdb $rays --basis sh2 --model physical --bounces 2
            "$bin/vdb-to-gi" -q $scene-$side.vdb -o $scene-$side.gi.gz --stats $scene-$side.json \
                --slices $scene-$side-slices
            "$bin/vdb-to-gi" -q $scene-sh2-$side.vdb -o $scene-sh2-$side.gi.gz
            "$bin/gi-lightmap" -q $scene.glb -o $scene-$side.glb $rays
        }
    done
    for kind in "" -sh2; do
        r=0
        /usr/bin/python3 "$root/tests/cli/same_vdb.py" $scene$kind-old.vdb $scene$kind-new.vdb |
            grep -q DIFFERENT && r=1
        [ "$(meta $scene$kind-old.vdb)" = "$(meta $scene$kind-new.vdb)" ] || r=1
        verdict "$scene$kind.vdb" $r
        r=0; cmp -s $scene$kind-old.gi.gz $scene$kind-new.gi.gz || r=1
        verdict "$scene$kind.gi.gz" $r
    done
    r=0
    [ "$(grep -v -e seconds -e over_read -e memory_peak -e '"input"' -e '"output"' $scene-old.json)" = \
        "$(grep -v -e seconds -e over_read -e memory_peak -e '"input"' -e '"output"' $scene-new.json)" ] || r=1
    verdict "$scene.json" $r
    r=0; diff -r $scene-old-slices $scene-new-slices >/dev/null || r=1
    verdict "$scene slices" $r
    r=0; cmp -s $scene-old.glb $scene-new.glb || r=1
    for f in $scene-old.lightmap*; do cmp -s "$f" "$(echo "$f" | sed 's/-old/-new/')" || r=1; done
    verdict "$scene.glb and its maps" $r
done
exit $status
