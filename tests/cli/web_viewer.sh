# run: early (among the slowest, so started first)
# web/viewer.html in headless Chromium: with a good .gi.gz it shows the file's
# figures (WebGL2 and WebGPU, whose frame carries the same light); GI on only adds light, to most of the frame; a
# truncated file and a foreign one each give an error naming the file while
# the scene keeps rendering, the same frame as with GI off.
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/puppeteer-core" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 32 >/dev/null
"$BIN/vdb-to-gi" -q world.vdb -o world.gi.gz
node "$ROOT/tests/web/check_viewer.mjs" "$DATA/world.glb" world.gi.gz 2>/dev/null
