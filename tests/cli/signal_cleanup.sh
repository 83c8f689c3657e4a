# SIGTERM while an output (or 86 of them) is being written leaves no temporary file and no
# output, and the process ends by the signal; a temporary left by a killed run
# (SIGKILL cannot be caught) is removed by the next run that writes the output.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 8 --basis ambient-cube
"$BIN/vdb-to-gi" -q world.vdb -o once.gi.gz || echo "convert failed"
# interrupt PATTERN COUNT COMMAND...: run COMMAND (first removing what PATTERN names)
# until COUNT temporaries match PATTERN.tmp-*, then SIGTERM it; up to ten tries, as a
# fast writer may finish first. Sets caught (1 once terminated) and status.
interrupt() {
    pattern=$1 count=$2
    shift 2
    caught=0
    for try in 1 2 3 4 5 6 7 8 9 10; do
        rm -f $pattern
        "$@" &
        pid=$!
        while kill -0 $pid 2>/dev/null; do
            n=0
            for t in $pattern.tmp-*; do [ -e "$t" ] && n=$((n + 1)); done
            if [ $n -ge $count ]; then
                kill -TERM $pid
                caught=1
                break
            fi
        done
        wait $pid
        status=$?
        [ $caught = 1 ] && break
    done
}
interrupt 'out.*' 1 "$BIN/vdb-to-gi" -q world.vdb -o out.gi.gz --bevy out.ktx2 --res 64,32,64
echo "caught during a write: $caught, status $status"
ls out.* 2>/dev/null | wc -l | sed 's/^/files left: /'
# A stale temporary of a process that is gone (pid 1 is never ours, so a dead pid is made).
sh -c 'exit 0' & dead=$!
wait $dead
touch "once.gi.gz.tmp-$dead-abcdef"
"$BIN/vdb-to-gi" -q world.vdb -o once.gi.gz || echo "convert failed"
ls once.gi.gz*
# More temporaries in flight than the handler once tracked (64): a --layers bake of 14
# lamps in 5 atlases holds 86 files until the end; SIGTERM with more than 64 of them
# written leaves none (it used to leave about 50).
/usr/bin/python3 - <<'PY'
v, faces, mtl = [], [], ["newmtl floor\nKd 0.7 0.7 0.7\n"]
def quad(x0, z0, x1, z1, y, m):
    b = len(v) + 1
    v.extend([(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)])
    faces.append((m, [(b, b + 2, b + 1), (b, b + 3, b + 2)]))
quad(-8, -8, 8, 8, 0, "floor")
for i in range(14):
    mtl.append("newmtl lamp%d\nKd 0.8 0.8 0.8\nKe %d 1 1\n" % (i, 1 + i))
    quad(-7 + i, -0.4, -6.4 + i, 0.4, 2.0, "lamp%d" % i)
open("lamps.mtl", "w").write("".join(mtl))
out = ["mtllib lamps.mtl"] + ["v %g %g %g" % p for p in v]
for m, tris in faces:
    out += ["usemtl " + m] + ["f %d %d %d" % t for t in tris]
open("lamps.obj", "w").write("\n".join(out) + "\n")
PY
interrupt 'lit.*' 65 "$BIN/gi-lightmap" -q lamps.obj -o lit.glb --layers --size 32 --texel 0.1
echo "layers: caught with more than 64 temporaries: $caught, status $status"
ls lit.* 2>/dev/null | wc -l | sed 's/^/files left: /'
