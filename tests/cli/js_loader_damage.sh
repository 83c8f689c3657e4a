# The JavaScript loader (tests/js/gi_loader.mjs) refuses damaged .gi.gz files with an
# Error, as the C reader does: every prefix, a flip of every byte, flips of the .gi
# inside gzipped again, and a byte after the stream (tests/js/check_damage.mjs), for a
# small file in each brick layout.
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --spacing 1 --rays 16 >/dev/null
for layout in seed compact; do
    "$BIN/vdb-to-gi" -q room.vdb -o room.gi.gz --layout $layout
    printf '%s: ' $layout
    node "$ROOT/tests/js/check_damage.mjs" room.gi.gz
done
