# The browser loader within bounds (issue 47; tests/web/check_bounds.mjs): gzip bombs sent
# both ways, an empty 963 MB atlas, a volume at the default budget, an absurd header, a cut
# file, a .vdb and an HTML page, through loadGi(url) in headless Chromium, WebGL2 and
# WebGPU, each refused naming the URL and what is wrong, or loaded and drawn, within
# +256 MB of the browser's process memory.
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/puppeteer-core" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
# room.obj is closed and has no lamp: dark under the default physical model, lit by the
# seed model's ambient fill.
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --spacing 1 --rays 16 --model seed >/dev/null
"$BIN/vdb-to-gi" -q room.vdb -o room.gi.gz
node "$ROOT/tests/web/check_bounds.mjs" room.gi.gz room.vdb 2>/dev/null
