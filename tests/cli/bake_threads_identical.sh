# --threads 1 and --threads 2 give identical grids (every voxel's bits), for both samplings.
for s in fibonacci random; do
    "$BIN/gi-bake" -q "$DATA/world.glb" -o t1.vdb --spacing 1 --rays 32 --sampling $s --seed 5 --threads 1 >/dev/null
    "$BIN/gi-bake" -q "$DATA/world.glb" -o t2.vdb --spacing 1 --rays 32 --sampling $s --seed 5 --threads 2 >/dev/null
    /usr/bin/python3 - <<'PY'
import pyopenvdb as vdb, struct
def dump(path):
    out = []
    for name in ("irradiance", "validity"):
        g = vdb.read(path, name)
        for item in g.citerOnValues():
            v = item.value if isinstance(item.value, tuple) else (item.value,)
            out.append((name, item.min, struct.pack("<%df" % len(v), *v)))
    return out
a, b = dump("t1.vdb"), dump("t2.vdb")
print("identical" if a == b and len(a) > 1000 else "DIFFERENT (%d vs %d voxels)" % (len(a), len(b)))
PY
done
