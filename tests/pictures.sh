#!/bin/sh
# pictures.sh: `make pictures`. The README's pictures from the demo's outputs:
# the slices of vdb-to-gi --slices, enlarged 4x without filtering (one probe
# is 4x4 pixels), the viewer in headless Chromium with GI off and on, and the
# top-left of the demo lightmap's atlas (gi-lightmap --slices).
set -eu
BUILD=${BUILD:-build/release}
[ -f out/world.gi.gz ] && [ -d out/slices ] || { echo "pictures: run make demo first" >&2; exit 1; }
mkdir -p docs/img
for s in baked bricks difference levels; do
    src=out/slices/$s.png
    # "out/slices/baked.png :  120 x  120, 3 channel, uint8 png"
    set -- $(oiiotool --info "$src" | tr -s ' ,' '  ')
    oiiotool "$src" --resample $(($3 * 4))x$(($5 * 4)) -o "docs/img/world_$s.png"
done
node tests/web/check_viewer.mjs data/world.glb out/world.gi.gz --save docs/img >/dev/null
"$BUILD/bin/gi-lightmap" -q data/world.glb -o out/world-lit.glb --slices out/lightmap
for s in charts map; do
    oiiotool --nosoftwareattrib "out/lightmap/${s}0.png" --cut 0,0,511,287 -o "docs/img/lightmap_world_$s.png"
done
echo "pictures: docs/img/world_{baked,bricks,difference,levels}.png, viewer_{gi_off,gi_on,levels,bricks}.png,"
echo "          lightmap_world_{charts,map}.png"
