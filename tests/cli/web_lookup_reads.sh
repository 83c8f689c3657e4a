# The WebGPU lookup reads each of its textures once a fragment (issue 46, item 3;
# tests/web/check_reads.mjs): written with TSL's select(), whose branches each rebuild
# what they use, the lookup held 76 texture reads where it needs 10, and a frame of the
# interior cost 3.9x three's own probe grid's for the same light (docs/web.md). The
# occluders' loop adds two (a shape's ends, read by index).
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/puppeteer-core" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
python3 "$DATA/make_scenes.py" --interior interior.glb
"$BIN/gi-bake" -q interior.glb -o interior.vdb --basis sh2 --rays 32
"$BIN/vdb-to-gi" -q interior.vdb -o l2.gi.gz
"$BIN/vdb-to-gi" -q interior.vdb -o scalar.gi.gz --basis scalar
node "$ROOT/tests/web/check_reads.mjs" l2.gi.gz scalar.gi.gz 2>/dev/null
