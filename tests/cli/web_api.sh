# One API for both back ends (tests/js/check_api.mjs): the same GiRuntime methods
# and options from vdbgi.js (WebGL2) and vdbgi-webgpu.js (WebGPU), unsupported
# materials left as they were with one warning, debug views by name.
[ -d "$ROOT/web/node_modules/three" ] || { echo "web/node_modules missing (make deps installs it)"; exit 77; }
node "$ROOT/tests/js/check_api.mjs"
