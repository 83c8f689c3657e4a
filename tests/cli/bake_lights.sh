# The scene's own light (issue 26): a glTF's KHR_lights_punctual lights with their nodes'
# transforms, a sky map, bounces and the physical model, recorded in the .vdb; bad lights,
# skies and combinations refused in one line with no output. The seed model unless a case
# names the physical one (a later --model wins).
floor='AACgwAAAAAAAAKDAAACgQAAAAAAAAKDAAACgQAAAAAAAAKBAAACgwAAAAAAAAKBAAAACAAEAAAADAAIAAAA='
# scene FILE POINT SPOT: a 10 m floor, a point light, a spot and a directional light.
scene() {
    cat >"$1" <<EOF
{"asset": {"version": "2.0"}, "extensionsUsed": ["KHR_lights_punctual"],
 "extensions": {"KHR_lights_punctual": {"lights": [
  {"type": "point", "color": [1, 0.5, 0.25], $2, "range": 7},
  {"type": "spot", "intensity": 20, "spot": $3},
  {"type": "directional", "intensity": 3}]}},
 "buffers": [{"byteLength": 62, "uri": "data:application/octet-stream;base64,$floor"}],
 "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                "min": [-5, 0, -5], "max": [5, 0, 5]},
               {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
 "nodes": [{"mesh": 0},
           {"name": "lamp", "translation": [1, 2, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}},
           {"name": "arm", "translation": [0, 4, 0], "children": [3]},
           {"name": "torch", "rotation": [-0.7071068, 0, 0, 0.7071068],
            "extensions": {"KHR_lights_punctual": {"light": 1}}},
           {"name": "sun", "rotation": [-0.7071068, 0, 0, 0.7071068],
            "extensions": {"KHR_lights_punctual": {"light": 2}}}],
 "scenes": [{"nodes": [0, 1, 2, 4]}], "scene": 0}
EOF
}
scene lights.gltf '"intensity": 10' '{"innerConeAngle": 0.3, "outerConeAngle": 0.6}'
scene negative.gltf '"intensity": -10' '{"innerConeAngle": 0.3, "outerConeAngle": 0.6}'
scene absurd.gltf '"intensity": 1e9' '{"innerConeAngle": 0.3, "outerConeAngle": 0.6}'
scene cone.gltf '"intensity": 10' '{"innerConeAngle": 0.6, "outerConeAngle": 0.3}'
# Radiance .hdr maps, flat scanlines of RGBE 1.0: 2:1, square, and a header claiming 40000 x 20000.
hdr() {
    printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n' "$2" "$3" >"$1"
    i=0
    while [ $i -lt $(($2 * $3)) ]; do printf '\200\200\200\201'; i=$((i + 1)); done >>"$1"
}
hdr sky.hdr 8 16
hdr square.hdr 8 8
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 20000 +X 40000\n' >huge.hdr
printf 'not an image\n' >text.hdr
bake() {
    "$BIN/gi-bake" --model seed --rays 16 --spacing 1 "$@" 2>err >out
    code=$?
    echo "$code $(grep '^scene' out)$(cat err)"
}
meta() {
    vdb_print -m "$1" | grep -E '^   (model|bounces|scene_lights|sky_map|sun_color):' | sort | uniq
}
bake lights.gltf -o lights.vdb
meta lights.vdb
bake lights.gltf -o off.vdb --lights off
meta off.vdb
bake lights.gltf -o physical.vdb --model physical --bounces 3 --sky-map sky.hdr --sky-rotation 45
meta physical.vdb
# The physical model bounces until converged by default: how many, and what the untraced carry.
python3 "$DATA/make_scenes.py" --room lit.glb
bake lit.glb -o auto.vdb --model physical --sky 0.3,0.5,1 --sun-color 0,0,0
grep '^bounces' out
vdb_print -m auto.vdb | grep -E '^   (bounces|bounces_traced|converge):' | sort | uniq
rm lit.glb lit.json auto.vdb
bake lights.gltf -o x.vdb --bounces auto
bake lights.gltf -o x.vdb --model physical --bounces 2 --converge 0.05
bake lights.gltf -o x.vdb --model physical --converge 1
bake lights.gltf -o given.vdb --sun 0,1,0
meta given.vdb
bake lights.gltf -o scene.vdb --sun scene
bake lights.gltf -o x.vdb --sun scene --lights off
bake "$DATA/room.obj" -o x.vdb --sun scene
bake lights.gltf -o x.vdb --model physical --ambient 0.2
bake lights.gltf -o x.vdb --model physical --falloff 3
bake negative.gltf -o x.vdb
bake absurd.gltf -o x.vdb
bake cone.gltf -o x.vdb
bake lights.gltf -o x.vdb --sky-map missing.hdr
bake lights.gltf -o x.vdb --sky-map text.hdr
bake lights.gltf -o x.vdb --sky-map square.hdr
bake lights.gltf -o x.vdb --sky-map huge.hdr
bake lights.gltf -o x.vdb --sky-map sky.hdr --sky 1,1,1
bake lights.gltf -o sky.hdr --sky-map sky.hdr
"$BIN/gi-lightmap" --model seed -q lights.gltf -o lit.glb --direct --layers --rays 8 --texel 0.5 --sky-map sky.hdr
echo "lightmap $?"
ls
