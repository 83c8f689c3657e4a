# Inconsistent packed (version 4) files: levels above the max, coarse blocks whose
# cells disagree, level bytes and header that count other bricks or points, sizes
# that do not add up, an atlas the bricks do not pack into, the older version 3,
# an unknown layout. Each is gzip'd whole, so only the readers' checks can catch
# it; the C reader (gi-inspect) and the JavaScript one each refuse every one with
# one line, and read the good file, and the good file with the layout field that
# compact files had before the lift (2, docs/format.md). A header that counts more bricks than its stored
# points can hold is refused before anything is allocated for them.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 16 >/dev/null
"$BIN/vdb-to-gi" -q world.vdb -o good.gi.gz --eps 0.3
mkdir bad
node "$ROOT/tests/js/craft_packed.mjs" good.gi.gz bad > names.txt
cat > load.mjs <<JS
import { readFileSync } from 'node:fs';
import { loadGi } from '$ROOT/tests/js/gi_loader.mjs';
try {
  const gi = await loadGi(readFileSync(process.argv[2]));
  console.log('read', gi.bricks.join('/'));
} catch (e) {
  console.log('refused:', e.message);
}
JS
printf 'good: C %s; JS %s\n' "$("$BIN/gi-inspect" good.gi.gz | grep -c '^bricks')" \
    "$(node load.mjs good.gi.gz | cut -d' ' -f1)"
while read -r name; do
    "$BIN/gi-inspect" "bad/$name.gi.gz" > out.txt 2> err.txt
    code=$?
    echo "$name"
    echo "  C  (exit $code, $(wc -l < err.txt) line): $(sed 's/^gi-inspect: bad\///' err.txt)"
    echo "  JS $(node load.mjs "bad/$name.gi.gz")"
done < names.txt
