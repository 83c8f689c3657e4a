# Emissive materials light the scene, and --layers splits the map by light
# (and a map past half floats is written as floats; absurd lights are refused):
# a closed room (Kd 0.7) with a ceiling lamp (OBJ Ke 4 3 2) and the sun off
# gives, under the seed model, two layers, the ambient fill and the lamp, each its own EXR and its own
# texture in the .glb's extras, adding up to the map. The .glb carries the lamp
# as emissiveFactor with KHR_materials_emissive_strength 4, so baking that
# .glb again lights the room as brightly (Debian's assimp does not read the
# strength: without the glTF shim the lamp's layer would be 4 times darker).
# An emissive texture (OBJ map_Ke) scales the lamp's light and goes into the .glb.
cat > lamp.mtl <<'MTL'
newmtl wall
Kd 0.7 0.7 0.7
newmtl lamp
Kd 0.8 0.8 0.8
Ke 4 3 2
MTL
{
    echo "mtllib lamp.mtl"
    for v in "0 0 0" "4 0 0" "4 0 4" "0 0 4" "0 3 0" "4 3 0" "4 3 4" "0 3 4" \
             "1.5 2.9 1.5" "2.5 2.9 1.5" "2.5 2.9 2.5" "1.5 2.9 2.5"; do echo "v $v"; done
    echo "usemtl wall"
    for f in "1 3 2" "1 4 3" "5 7 8" "5 6 7" "1 6 5" "1 2 6" "2 7 6" "2 3 7" "3 8 7" \
             "3 4 8" "4 5 8" "4 1 5"; do echo "f $f"; done
    echo "usemtl lamp"
    echo "f 9 11 10"; echo "f 9 12 11"
} > lamp.obj
max() { oiiotool --stats "$1" | sed -n 's/ *Stats Max: *\([0-9.]*\) \([0-9.]*\) \([0-9.]*\).*/\1 \2 \3/p'; }
"$BIN/gi-lightmap" --model seed -q lamp.obj -o lamp.glb --texel 0.1 --size 256 --sun-color 0,0,0 --layers --stats lamp.json
echo "exit $?: $(ls lamp.*.exr | tr '\n' ' ')"
grep -e '"layers"' -e '"passes"' lamp.json
node "$ROOT/tests/js/check_gltf.mjs" lamp.glb
node -e '
const b = require("fs").readFileSync("lamp.glb"), j = JSON.parse(b.subarray(20, 20 + b.readUInt32LE(12)));
for (const m of j.materials)
  console.log(`material: emissive ${JSON.stringify(m.emissiveFactor ?? null)}, strength ${m.extensions?.KHR_materials_emissive_strength?.emissiveStrength ?? "-"}, layers ${m.extras.vdbgi_lightmap.layers.map((l) => l.name).join(" ")}`);
console.log(`extensionsUsed ${j.extensionsUsed}`);'
for f in lamp.lightmap0.exr lamp.ambient.lightmap0.exr lamp.emissive2.lightmap0.exr; do echo "$f max E: $(max $f)"; done
# The sum of the layers is the map, texel by texel (half floats: to their rounding).
oiiotool lamp.ambient.lightmap0.exr lamp.emissive2.lightmap0.exr --add lamp.lightmap0.exr --sub --abs \
    --rangecheck 0,0,0 0.02,0.02,0.02 | awk '/within/ { print "texels where the layers add up to the map within 0.02:", $1 }'
"$BIN/gi-lightmap" --model seed -q lamp.glb -o again.glb --size 256 --sun-color 0,0,0 --layers
echo "again.glb: $(ls again.*.exr | tr '\n' ' ')"
echo "again.emissive1.lightmap0.exr max E: $(max again.emissive1.lightmap0.exr)"
# Assimp numbers materials as meshes first use them, not as the file lists
# them: with an unused emitter of strength 50 put first, the lamp still finds
# its own strength (by its factors: these materials have no names).
node "$ROOT/tests/js/shuffle_materials.mjs" lamp.glb shuffled.glb
"$BIN/gi-lightmap" --model seed -q shuffled.glb -o shuffled-lit.glb --size 256 --sun-color 0,0,0 --layers
echo "shuffled.glb: $(ls shuffled-lit.*.exr | tr '\n' ' ')max E $(max shuffled-lit.emissive1.lightmap0.exr)"
# An emissive texture scales the lamp: a grey one (sRGB 128, linear 0.2158) on
# the lamp's own UVs (OBJ map_Ke) gives its layer 0.2158 of the largest E.
oiiotool --create 4x4 3 --fill:color=0.5,0.5,0.5 0,0,4,4 -d uint8 --nosoftwareattrib -o grey.png
sed 's/^mtllib lamp.mtl/mtllib grey.mtl/; s/^usemtl lamp/vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nusemtl lamp/; s/^f 9 11 10/f 9\/1 11\/3 10\/2/; s/^f 9 12 11/f 9\/1 12\/4 11\/3/' lamp.obj > grey.obj
{ cat lamp.mtl; echo "map_Ke grey.png"; } > grey.mtl
"$BIN/gi-lightmap" --model seed -q grey.obj -o grey.glb --texel 0.1 --size 256 --sun-color 0,0,0 --layers
echo "map_Ke grey.png: max E $(max grey.emissive2.lightmap0.exr); emissiveTexture in the .glb: $(node -e '
const b = require("fs").readFileSync("grey.glb"), j = JSON.parse(b.subarray(20, 20 + b.readUInt32LE(12)));
console.log(j.materials.some((m) => m.emissiveTexture) ? "yes" : "no")')"
node "$ROOT/tests/js/check_gltf.mjs" grey.glb
# Without the lamp's Ke the room has only its fill.
sed -i '/^Ke/d' lamp.mtl
"$BIN/gi-lightmap" --model seed -q lamp.obj -o dark.glb --texel 0.1 --size 256 --sun-color 0,0,0 --layers
echo "no Ke: $(ls dark.*.exr | tr '\n' ' '), max E: $(max dark.lightmap0.exr)"
"$BIN/gi-lightmap" --model seed lamp.obj -o ao.glb --mode ao --layers 2>&1; echo "ao with layers: exit $?"
# A lamp at the emission cap (10^6) gives E in the millions, past half floats (65504):
# that map is written as 32-bit floats, every texel finite; lights past the cap are refused.
sed 's/^mtllib lamp.mtl/mtllib bright.mtl/' lamp.obj > bright.obj
printf 'newmtl wall\nKd 0.7 0.7 0.7\nnewmtl lamp\nKd 0.8 0.8 0.8\nKe 1000000 1000000 1000000\n' > bright.mtl
"$BIN/gi-lightmap" --model seed -q bright.obj -o bright.glb --texel 0.1 --size 256 --sun-color 0,0,0
oiiotool --stats bright.lightmap0.exr | awk '/openexr/ { print $8, $9 } /InfCount|NanCount/ { print $2, $3, $4, $5 }' | tr '\n' ' '
echo
for light in "--sky 3e38,0,0" "--ambient 1e38" "--sun-color 3e38,1,1"; do
    "$BIN/gi-lightmap" --model seed -q lamp.obj -o refused.glb $light 2>&1; echo "exit $?, $(ls refused.* 2>/dev/null | wc -l) output(s)"
done
