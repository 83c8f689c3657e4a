# Inconsistent packed (version 5) files: levels above the max, coarse blocks whose
# cells disagree, level bytes and header that count other bricks or points, sizes
# that do not add up, bricks placed outside the atlas, between its layers, over the
# block of zeros or over another brick's points, an atlas too large for its bricks,
# the older versions 3 and 4, a newer version 9, a scalar file labelled version 7 (L2
# terms), an unknown layout. Each is gzip'd whole, so only the
# readers' checks can catch it; the C reader (gi-inspect), the JavaScript one and the C
# one built to WebAssembly (the worker's, behind the JavaScript header checks) each
# refuse every one with one line, and read the good file. A header that counts more
# bricks than its stored points can hold is refused before anything is allocated for
# them; a file that unpacks to 50 MB past what its header declares, or whose header
# declares 33 M indirection cells for a few bricks, is refused from its first 112
# bytes, with the same message by both. Last, the textures (version 2) with the layout numbers written before
# they were the same everywhere (0 seed, 3 compact) are still read, alike.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 16 >/dev/null
"$BIN/vdb-to-gi" -q world.vdb -o good.gi.gz --eps 0.3
mkdir bad
node "$ROOT/tests/js/craft_packed.mjs" good.gi.gz bad > names.txt
read_js() { node "$ROOT/tests/js/read_gi.mjs" "$1"; } # "read ..." or "refused: ..."
printf 'good: C %s; JS %s\n' "$("$BIN/gi-inspect" good.gi.gz | grep -c '^bricks')" \
    "$(read_js good.gi.gz | cut -d' ' -f1)"
node "$ROOT/tests/js/check_wasm.mjs" good.gi.gz | sed 's/^WebAssembly/good: WASM/'
while read -r name; do
    "$BIN/gi-inspect" "bad/$name.gi.gz" > out.txt 2> err.txt
    code=$?
    echo "$name"
    echo "  C  (exit $code, $(wc -l < err.txt) line): $(sed 's/^gi-inspect: bad\///' err.txt)"
    echo "  JS $(read_js "bad/$name.gi.gz")"
    node "$ROOT/tests/js/check_wasm.mjs" "bad/$name.gi.gz" | sed 's/^WebAssembly/  WASM/'
done < names.txt
# Version 2 with the old compact number 3 reads as the same textures as with 2.
"$BIN/gi-inspect" good.gi.gz --textures new.gi > /dev/null
node -e "
const fs = require('fs'), b = fs.readFileSync('new.gi');
console.log('textures written with layout field', b.readUInt32LE(104));
b.writeUInt32LE(3, 104); fs.writeFileSync('old.gi', b);"
"$BIN/gi-inspect" old.gi --textures again.gi > /dev/null && cmp new.gi again.gi &&
    echo "old number 3: C reads the same textures"
gzip -n new.gi old.gi
printf 'old number 3: JS %s, as %s\n' "$(read_js old.gi.gz)" "$(read_js new.gi.gz)"
