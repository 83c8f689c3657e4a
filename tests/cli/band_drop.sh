# tests/band_drop.py (docs/directional.md, "Bricks that drop bands") on the bundled
# world baked with L2 terms at 1 m: under seed 000's black sky no level-0 cell may drop
# every term even at 20 % error, and a few may keep L1 only; and it refuses probes
# without terms by name.
"$BIN/gi-bake" -q "$DATA/world.glb" -o sh.vdb --spacing 1 --rays 64 --basis sh2 >/dev/null
/usr/bin/python3 "$ROOT/tests/band_drop.py" sh.vdb
"$BIN/gi-bake" -q "$DATA/world.glb" -o plain.vdb --spacing 1 --rays 16 >/dev/null
/usr/bin/python3 "$ROOT/tests/band_drop.py" plain.vdb 2>&1
echo "exit $?"
