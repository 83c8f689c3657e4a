# The web package as a three.js developer meets it (web/README.md): npm pack web/,
# install the tarball and three into a scratch app, take main.js and index.html
# verbatim from the README, build the site with the README's esbuild commands and
# again with its Vite commands, as they are, and open each dist/index.html in
# headless Chromium: each draws the scene, and no page says a warning or an error.
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -x "$ROOT/web/node_modules/.bin/esbuild" ] ||
   [ ! -x "$ROOT/web/node_modules/.bin/vite" ]; then
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
# A block of the README, as the user's install holds it.
. "$ROOT/tests/cli/readme.inc"
block() { readme_block "$PWD/node_modules/vdbgi/README.md" "$1"; }
cd app
printf '{ "name": "scratch", "private": true, "type": "module" }\n' > package.json
# The bundlers from web/'s own install (offline: linked, as npm links a folder).
npm install --offline --no-audit --no-fund --loglevel=error "../$tarball" "$ROOT/web/node_modules/three" \
    "$ROOT/web/node_modules/esbuild" "$ROOT/web/node_modules/vite" >/dev/null || echo "npm install failed"
block main.js > main.js
block index.html > index.html
echo "main.js: $(wc -l < main.js) lines, index.html: $(wc -l < index.html) lines from node_modules/vdbgi/README.md"
cp -r . ../vite-app 2>/dev/null
block esbuild > build.sh
sh -e build.sh >/dev/null 2>build.err || { echo "the esbuild commands failed:"; head -5 build.err; }
cd ../vite-app
block vite > build.sh
sh -e build.sh >/dev/null 2>build.err || { echo "the Vite commands failed:"; head -5 build.err; }
cd ..
for site in app vite-app; do
    printf '%s: ' "$([ $site = app ] && echo esbuild || echo Vite)"
    node "$ROOT/tests/web/check_package.mjs" "$PWD/$site/dist"
done
