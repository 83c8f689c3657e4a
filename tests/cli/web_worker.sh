# loadGi's decoding in a module worker (issue 40, item 1): the bundled world's scalar and
# L2 volumes (as the default writes it, every term in colour here, and as version 8), a
# file cut short and one with a damaged level byte, loaded with the worker (the C reader
# as WebAssembly), on the page, with a worker script that is not there (the page takes
# over), with the worker as esbuild bundles it by web/README.md's words and with the
# worker told to rebuild in JavaScript, give the same textures, byte for byte, and the
# same refusals (tests/web/check_worker.mjs).
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/esbuild" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
mkdir site
"$BIN/gi-bake" -q "$DATA/world.glb" -o l2.vdb --spacing 1 --rays 16 --basis sh2 >/dev/null
"$BIN/vdb-to-gi" -q l2.vdb -o site/l2.gi.gz
"$BIN/vdb-to-gi" -q l2.vdb -o site/l2v8.gi.gz --gi-version 8
"$BIN/vdb-to-gi" -q l2.vdb -o site/scalar.gi.gz --basis scalar
size=$(wc -c < site/l2.gi.gz)
head -c $((size / 2)) site/l2.gi.gz > site/cut.gi.gz
# A level byte no converter writes (the first brick's, raised past the file's max level):
# the C reader refuses it as the JavaScript one does, which words the refusal.
node -e '
const fs = require("fs"), zlib = require("zlib");
const gi = zlib.gunzipSync(fs.readFileSync("site/l2.gi.gz")), header = gi.readUInt32LE(12);
const at = gi.indexOf(Buffer.from([1]), header);
gi[at] = 9;
fs.writeFileSync("site/bad.gi.gz", zlib.gzipSync(gi));'
"$ROOT/web/node_modules/.bin/esbuild" "$ROOT/web/gi-worker.js" --bundle --format=esm \
    --outfile=site/gi-worker.js --log-level=error
node "$ROOT/tests/web/check_worker.mjs" "$PWD/site"
