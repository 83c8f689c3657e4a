# gi-lightmap end to end on the bundled room: a lightmap (two passes, direct sun)
# and an AO map, each a .glb the Khronos validator passes with no error; the EXR
# beside a lightmap; the same bytes on one thread and two; bad input refused
# with one line, a non-zero exit and no file written.
"$BIN/gi-lightmap" --help | head -1
"$BIN/gi-lightmap" -q "$DATA/room.obj" -o room.glb --texel 0.1 --size 256 --direct --threads 1
echo "lightmap exit $?: $(ls room.* | tr '\n' ' ')"
node "$ROOT/tests/js/check_gltf.mjs" room.glb
"$BIN/gi-lightmap" -q "$DATA/room.obj" -o sliced.glb --texel 0.1 --size 256 --slices slices
for f in slices/*.png; do echo "$f: $(oiiotool --info "$f" | sed 's/^[^:]*: *//')"; done
"$BIN/gi-lightmap" -q "$DATA/room.obj" -o room2.glb --texel 0.1 --size 256 --direct --threads 2
cmp room.glb room2.glb && cmp room.lightmap0.exr room2.lightmap0.exr && echo "1 and 2 threads: same bytes"
oiiotool --info room.lightmap0.exr | sed 's/^room.lightmap0.exr *: *//'
"$BIN/gi-lightmap" -q "$DATA/room.obj" -o ao.glb --mode ao --ao-dist 0.5 --texel 0.1 --size 256
echo "ao exit $?: $(ls ao.* | tr '\n' ' ')"
node "$ROOT/tests/js/check_gltf.mjs" ao.glb
# A scene with a usable second UV set keeps it (gi-lightmap's own output, baked again);
# one whose set leaves [0, 1], overlaps itself or sits in one texel is unwrapped anew,
# with a warning.
"$BIN/gi-lightmap" room.glb -o again.glb --size 256 --threads 1 | grep -e charts -e texels
node "$ROOT/tests/js/check_gltf.mjs" again.glb
for how in outside overlap onetexel; do
    node "$ROOT/tests/js/edit_uv1.mjs" room.glb spoilt.glb $how
    "$BIN/gi-lightmap" spoilt.glb -o re.glb --size 256 --texel 0.1 2>&1 >/dev/null | grep 'second UV'
done
# Bad input: each one line on stderr, the exit code, nothing written.
mkdir bad && cd bad
"$BIN/gi-lightmap" missing.obj -o x.glb 2> err.txt; echo "missing scene: exit $?, $(wc -l < err.txt) line"
"$BIN/gi-lightmap" "$DATA/room.obj" -o x.glb --passes 0 2> err.txt; echo "passes 0: exit $?, $(cat err.txt | head -1)"
"$BIN/gi-lightmap" "$DATA/room.obj" -o x.glb --model seed --passes auto 2> err.txt; echo "passes auto, seed: exit $?, $(cat err.txt | head -1)"
"$BIN/gi-lightmap" "$DATA/room.obj" -o x.glb --model seed --converge 0.01 2> err.txt; echo "converge, seed: exit $?, $(head -1 err.txt)"
# Under the physical model the default is auto: passes until the next would add under 1 %,
# at most three swept and the third carrying the rest.
python3 "$DATA/make_scenes.py" --room lit.glb
"$BIN/gi-lightmap" lit.glb -o auto.glb -q --model physical --sun-color 0,0,0 --sky 0.5,0.6,0.8 --rays 16 --texel 0.5 --stats auto.json
python3 -c "import json; s=json.load(open('auto.json')); print('physical, default: %d passes of the %d the light needs, the last adding %.2f %%, the unswept %.1f %%' % (s['passes'], s['bounces'], 100 * s['last_pass_share'], 100 * s['tail_share']))"
# --rays auto: a texel's rays by its pilot's spread, as few as meet --noise as measured. Every
# bake says the noise a pass's gather left, measured at points on the surfaces: auto's within
# its target, the fixed 16 rays' several times it. AO takes a fixed count.
for rays in auto 16; do
    noise=""
    [ $rays = auto ] && noise="--noise 0.1"
    # shellcheck disable=SC2086
    "$BIN/gi-lightmap" lit.glb -o auto.glb --texel 0.25 --rays $rays $noise --stats $rays.json > out.txt
    echo "rays $rays: exit $?, $(grep -c '^noise .* of the light in a pass, measured at 256 points on the surfaces' out.txt) noise line"
done
python3 -c "import json; a=json.load(open('auto.json')); f=json.load(open('16.json')); print('auto: noise in 8.5..10 %%: %s, rays a texel in 32..1024: %s; fixed 16: %g rays a texel, over 3x auto\'s noise: %s' % (0.085 <= a['noise'] <= 0.1, 32 <= a['gather_rays'] <= 1024, f['gather_rays'], f['noise'] > 3 * a['noise']))"
"$BIN/gi-lightmap" "$DATA/room.obj" -o x.glb --mode ao --rays auto 2> err.txt; echo "ao, auto: exit $?, $(head -1 err.txt)"
"$BIN/gi-lightmap" "$DATA/room.obj" -o x.glb --mode ao --rays 32 --noise 0.1 2> err.txt; echo "ao, --noise: exit $?, $(head -1 err.txt)"
rm -f lit.glb lit.json auto.glb auto.json 16.json auto.lightmap*.exr out.txt x.glb
"$BIN/gi-lightmap" "$DATA/room.obj" -o x.gltf 2> err.txt; echo "not .glb: exit $?, $(head -1 err.txt)"
"$BIN/gi-lightmap" "$DATA/room.obj" -o x.glb --mode bake 2> err.txt; echo "mode: exit $?, $(head -1 err.txt)"
echo "keep me" > notes.glb
"$BIN/gi-lightmap" "$DATA/room.obj" -o notes.glb 2> err.txt; echo "not a glTF in the way: exit $?, $(cat notes.glb)"
cp "$ROOT/tests/hostile/lightmap/nan.obj" .
"$BIN/gi-lightmap" nan.obj -o y.glb 2> err.txt; echo "only a NaN triangle: exit $?, $(tail -1 err.txt)"
echo "files left: $(ls | grep -v -e err.txt -e notes.glb -e nan.obj | wc -l)"
# All outputs or none: a --stats or -o naming a directory is refused before anything is
# written (the .glb and its EXR used to be renamed into place first).
mkdir -p dirstats.json dirout.glb
"$BIN/gi-lightmap" -q "$DATA/room.obj" -o keep.glb --stats dirstats.json 2>&1; echo "stats a directory: exit $?, $(ls keep.* 2>/dev/null | wc -l) output(s)"
"$BIN/gi-lightmap" -q "$DATA/room.obj" -o dirout.glb 2>&1; echo "-o a directory: exit $?, $(ls dirout.* 2>/dev/null | grep -vc '^dirout.glb$') output(s) beside it"
# One image shared by 24 materials is decoded once (24 decodes of a 4096^2 one took
# 3.4 GB): the .glb holds it once, and every material names it.
oiiotool --create 64x64 3 --fill:color=0.5,0.25,0.125 0,0,64,64 -d uint8 --nosoftwareattrib -o shared.png
{
    for i in $(seq 1 24); do printf 'newmtl m%d\nKd 1 1 1\nmap_Kd shared.png\n' $i; done
} > shared.mtl
{
    echo "mtllib shared.mtl"
    for i in $(seq 0 24); do echo "v $i 0 0"; echo "v $i 0 1"; done
    echo "vt 0 0"; echo "vt 1 0"; echo "vt 0 1"
    for i in $(seq 1 24); do echo "usemtl m$i"; echo "f $((2 * i - 1))/1 $((2 * i + 1))/2 $((2 * i))/3"; done
} > shared.obj
"$BIN/gi-lightmap" -q shared.obj -o shared.glb --size 64
node -e '
const b = require("fs").readFileSync("shared.glb"), j = JSON.parse(b.subarray(20, 20 + b.readUInt32LE(12)));
const sources = new Set(j.materials.map((m) => j.textures[m.pbrMetallicRoughness.baseColorTexture.index].source));
console.log(`shared texture: ${j.materials.length} materials on ${sources.size} image(s); ${j.images.length} images in the .glb with the lightmap`);'
# Work a small file may ask for is bounded before it is spent (issue 27): 64 quads of
# 1024 x 1024 texels each (an atlas apiece, 67 M texels, 4 GB) are refused by their texels;
# one 500 m quad (scaled into one atlas, 1 M texels) by its rays at 4096 a texel.
cp "$ROOT/tests/hostile/lightmap/quads64.obj" quads.obj
printf 'v 0 0 0\nv 500 0 0\nv 500 0 500\nv 0 0 500\nf 1 3 2\nf 1 4 3\n' > plane.obj
"$BIN/gi-lightmap" quads.obj -o quads.glb 2>&1 >/dev/null; echo "exit $?"
"$BIN/gi-lightmap" plane.obj -o plane.glb --rays 4096 2>&1 >/dev/null; echo "exit $?"
ls quads.* plane.*
