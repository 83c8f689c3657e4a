# run: early (among the slowest, so started first)
# The browser runtime (web/) draws what the C sampler computes: headless
# Chromium renders the bundled world's probe-colour view through WebGL2 and
# through WebGPU (TSL), for both encodings and both brick layouts, and 400
# covered pixels match gi-inspect --at at their world positions within the
# tolerance docs/web.md derives; the brick-level view shows their levels. An L2
# volume (versions 8 and 7) is read with each pixel's own normal.
# The seed's range criterion at a coarse eps puts level 1 (and, seed layout, 2) bricks where
# the camera looks, so the lookup's coarse-brick arithmetic is exercised.
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/puppeteer-core" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 32 >/dev/null
for run in rgbm,seed rgb9e5,seed rgbm,compact rgb9e5,compact; do
    "$BIN/vdb-to-gi" -q world.vdb -o w.gi.gz --encoding ${run%,*} --layout ${run#*,} --criterion range --eps 5
    for backend in webgl webgpu; do
        node "$ROOT/tests/web/check_probe.mjs" $backend "$DATA/world.glb" w.gi.gz "$BIN/gi-inspect" 2>/dev/null
    done
done
# At 0.5 m the runtime's columns texture has more than one row: the shaders' row arithmetic.
"$BIN/gi-bake" -q "$DATA/world.glb" -o fine.vdb --rays 16 >/dev/null
"$BIN/vdb-to-gi" -q fine.vdb -o w.gi.gz --criterion range --eps 5
for backend in webgl webgpu; do
    node "$ROOT/tests/web/check_probe.mjs" $backend "$DATA/world.glb" w.gi.gz "$BIN/gi-inspect" 2>/dev/null
done
# L2 terms (version 8, the second band in luminance; and version 7, all in colour):
# each pixel reads with its own world normal, half a spacing off its surface, in both
# back ends.
"$BIN/gi-bake" -q "$DATA/world.glb" -o sh.vdb --spacing 1 --rays 32 --basis sh2 >/dev/null
for version in 8 7; do
    "$BIN/vdb-to-gi" -q sh.vdb -o w.gi.gz --criterion range --eps 5 --gi-version $version
    for backend in webgl webgpu; do
        printf 'version %s, ' $version
        node "$ROOT/tests/web/check_probe.mjs" $backend "$DATA/world.glb" w.gi.gz "$BIN/gi-inspect" 2>/dev/null
    done
done
