# Ambient cubes to Bevy: KTX2 (read back by the npm package ktx-parse), the PNG of
# bevy-baked-gi, their JSON placement; scalar-only probes and bad grids are refused.
"$BIN/gi-bake" -q "$DATA/room.obj" -o cubes.vdb --rays 32 --basis ambient-cube >/dev/null
"$BIN/gi-bake" -q "$DATA/room.obj" -o scalar.vdb --rays 8 >/dev/null
"$BIN/vdb-to-gi" cubes.vdb --bevy v.ktx2 --bevy-baked-gi v.png --res 7,3,5 \
    --box -3,0,-2.5,3,3,2.5 || exit 1
node "$ROOT/tests/js/check_ktx2.mjs" v.ktx2 7 3 5
"$BIN/vdb-to-gi" -q cubes.vdb --bevy v9.ktx2 --bevy-format rgb9e5 --voxel 1 || exit 1
node "$ROOT/tests/js/check_ktx2.mjs" v9.ktx2 $(sed -n 's/.*"resolution": \[\([0-9]*\), \([0-9]*\), \([0-9]*\)\].*/\1 \2 \3/p' v9.ktx2.json)
iinfo v.png | sed 's/^v.png : *//; s/  */ /g'
grep -c '"transform"' v.ktx2.json v.png.json
for args in "scalar.vdb --bevy s.ktx2" "cubes.vdb --bevy s.ktx2 --box -9,0,0,1,1,1" \
            "cubes.vdb --bevy s.ktx2 --res 3000,1,1" "cubes.vdb --bevy s.ktx2 --res 0" \
            "cubes.vdb --bevy s.ktx2 --voxel -1"; do
    # shellcheck disable=SC2086
    "$BIN/vdb-to-gi" $args >/dev/null 2>err
    echo "$? $(head -n 1 err)"
done
ls s.* 2>/dev/null | wc -l
