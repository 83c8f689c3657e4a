# vdbgi/react (issue 40, item 6): <GiLight> around a glTF that suspends while it loads,
# in React Three Fiber, draws the frame a plain three.js page draws with the README's
# recipe, pixel for pixel, and nothing with the light off (tests/web/check_react.mjs);
# and web/README.md's R3F example, its page and its esbuild commands taken as they are,
# builds and draws the scene.
if [ ! -x "${CHROMIUM:-/usr/bin/chromium}" ] || [ ! -d "$ROOT/web/node_modules/@react-three/fiber" ] ||
   [ ! -d "$ROOT/web/node_modules/esbuild" ]; then
    echo "chromium or web/node_modules missing (make deps installs both)"
    exit 77
fi
mkdir site
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 16 >/dev/null
"$BIN/vdb-to-gi" -q world.vdb -o site/world.gi.gz
cp "$DATA/world.glb" site/
node "$ROOT/tests/web/check_react.mjs" "$PWD/site"
# The README's example, in an app whose node_modules links web/'s (as web_types does).
. "$ROOT/tests/cli/readme.inc"
block() { readme_block "$ROOT/web/README.md" "$1"; }
mkdir -p app/node_modules/@react-three app/node_modules/.bin
ln -s "$ROOT/web" app/node_modules/vdbgi
for m in three react react-dom @react-three/fiber esbuild; do
    ln -s "$ROOT/web/node_modules/$m" app/node_modules/$m
done
ln -s "$ROOT/web/node_modules/.bin/esbuild" app/node_modules/.bin/esbuild
cp site/world.glb site/world.gi.gz app/
cd app
block main.jsx > main.jsx
block r3f-index.html > index.html
block r3f-esbuild > build.sh
echo "main.jsx: $(wc -l < main.jsx) lines, index.html: $(wc -l < index.html) lines from web/README.md"
sh -e build.sh >/dev/null 2>build.err || { echo "the esbuild commands failed:"; head -5 build.err; }
printf 'README example: '
node "$ROOT/tests/web/check_package.mjs" "$PWD/dist" --r3f
