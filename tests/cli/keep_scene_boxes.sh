# Boxes the user names in the glTF (issue 39, item 2): a node named vdbgi_keep* is no
# geometry but a space what moves uses; gi-bake --keep-box scene keeps the probes of those
# boxes (their world bounds, node transforms applied). The marker neither occludes nor
# lights: the bake without the option is the bake of the scene without the marker, byte
# for byte; with it, the bake of --keep-box with the box's numbers, the marker at the root
# or under a moved parent. No marker, one without a vertex, or past 64 is refused with one
# line, by the bake that asks for them only.
set -u
python3 - "$DATA" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
from make_scenes import GlbWriter, Mesh

def ground(w):
    """The scene: a 10 m floor and a 2 x 3 x 2 m block, grey."""
    m = Mesh()
    m.quad((-5, 0, 5), (5, 0, 5), (5, 0, -5), (-5, 0, -5))
    m.box((-1, 0, -1), (1, 3, 1))
    w.node("ground", w.mesh("ground", m, w.material("grey", (0.6, 0.6, 0.6))))

def cube(w):
    """A marker's mesh: a 2 m cube, red (were it geometry, it would show)."""
    m = Mesh()
    m.box((0, 0, 0), (2, 2, 2))
    return w.mesh("marker", m, w.material("marker", (0.9, 0.1, 0.1)))

def scene(path, markers):
    w = GlbWriter()
    ground(w)
    mesh = cube(w) if markers else None
    for i in range(markers):
        # The first: a 2 m cube moved to x 2..4, y 0.5..2.5, z 1..3 by its node.
        w.node("vdbgi_keep_balcony" if i == 0 else "vdbgi_keep.%03d" % i, mesh,
               translation=(2, 0.5, 1) if i == 0 else (-4, 0, -4))
    w.write(path)

scene("plain.glb", 0)
scene("marked.glb", 1)
scene("many.glb", 65)

# The same box from a marker under a moved parent, and a marker with no mesh (an empty).
w = GlbWriter()
ground(w)
child = w.node("vdbgi_keep_nested", cube(w), translation=(1, 0.5, 1), root=False)
w.node("group", None, translation=(1, 0, 0), children=[child])
w.write("nested.glb")
w = GlbWriter()
ground(w)
w.node("vdbgi_keep_empty", None, translation=(2, 1, 2))
w.write("empty.glb")
PY
conv() { "$BIN/vdb-to-gi" -q "$1.vdb" -o "$1.gi.gz"; }
"$BIN/gi-bake" -q plain.glb -o plain.vdb --spacing 0.5 --rays 32 && conv plain
"$BIN/gi-bake" -q marked.glb -o marked.vdb --spacing 0.5 --rays 32 && conv marked
cmp -s plain.gi.gz marked.gi.gz && echo "ok: the marker is no geometry: the scene bakes as without it"
"$BIN/gi-bake" marked.glb -o info.vdb --spacing 0.5 --rays 32 | grep -o 'scene .*'
"$BIN/gi-bake" -q marked.glb -o kept.vdb --spacing 0.5 --rays 32 --keep-box scene && conv kept
"$BIN/gi-bake" -q plain.glb -o given.vdb --spacing 0.5 --rays 32 --keep-box 2,0.5,1,4,2.5,3 && conv given
cmp -s kept.gi.gz given.gi.gz && echo "ok: --keep-box scene keeps what --keep-box 2,0.5,1,4,2.5,3 keeps"
"$BIN/gi-bake" -q nested.glb -o nested.vdb --spacing 0.5 --rays 32 --keep-box scene && conv nested
cmp -s nested.gi.gz given.gi.gz && echo "ok: a marker under a moved parent gives the same box"
/usr/bin/python3 - <<'PY'
import pyopenvdb as vdb
g = vdb.read("kept.vdb", "irradiance")
xf = g.transform
inside = total = 0
for it in g.citerOnValues():
    if it.count != 1:
        continue
    x, y, z = xf.indexToWorld(it.min)
    total += 1
    inside += 2 <= x <= 4 and 0.5 <= y <= 2.5 and 1 <= z <= 3
print(f"{'ok' if total and inside == total else 'FAIL'}: {inside} of {total} kept probes in the box")
PY
"$BIN/gi-bake" -q plain.glb -o none.vdb --spacing 0.5 --keep-box scene 2>err.txt
echo "exit $?, $(wc -l <err.txt) line, output $([ -e none.vdb ] && echo written || echo absent)"
cat err.txt
"$BIN/gi-bake" -q empty.glb -o empty.vdb --spacing 0.5 --keep-box scene 2>&1
echo "exit $?"
# Markers past the most boxes stop only the bake that would use them.
"$BIN/gi-bake" -q many.glb -o many.vdb --spacing 0.5 --rays 8 && echo "65 markers, not used: baked"
"$BIN/gi-bake" -q many.glb -o many2.vdb --spacing 0.5 --keep-box scene 2>&1
echo "exit $?"
