# run: early (among the slowest, so started first)
# web/viewer.html in headless Chromium with a scene from gi-lightmap and no
# probe volume: it finds the lightmap on every material, and the map only adds
# light (WebGL2, untone-mapped), in WebGPU too; with --layers, the panel's
# compositor weighs each light (WebGL2 and WebGPU).
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/puppeteer-core" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
"$BIN/gi-lightmap" -q "$DATA/world.glb" -o lit.glb --texel 0.5 --size 512
# The seed model, whose ambient layer makes two sliders of the sun's one.
"$BIN/gi-lightmap" -q "$DATA/world.glb" -o layers.glb --texel 0.5 --size 512 --layers --model seed
node "$ROOT/tests/web/check_lightmap.mjs" lit.glb layers.glb 2>/dev/null
# The split in one call (issue 40, item 2; tests/web/check_split.mjs): GiRuntime.lightScene() on
# lit.glb with the volume of the same world and a sphere as the moving object, against the
# recipe docs/lightmap.md writes out, WebGL2 and WebGPU.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 32 >/dev/null
"$BIN/vdb-to-gi" -q world.vdb -o world.gi.gz
node "$ROOT/tests/web/check_split.mjs" lit.glb world.gi.gz 2>/dev/null
