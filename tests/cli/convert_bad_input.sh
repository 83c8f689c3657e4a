# Bad .vdb inputs: one line naming the problem, exit 1, no output file; an existing
# output survives (two grids named irradiance: refused, not the first taken; eight
# probes 2000 spacings apart, or probes one per leaf: refused before gigabytes are
# spent; a conversion past --memory-limit: stopped, naming the file). The odd
# files are made with pyopenvdb (Debian's system python3).
"$BIN/gi-bake" -q "$DATA/room.obj" -o good.vdb --rays 8 >/dev/null
. "$ROOT/tests/cli/bad_vdb.inc"
make_bad_vdbs good.vdb
/usr/bin/python3 - <<'PY'
import pyopenvdb as vdb
a = vdb.Vec3SGrid(); a.name = "irradiance"; a.getAccessor().setValueOn((0, 0, 0), (1, 1, 1))
b = vdb.Vec3SGrid(); b.name = "irradiance"; b.getAccessor().setValueOn((0, 0, 0), (2, 2, 2))
vdb.write("twice.vdb", grids=[a, b])
# Eight probes 2000 spacings apart: the indirection would be 133 M cells (gigabytes).
g = vdb.Vec3SGrid(); g.name = "irradiance"
for i in range(8):
    g.getAccessor().setValueOn((i % 2 * 2000, i // 2 % 2 * 2000, i // 4 * 2000), (1, 1, 1))
vdb.write("sparse.vdb", grids=[g])
# Probes one per leaf: 9000 fill 72 000 cells (gigabytes at 200 000); 70 000
# would cost OpenVDB 6 kB a leaf (refused from the tree's bytes, before it reads).
for name, n in (("leaves9k.vdb", 9000), ("leaves70k.vdb", 70000)):
    g = vdb.Vec3SGrid(); g.name = "irradiance"; a = g.getAccessor()
    for k in range(n):
        a.setValueOn((k % 42 * 8, k // 42 % 42 * 8, k // 1764 * 8), (1, 1, 1))
    vdb.write(name, grids=[g])
PY
printf '\037\213keep' > out.gi.gz # a gzip magic, then data
for f in missing.vdb text.vdb truncated.vdb nogrid.vdb wrongtype.vdb empty.vdb twice.vdb sparse.vdb \
         leaves9k.vdb leaves70k.vdb; do
    "$BIN/vdb-to-gi" "$f" -o out.gi.gz 2>err >/dev/null
    echo "$? $(cat err)"
done
"$BIN/vdb-to-gi" good.vdb -o no/such/dir/out.gi.gz 2>err >/dev/null; echo "$? $(cat err)"
# Past a stated memory limit: one line naming the file, the output kept.
"$BIN/vdb-to-gi" good.vdb -o out.gi.gz --memory-limit 1M 2>err >/dev/null; echo "$? $(cat err)"
echo "out.gi.gz: $(tail -c 4 out.gi.gz)"
ls
