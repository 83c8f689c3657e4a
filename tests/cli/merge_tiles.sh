# A tiled bake (issue 28): the bundled world baked whole and in 4 tiles (on 1 and 2 threads),
# the tiles merged by gi-merge in any order, equal the whole bake probe for probe, bit for bit
# (compared in pyopenvdb under Debian's python3); broken sets and bad tiles are refused.
bake() { "$BIN/gi-bake" "$DATA/world.glb" --spacing 1 --rays 16 --sampling random "$@"; }
bake -q -o whole.vdb || echo "whole bake failed"
for i in 1 2 3 4; do
    bake -o tile$i.vdb --tile $i/4 --threads $((1 + i % 2)) | grep '^probes'
done
"$BIN/gi-merge" tile3.vdb tile1.vdb tile4.vdb tile2.vdb -o world.vdb | sed 's/ in [0-9.]* s$//;/^output/d'
/usr/bin/python3 "$ROOT/tests/cli/same_vdb.py" whole.vdb world.vdb
/usr/bin/python3 - world.vdb whole.vdb <<'PY'
import sys
import pyopenvdb as vdb
meta = vdb.read(sys.argv[1], "irradiance").metadata
print("tile keys left:", sorted(k for k in meta if k.startswith("tile") or k == "lattice_probes"))
print("probes", meta["probes"], "=", vdb.read(sys.argv[2], "irradiance").metadata["probes"])
PY
run() {
    "$BIN/gi-merge" "$@" -o out.vdb 2>err >/dev/null
    echo "$? $(cat err)"
}
bake -q -o other1.vdb --tile 1/4 --rays 32
bake -q -o three1.vdb --tile 1/3
run tile1.vdb tile2.vdb tile3.vdb
run tile1.vdb tile2.vdb tile3.vdb tile4.vdb tile2.vdb
run other1.vdb tile2.vdb tile3.vdb tile4.vdb
run tile1.vdb tile2.vdb three1.vdb tile4.vdb
run whole.vdb
run tile1.vdb missing.vdb
# Tiles of the same bake whose grids differ (edited in pyopenvdb): one short, one renamed,
# one of another type; the merge reads them a grid at a time and refuses each by name.
/usr/bin/python3 - <<'PY'
import pyopenvdb as vdb
grids, meta = vdb.readAll("tile2.vdb")
vdb.write("short2.vdb", grids=[g for g in grids if g.name != "stderr"], metadata=meta)
for g in grids:
    if g.name == "stderr":
        g.name = "noise"
vdb.write("renamed2.vdb", grids=grids, metadata=meta)
grids, meta = vdb.readAll("tile2.vdb")
vec = vdb.Vec3SGrid()
vec.name, vec.transform = "stderr", grids[0].transform
vec.getAccessor().setValueOn((0, 0, 0), (1, 1, 1))
vdb.write("typed2.vdb", grids=[vec if g.name == "stderr" else g for g in grids], metadata=meta)
PY
run tile1.vdb short2.vdb tile3.vdb tile4.vdb
run tile1.vdb renamed2.vdb tile3.vdb tile4.vdb
run tile1.vdb typed2.vdb tile3.vdb tile4.vdb
# The grids held past a stated memory limit: stopped, naming the tile, nothing written.
run tile1.vdb tile2.vdb tile3.vdb tile4.vdb --memory-limit 1M
"$BIN/gi-merge" tile1.vdb tile2.vdb tile3.vdb tile4.vdb -q -o out.vdb --memory-limit 1G && echo "merged under 1G"
"$BIN/gi-merge" tile1.vdb 2>&1; echo "exit $?"
"$BIN/gi-merge" -o out.vdb 2>&1; echo "exit $?"
for t in 0/4 5/4 1/1 2 x/4; do
    bake -q -o x.vdb --tile $t 2>&1 | head -n 1
done
ls
