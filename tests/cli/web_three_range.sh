# run: early (among the slowest, so started first)
# The three.js range web/package.json claims (>= 0.165 for WebGL2, >= 0.175 for
# WebGPU, up to 0.187, the version every other browser test runs): the oldest
# ends draw what the C sampler computes, as cli/web_render checks on 0.187.
# 0.183 is the first whose standard material splits its diffuse colour from
# the base colour (diffuseContribution) before three/tsl exports it; metalness
# 0.5 must still halve the bounce there.
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/three-0.165" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 32 >/dev/null
"$BIN/vdb-to-gi" -q world.vdb -o w.gi.gz --criterion range --eps 5
for run in 0.165,webgl 0.175,webgl 0.175,webgpu 0.183,webgpu; do
    echo "three ${run%,*}:"
    THREE_PACKAGE=three-${run%,*} node "$ROOT/tests/web/check_probe.mjs" ${run#*,} "$DATA/world.glb" w.gi.gz \
        "$BIN/gi-inspect" 2>/dev/null
done
