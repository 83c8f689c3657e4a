# --budget (issue 39, item 4): vdb-to-gi converts at eps 0.1, 0.2, 0.4, then the same as
# .gi version 8 (where the converter chose 7, as it does for this world), then without the
# L2 terms, and keeps the first that fits; gi-bake keeps the finest spacing whose
# estimate fits. A budget that fits changes no byte; each tighter one gives the bytes of
# the ladder's step that fits, no more VRAM than asked; the figures it quotes are the
# CSV files' rows; what cannot fit or makes no sense is refused with one line, no output.
set -u
vram() { python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["vram_bytes"])' "$1"; }
"$BIN/gi-bake" -q "$DATA/world.glb" -o w.vdb --basis sh2 --spacing 1 --rays 16
for e in 0.1 0.2 0.4; do
    "$BIN/vdb-to-gi" -q w.vdb -o "l2-$e.gi.gz" --eps $e --stats "l2-$e.json"
done
for e in 0.1 0.2 0.4; do
    "$BIN/vdb-to-gi" -q w.vdb -o "v8-$e.gi.gz" --eps $e --gi-version 8 --stats "v8-$e.json"
done
for e in 0.1 0.2 0.4; do
    "$BIN/vdb-to-gi" -q w.vdb -o "scalar-$e.gi.gz" --eps $e --basis scalar --stats "scalar-$e.json"
done
v1=$(vram l2-0.1.json) v2=$(vram l2-0.2.json) v4=$(vram l2-0.4.json)
w1=$(vram v8-0.1.json) w2=$(vram v8-0.2.json) w4=$(vram v8-0.4.json)
vs=$(vram scalar-0.1.json) s2=$(vram scalar-0.2.json) s4=$(vram scalar-0.4.json)
echo "L2 at eps 0.1, 0.2, 0.4: $v1 $v2 $v4 bytes; version 8: $w1 $w2 $w4; scalar: $vs $s2 $s4" >&2
# The first step of the ladder that fits b bytes, as the file it must equal.
expect() {
    for f in l2-0.1:$v1 l2-0.2:$v2 l2-0.4:$v4 v8-0.1:$w1 v8-0.2:$w2 v8-0.4:$w4 scalar-0.1:$vs \
        scalar-0.2:$s2 scalar-0.4:$s4; do
        [ "${f#*:}" -le "$1" ] && { echo "${f%%:*}.gi.gz"; return; }
    done
    echo none
}
ok=1
for b in $((v1 * 2)) $v1 $((v1 - 1)) $v2 $v4 $((v4 - 1)) $w2 $w4 $((w4 - 1)) $vs $((vs - 1)) $s2 $s4; do
    mb=$(awk -v b="$b" 'BEGIN { printf "%.6f", b / 1e6 }')
    want=$(expect "$(awk -v m="$mb" 'BEGIN { printf "%.0f", m * 1e6 }')")
    rm -f got.gi.gz
    "$BIN/vdb-to-gi" w.vdb -o got.gi.gz --budget "$mb" --stats got.json >got.txt || ok=0
    got=$(vram got.json)
    if ! cmp -s got.gi.gz "$want" || [ "$got" -gt "$b" ]; then
        echo "FAIL: --budget $mb gave $got bytes, not $want's" >&2
        ok=0
    fi
done
[ $ok = 1 ] && echo "ok: each budget gives the first of eps 0.1, 0.2, 0.4 with the terms, then as version 8, then without, that fits, byte for byte"
# The curve quoted for 1 m, L2 at eps 0.1, is memory_world*.csv's.
"$BIN/vdb-to-gi" w.vdb -o got.gi.gz --budget 1000 | grep '^budget' >quoted.txt
row() { awk -F, '$1 == 1 && $2 == "compact" && $3 == "L2" && $4 == 0.1 {
    printf "%.1f %.1f\n", 100 * $16, 100 * $14 }' "$ROOT/docs/data/$1"; }
# shellcheck disable=SC2046 # each row is two words
set -- $(row memory_world.csv) $(row memory_world200.csv)
if grep -q "characters $1 % RMSE on the bundled world, $3 % on the 200 m world; surfaces $2 %, $4 %" \
    quoted.txt; then
    echo "ok: the quoted error is the CSV files' row for 1 m, L2, eps 0.1"
else
    echo "FAIL: quoted $(cat quoted.txt), the CSV files say $*"
fi
# Nothing fits: one line, exit 1, nothing written.
small=$(printf '%s\n' "$vs" "$s2" "$s4" | sort -n | head -n 1)
small=$(awk -v b="$small" 'BEGIN { printf "%.6f", (b - 1) / 1e6 }')
"$BIN/vdb-to-gi" -q w.vdb -o none.gi.gz --budget "$small" 2>err.txt
echo "exit $?, $(wc -l <err.txt) line, output $([ -e none.gi.gz ] && echo written || echo absent)"
sed 's/--budget [0-9.]* MB/--budget B MB/; s/takes [0-9.]* kB/takes N kB/' err.txt
for bad in 0 -1 nan abc 2e6; do
    "$BIN/vdb-to-gi" -q w.vdb -o bad.gi.gz --budget "$bad" 2>&1 | head -n 1
done
# --gi-version 7 asks for the terms' file; where only the scalar fits, the scalar is written.
mb=$(awk -v b="$vs" 'BEGIN { printf "%.6f", b / 1e6 }')
"$BIN/vdb-to-gi" -q w.vdb -o v7.gi.gz --gi-version 7 --budget "$mb" --stats v7.json &&
    cmp -s v7.gi.gz scalar-0.1.gi.gz && echo "ok: --gi-version 7 at the scalar's budget writes the scalar"
# gi-bake: the finest spacing whose 8-ray preview fits, halving from 4 m.
"$BIN/gi-bake" "$DATA/world.glb" -o b.vdb --budget 5 --rays 8 >bake.txt
grep -o '^probes .* spacing' bake.txt
# The preview's figures: the chosen spacing's within the budget, the next finer's past it,
# and the chosen one's the VRAM an 8-ray bake at that spacing converts to, less 7 %.
"$BIN/gi-bake" -q "$DATA/world.glb" -o p8.vdb --basis sh2 --spacing 1 --rays 8
"$BIN/vdb-to-gi" -q p8.vdb -o p8.gi.gz --stats p8.json
sed -n 's/^budget .*: \([0-9.]*\) m with the L2 terms, an estimated \([0-9.]*\) MB converted (an 8-ray preview.s, less 7 %) (\([0-9.]*\) m: \([0-9.]*\) MB).*/\1 \2 \3 \4/p' \
    bake.txt | awk -v real="$(vram p8.json)" '{
    d = $2 * 1.07 - real / 1e6
    ok = $1 == 1 && $2 <= 5 && $4 > 5 && $3 == 0.5 && d < 0.06 && d > -0.06
    printf "%s: %s m estimated at %s MB (an 8-ray bake converts to %.1f MB), %s m at %s MB\n",
        ok ? "ok" : "FAIL", $1, $2, real / 1e6, $3, $4 }'
"$BIN/gi-bake" -q "$DATA/world.glb" -o b.vdb --budget 0.5 --rays 8
"$BIN/vdb-to-gi" -q b.vdb -o b.gi.gz --budget 0.5 --stats b.json
echo "gi-bake and vdb-to-gi at 0.5 MB: $(python3 -c 'import json; j = json.load(open("b.json")); print(j["spacing"], "m,", "fits" if j["vram_bytes"] <= 5e5 else "does not fit")')"
# A keep box that no point of the 4 m and 2 m lattices falls in: those spacings are passed over.
"$BIN/gi-bake" "$DATA/world.glb" -o kb.vdb --budget 1 --keep-box 0.2,0.2,0.2,0.8,1.8,0.8 --rays 8 |
    grep -o '^probes .* spacing'
"$BIN/gi-bake" -q "$DATA/world.glb" -o tiny.vdb --budget 0.01 --rays 8
echo "exit $?, output $([ -e tiny.vdb ] && echo written || echo absent)"
"$BIN/gi-bake" -q "$DATA/world.glb" -o x.vdb --budget 5 --spacing 1 2>&1 | head -n 1
"$BIN/gi-bake" -q "$DATA/world.glb" -o x.vdb --budget 5 --tile 1/2 2>&1 | head -n 1
"$BIN/gi-bake" -q "$DATA/world.glb" -o x.vdb --budget 5 --basis ambient-cube 2>&1 | head -n 1
# gi-lightmap: the finest texel of the ladder whose atlases fit, found by unwrapping; the
# next finer (0.25 m, baked at --texel) past the budget.
lm() { python3 -c 'import json, sys; j = json.load(open(sys.argv[1])); print(j["texel"], j["vram_bytes"])' "$1"; }
"$BIN/gi-lightmap" -q "$DATA/world.glb" -o lm.glb --budget 1 --rays 4 --passes 1 --stats lm.json
"$BIN/gi-lightmap" -q "$DATA/world.glb" -o lm25.glb --texel 0.25 --rays 4 --passes 1 --stats lm25.json
# shellcheck disable=SC2046 # each is two words
set -- $(lm lm.json) $(lm lm25.json)
echo "gi-lightmap at 1 MB: $1 m texels, $([ "$2" -le 1000000 ] && echo fits || echo "does not fit"); $3 m: $([ "$4" -gt 1000000 ] && echo "past it" || echo "FAIL: fits too")"
# The quoted curves are lightmap_world.csv's and lightmap_interior.csv's rows: at 4 MB the
# texel is 0.125 m, one of theirs; at 1 MB 0.375 m, between theirs at 0.5 and 0.25 m.
row() { awk -F, -v t="$2" 'NR > 1 && $1 == t { printf "%.1f", 100 * $7 }' "$ROOT/docs/data/lightmap_$1.csv"; }
"$BIN/gi-lightmap" "$DATA/world.glb" -o lm.glb --budget 4 --rays 4 --passes 1 | grep '^budget' >q4.txt
"$BIN/gi-lightmap" "$DATA/world.glb" -o lm.glb --budget 1 --rays 4 --passes 1 | grep '^budget' >q1.txt
if grep -q "texels of 0.125 m, .*: surfaces $(row world 0.125) % RMSE on the bundled world (one pass, seed model), $(row interior 0.125) % on the interior" q4.txt &&
    grep -q "texels of 0.375 m, .* 0.5 m (surfaces $(row world 0.5) % RMSE on the bundled world, $(row interior 0.5) % on the interior) and 0.25 m ($(row world 0.25) %, $(row interior 0.25) %)" q1.txt; then
    echo "ok: the lightmap's quoted error is the CSV files' rows at 0.125 m, and at 0.5 and 0.25 m around 0.375 m"
else
    echo "FAIL: quoted $(cat q4.txt q1.txt)"
fi
"$BIN/gi-lightmap" -q "$DATA/world.glb" -o none.glb --budget 0.001 --rays 4
echo "exit $?, output $([ -e none.glb ] && echo written || echo absent)"
"$BIN/gi-lightmap" -q "$DATA/world.glb" -o x.glb --budget 1 --texel 0.5 2>&1 | head -n 1
"$BIN/gi-lightmap" -q "$DATA/world.glb" -o x.glb --budget 1 --layers 2>&1 | head -n 1
