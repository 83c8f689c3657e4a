# Occluders for what moves (issue 45, item 3): a sphere and a two-capsule body over a floor
# lit by a flat lightmap and by a baked volume, WebGL2 and WebGPU, against the closed form
# of the cosine-weighted hemisphere they cover (tests/web/check_occluders.mjs).
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/puppeteer-core" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
floor='AACgwAAAAAAAAKDAAACgQAAAAAAAAKDAAACgQAAAAAAAAKBAAACgwAAAAAAAAKBAAAACAAEAAAADAAIAAAA='
cat >floor.gltf <<JSON
{"asset": {"version": "2.0"},
 "buffers": [{"byteLength": 62, "uri": "data:application/octet-stream;base64,$floor"}],
 "bufferViews": [{"buffer": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 12}],
 "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                "min": [-5, 0, -5], "max": [5, 0, 5]},
               {"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}],
 "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
 "nodes": [{"mesh": 0}], "scenes": [{"nodes": [0]}], "scene": 0}
JSON
"$BIN/gi-bake" -q floor.gltf -o floor.vdb --model physical --sky 1,1,1 --sun-color 0,0,0 --rays 64
"$BIN/vdb-to-gi" -q floor.vdb -o floor.gi.gz
node "$ROOT/tests/web/check_occluders.mjs" floor.gi.gz 2>/dev/null
