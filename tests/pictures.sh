#!/bin/sh
# pictures.sh: `make pictures`. The README's pictures from the demo's outputs:
# the slices of vdb-to-gi --slices, enlarged 4x without filtering (one probe
# is 4x4 pixels), the viewer in headless Chromium with GI off and on, and the
# top-left of the demo lightmap's atlas (gi-lightmap --slices); then the interior of
# make_scenes.py --interior at 1 and 3 bounces: a slice 0.5 m over its floor, and the viewer
# showing the baked light alone (docs/lights.md).
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
I=out/interior
mkdir -p "$I"
python3 data/make_scenes.py --interior "$I/interior.glb"
for b in 1 3; do
    "$BUILD/bin/gi-bake" -q "$I/interior.glb" -o "$I/b$b.vdb" --model physical --bounces $b \
        --basis sh2 --spacing 0.25 --rays 1024 --sky 0.6,0.7,0.9
    "$BUILD/bin/vdb-to-gi" -q "$I/b$b.vdb" -o "$I/b$b.gi.gz" --slices "$I/slices$b" --slice-at 0.5 --exposure 0
    # The house is the lower right of the volume's extent: 12 x 6 m, from 8 m in on x and z.
    oiiotool "$I/slices$b/baked.png" --cut 48x24+32+32 --resample 288x144 -o "$I/slice$b.png"
    mkdir -p "$I/viewer$b"
    VIEW='cam=2.5,11,-5.5&at=7,0,3.5&gui=0&sun=0&ambient=0&lights=0' \
        node tests/web/check_viewer.mjs "$I/interior.glb" "$I/b$b.gi.gz" --save "$I/viewer$b" >/dev/null 2>&1 || true
    oiiotool "$I/viewer$b/viewer_gi_on.png" --cut 640x400+80+90 --resample 320x200 -o "$I/view$b.png"
done
oiiotool --nosoftwareattrib "$I/slice1.png" "$I/slice3.png" --mosaic:pad=8 2x1 -o docs/img/interior_slices.png
oiiotool --nosoftwareattrib "$I/view1.png" "$I/view3.png" --mosaic:pad=8 2x1 -o docs/img/interior_viewer.png
echo "pictures: docs/img/world_{baked,bricks,difference,levels}.png, viewer_{gi_off,gi_on,levels,bricks}.png,"
echo "          lightmap_world_{charts,map}.png, interior_{slices,viewer}.png"
