# The web package as a three.js developer meets it (web/README.md): npm pack web/,
# install the tarball and three into a scratch app, take main.js verbatim from the
# README's example, bundle it with esbuild, and open it in headless Chromium: it
# draws the scene, and no page says a warning or an error.
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -x "$ROOT/web/node_modules/.bin/esbuild" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
mkdir app
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 16 >/dev/null
"$BIN/vdb-to-gi" -q world.vdb -o app/world.gi.gz
"$BIN/gi-lightmap" -q "$DATA/world.glb" -o app/world-lit.glb
tarball=$(cd "$ROOT/web" && npm pack --silent --pack-destination "$OLDPWD")
tar tzf "$tarball" | sed 's|^package/||' | sort | tr '\n' ' '
echo
cd app
printf '{ "name": "scratch", "private": true, "type": "module" }\n' > package.json
npm install --offline --no-audit --no-fund --loglevel=error "../$tarball" "$ROOT/web/node_modules/three" \
    >/dev/null || echo "npm install failed"
awk '/<!-- example: main.js/ { on = 1; next } on && /^```js/ { take = 1; next }
     take && /^```/ { exit } take { print }' node_modules/vdbgi/README.md > main.js
echo "main.js: $(wc -l < main.js) lines from node_modules/vdbgi/README.md"
"$ROOT/web/node_modules/.bin/esbuild" main.js --bundle --format=esm --outfile=dist/main.js --log-level=error ||
    echo "esbuild failed"
printf '<!doctype html>\n<link rel="icon" href="data:,">\n<body style="margin:0">\n<script type="module" src="dist/main.js"></script>\n' \
    > index.html
node "$ROOT/tests/web/check_package.mjs" "$PWD"
