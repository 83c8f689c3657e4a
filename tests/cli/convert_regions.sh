# vdb-to-gi --region N converts region by region to the whole conversion's bytes
# and figures (scalar and L2, any region size and thread count); bad region
# sizes and options that need the whole lattice are refused in one line; damaged
# files are refused as the whole read refuses them. A lattice of whole equal leaves
# (which OpenVDB's clipped read prunes) converts alike too.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --rays 16 >/dev/null
"$BIN/gi-bake" -q "$DATA/world.glb" -o sh2.vdb --rays 16 --basis sh2 >/dev/null
figures() { grep -v -e seconds -e '"output"' -e convert_over_read -e memory_peak "$1"; }
# Whole leaves of equal probes: OpenVDB's clipped read prunes them into tiles,
# which must read back as the probes they are.
/usr/bin/python3 - <<'PY'
import pyopenvdb as vdb
g = vdb.Vec3SGrid(); g.name = "irradiance"; a = g.getAccessor()
v = vdb.FloatGrid(); v.name = "validity"; b = v.getAccessor()
for x in range(24):
    for y in range(8):
        for z in range(80):
            a.setValueOn((x, y, z), (0.5, 0.5, 0.5) if z < 40 else (0.2, 0.3, 0.4))
            b.setValueOn((x, y, z), 0.0)
vdb.write("flat.vdb", grids=[g, v])
# Two slabs of probes 84 points apart: a region and its halo between them read
# nothing, yet hold the + border of the coarse bricks below (it crashed once).
g = vdb.Vec3SGrid(); g.name = "irradiance"; a = g.getAccessor()
for x in range(32):
    for y in range(4):
        for z in list(range(32, 36)) + list(range(120, 128)):
            a.setValueOn((x, y, z), (0.5, 0.5, 0.5))
vdb.write("gap.vdb", grids=[g])
PY
for f in world sh2 flat gap; do
    "$BIN/vdb-to-gi" -q $f.vdb -o $f.gi.gz --stats $f.json
    for run in 32,1 32,2 96,2; do
        "$BIN/vdb-to-gi" -q $f.vdb -o r.gi.gz --stats r.json --region ${run%,*} --threads ${run#*,}
        if cmp -s $f.gi.gz r.gi.gz && figures $f.json > a.txt && figures r.json > b.txt &&
            cmp -s a.txt b.txt; then
            echo "$f, region ${run%,*}, ${run#*,} threads: the same bytes and figures"
        else
            echo "$f, region ${run%,*}, ${run#*,} threads: DIFFERENT"
        fi
    done
done
"$BIN/vdb-to-gi" -v sh2.vdb -o r.gi.gz --region 64 | grep -c '^memory  *peak'
for args in "--region 0" "--region 48" "--region x" "--region 64 --slices d" \
            "--region 64 --bevy b.ktx2" "--region 64 --layout seed"; do
    # shellcheck disable=SC2086
    "$BIN/vdb-to-gi" world.vdb -o bad.gi.gz $args 2>err >/dev/null
    echo "$? $(cat err)"
done
. "$ROOT/tests/cli/bad_vdb.inc"
make_bad_vdbs world.vdb
for f in missing.vdb text.vdb truncated.vdb nogrid.vdb wrongtype.vdb empty.vdb; do
    "$BIN/vdb-to-gi" "$f" -o out.gi.gz --region 32 2>err >/dev/null
    echo "$? $(cat err)"
done
ls bad.gi.gz out.gi.gz 2>&1 | sed 's/.*cannot access/cannot access/'
