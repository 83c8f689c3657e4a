# The package's types (issue 40, item 4): tests/ts/example.ts, which uses every entry point
# ('vdbgi', 'vdbgi/webgpu', 'vdbgi/format', 'vdbgi/lightmap-layers', 'vdbgi/react',
# 'vdbgi/probe-grid') as an app would, compiles under tsc --strict against web/*.d.ts, resolved through
# web/package.json's exports as a user's node_modules would hold the package, with
# @types/three, React's types and React Three Fiber's; and an
# example with a wrong option, a misspelt export and a wrong argument fails as it should.
tsc="$ROOT/web/node_modules/typescript/bin/tsc"
[ -f "$tsc" ] && [ -d "$ROOT/web/node_modules/@types/three" ] || { echo "web/node_modules missing (make deps installs it)"; exit 77; }
mkdir -p node_modules/@types node_modules/@react-three
ln -s "$ROOT/web" node_modules/vdbgi
for m in three @types/three react @types/react @react-three/fiber; do
    ln -s "$ROOT/web/node_modules/$m" node_modules/$m
done
cp "$ROOT/tests/ts/example.ts" "$ROOT/tests/ts/tsconfig.json" .
node "$tsc" -p tsconfig.json && echo "example.ts: tsc --strict clean"
# Four mistakes a user makes: each must be an error.
sed -e 's/maxBytes: 2 \* MAX_BYTES,/maxBytes: "64M",/' \
    -e 's/gi.setKnobs(.character., /gi.setKnobs("hero", /' \
    -e 's/compositor.names()/compositor.layerNames()/' \
    -e "s/debug: 'level',/debug: 'levels',/" example.ts > wrong.ts
sed 's/example.ts/wrong.ts/' tsconfig.json > wrong.json
node "$tsc" -p wrong.json | sed -n 's/^wrong.ts([0-9,]*): error \(TS[0-9]*\).*/wrong.ts: \1/p'
# Every value each entry point exports is declared, and nothing it does not (tests/js/check_types.mjs).
node --no-deprecation "$ROOT/tests/js/check_types.mjs"
