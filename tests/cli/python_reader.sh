# tests/gi_reader.py, a reader written in Python from docs/format.md alone, agrees
# with the C sampler (gi-inspect --at) at 1000 points, in the seed layout (version
# 1), the compact layout packed (version 5, both encodings, with few and with many
# level seams to stitch), and the compact layout's textures (version 2); and between two
# floors 76 m apart, where columns hold no brick and read black (no lift).
/usr/bin/python3 -c 'import numpy' 2>/dev/null || { echo "no numpy for /usr/bin/python3"; exit 77; }
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 16 >/dev/null
set -- $(awk 'BEGIN { s = 4242; for (i = 0; i < 1000; i++) {
    s = (s * 1103515245 + 12345) % 2147483648; x = s / 2147483648 * 64 - 33;
    s = (s * 1103515245 + 12345) % 2147483648; y = s / 2147483648 * 18 - 3;
    s = (s * 1103515245 + 12345) % 2147483648; z = s / 2147483648 * 64 - 33;
    printf "%.4f,%.4f,%.4f ", x, y, z } }')
compare() {
    for p in "$@"; do printf -- '--at %s\n' "$p"; done | xargs "$BIN/gi-inspect" "$file" |
        sed -n 's/^at  *//p' > c.txt
    /usr/bin/python3 "$ROOT/tests/gi_reader.py" "$file" "$@" > py.txt || return
    # gi-inspect prints 6 significant digits: the same float32 agrees to that.
    paste -d' ' c.txt py.txt | awk -v name="$name" '
        { n++; lit += ($3 + $4 + $5 > 0); bad = 0
          for (k = 3; k <= 5; k++) { d = $k - $(k + 5); if (d < 0) d = -d
              m = $k < 0 ? -$k : $k; if (d > 1e-5 * m + 1e-9) bad = 1 }
          wrong += bad
          if (bad && wrong <= 3) print "  differs: " $0 }
        END { printf "%s: %d points, %d differ (%s)\n", name, n, wrong, (lit > n / 3 ? "most lit" : "few lit") }'
}
for run in seed,rgbm,0.2 compact,rgbm,0.2 compact,rgb9e5,0.2 compact,rgbm,5; do
    IFS=, read -r layout encoding eps <<RUN
$run
RUN
    "$BIN/vdb-to-gi" -q world.vdb -o w.gi.gz --layout $layout --encoding $encoding --eps $eps
    file=w.gi.gz name="version $(gzip -dc w.gi.gz | od -An -tu4 -j8 -N4 | tr -d ' '), $layout, $encoding, eps $eps"
    compare "$@"
done
"$BIN/gi-inspect" w.gi.gz --textures t.gi >/dev/null
file=t.gi name="version 2, compact textures" compare "$@"
printf 'v -42 0 -2\nv -38 0 -2\nv -38 0 2\nv -42 0 2\nv 38 0 -2\nv 42 0 -2\nv 42 0 2\nv 38 0 2\nf 4 3 2 1\nf 8 7 6 5\n' >gap.obj
"$BIN/gi-bake" -q gap.obj -o gap.vdb --spacing 1 --rays 16 --sky 0.5,0.5,0.5
"$BIN/vdb-to-gi" -q gap.vdb -o gap.gi.gz
file=gap.gi.gz name="version 5, two floors and empty columns between" compare $(awk 'BEGIN {
    for (i = 0; i <= 40; i++) printf "%.2f,0.5,0.3 ", -44 + i * 2.2 }')
