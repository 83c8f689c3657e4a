# The .vdb opens in pyopenvdb (Debian's system python3): grids, transform, metadata,
# probe positions at origin + spacing * ijk, and the closed room's inside probes
# lit by ambient fill alone: at most albedo (<= 1) x ambient, so no sun got in.
# room.obj is closed and has no lamp: dark under the default physical model, lit by the
# seed model's ambient fill.
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --rays 64 --model seed --falloff inf >/dev/null
/usr/bin/python3 - <<'PY'
import pyopenvdb as vdb
grids, file_meta = vdb.readAll("room.vdb")
by = {g.name: g for g in grids}
irr, val = by["irradiance"], by["validity"]
print(sorted(by), irr.valueTypeName, val.valueTypeName)
print("voxel", irr.transform.voxelSize(), "origin", irr.transform.indexToWorld((0, 0, 0)))
print("counts equal", irr.activeVoxelCount() == val.activeVoxelCount() == irr["probes"])
print("meta", irr["rays"], irr["falloff"], irr["sampling"], irr["scene"], irr["triangles"])
# A probe well inside the room, above the floor and away from the table.
ijk = irr.transform.worldToIndexCellCentered((2.25, 1.75, 1.75))
rgb = irr.getConstAccessor().getValue(ijk)
print("inside lit", min(rgb) > 0.01, "no sun", max(rgb) <= 0.15 + 1e-6,
      "validity", val.getConstAccessor().getValue(ijk))
inside = outside = 0
acc = val.getConstAccessor()
for item in irr.citerOnValues():
    x, y, z = irr.transform.indexToWorld(item.min)
    if -3 < x < 3 and 0 < y < 3 and -2.5 < z < 2.5:
        inside += acc.getValue(item.min) <= irr["invalid_threshold"]
    else:
        outside += acc.getValue(item.min) > irr["invalid_threshold"]
print("inside valid", inside > 0, "outside invalid", outside > 0)
PY
# And back: a file pyopenvdb wrote, its grids stored as half floats, converts.
/usr/bin/python3 - <<'PY'
import pyopenvdb as vdb
grids, file_meta = vdb.readAll("room.vdb")
for g in grids:
    g.saveFloatAsHalf = True
vdb.write("half.vdb", grids=grids, metadata=file_meta)
PY
"$BIN/vdb-to-gi" half.vdb -o half.gi.gz >/dev/null && "$BIN/vdb-to-gi" room.vdb -o room.gi.gz >/dev/null
"$BIN/gi-inspect" half.gi.gz | grep -E "^(box|indirection)"
"$BIN/gi-inspect" room.gi.gz | grep -E "^(box|indirection)"
