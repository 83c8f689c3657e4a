# Our bake through three.js's own lighting path (issue 46, item 2): makeProbeGrid
# (web/gi-probe-grid.js) fills three r187's LightProbeGridWebGL / LightProbeGrid from a
# loaded volume. In node, at probes of the interior's grid, three's L2 irradiance from
# the grid's coefficients is our lookup's (L2 and scalar, RGBM and RGB9E5, both layouts;
# tests/js/check_probe_grid.mjs); in headless Chromium, WebGL2 and WebGPU, the interior
# lit only by the bounce through three's grid with untouched materials is our runtime's
# frame within 2 % (tests/web/check_probe_grid.mjs).
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/puppeteer-core" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
python3 "$DATA/make_scenes.py" --interior interior.glb
"$BIN/gi-bake" -q interior.glb -o interior.vdb --basis sh2
"$BIN/vdb-to-gi" -q interior.vdb -o interior.gi.gz
"$BIN/vdb-to-gi" -q interior.vdb -o scalar.gi.gz --basis scalar
"$BIN/vdb-to-gi" -q interior.vdb -o e5.gi.gz --encoding rgb9e5
"$BIN/vdb-to-gi" -q interior.vdb -o seed.gi.gz --basis scalar --layout seed
node "$ROOT/tests/js/check_probe_grid.mjs" interior.gi.gz scalar.gi.gz e5.gi.gz seed.gi.gz
node "$ROOT/tests/web/check_probe_grid.mjs" interior.glb interior.gi.gz 2>/dev/null
