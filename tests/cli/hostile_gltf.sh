# Hostile glTF files (issue 27, tests/hostile/gltf): each is refused in one line naming the file
# and the problem, or baked with a warning, by gi-bake and gi-lightmap, within 20 s and
# 4 GB, leaving no output; emission out of range refused or capped with a warning. Before the checks: nodes 40 000 deep and extras 100 000 deep
# crashed (SIGSEGV in assimp and tinygltf), a FIFO buffer or image hung, a .glb whose JSON
# chunk claims 3 GiB took 3 GB, a node cycle, and 20 000 instances asked for 13 GB.
. "$ROOT/tests/cli/hostile.inc"
hostile_limit 4000
# The files are tests/hostile/gltf (its README says what each does wrong); the FIFOs
# they name are made here.
cp "$ROOT"/tests/hostile/gltf/* .
mv ORIGINAL_good.gltf good.gltf
mkfifo fifo.bin fifo.png
for f in deep_nodes.gltf deep_extras.gltf cycle.gltf fifo_buffer.gltf proc_buffer.gltf \
    instances.gltf huge_chunk.glb lenient_base64.gltf accessor_past_its_buffer.gltf \
    view_past_its_buffer.gltf fifo_image.gltf good.gltf; do
    for tool in gi-bake gi-lightmap; do
        ($limit; timeout 20 "$BIN/$tool" "$f" -o "out.$tool.$([ $tool = gi-bake ] && echo vdb || echo glb)" -q) >/dev/null 2>err
        rc=$?
        left=$(ls out.* 2>/dev/null | wc -l)
        echo "$tool $f: exit $rc, $(wc -l < err) line(s), $left output(s): $(head -n 1 err)"
        rm -f out.*
    done
done
# An OBJ texture naming a /proc file that claims to be regular and never ends: a warning.
printf 'mtllib proc.mtl\nv 0 0 0\nv 1 0 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n' > proc.obj
printf 'newmtl m\nmap_Kd /proc/self/pagemap\n' > proc.mtl
for tool in gi-bake gi-lightmap; do
    ($limit; timeout 20 "$BIN/$tool" proc.obj -o "out.$([ $tool = gi-bake ] && echo vdb || echo glb)") >/dev/null 2>err
    echo "$tool proc.obj: exit $?: $(grep -m 1 ignored err)"
    rm -f out.*
done
# Emission: refused where it is no light, capped at 10^6 with a warning where it is too much.
for f in strength_negative.gltf strength_huge.gltf factor_huge.gltf; do
    for tool in gi-bake gi-lightmap; do
        ($limit; timeout 20 "$BIN/$tool" "$f" -o "out.$([ $tool = gi-bake ] && echo vdb || echo glb)") >/dev/null 2>err
        echo "$tool $f: exit $?, $(ls out.* 2>/dev/null | wc -l) output(s): $(grep -m 1 -v '^gi-[a-z]*: [0-9]' err)"
        rm -f out.*
    done
done
# A room and one triangle 1000 km away: offsets are local (the room bakes as alone,
# tests/test_lights.c), and a warning says the far coordinates are coarse.
{ cat "$DATA/room.obj"; echo "v 1000000 0 0"; echo "v 1000001 0 0"; echo "v 1000000 0 1"; echo "f -3 -2 -1"; } > far.obj
cp "$DATA/room.mtl" . 2>/dev/null
for tool in gi-bake gi-lightmap; do
    ($limit; timeout 20 "$BIN/$tool" far.obj -o "out.$([ $tool = gi-bake ] && echo vdb || echo glb)") >/dev/null 2>err
    echo "$tool far.obj: exit $?: $(grep -m 1 'from the origin' err)"
    rm -f out.*
done
# Headers that declare more than the file holds (assimp reserves what they say: its own
# invalid/OutOfMemory.off, 309 bytes declaring 3.5 x 10^11 vertices, took 4.6 GB).
cp "$ROOT/tests/hostile/scenes/huge.off" "$ROOT/tests/hostile/scenes/huge.ply" .
# OBJ has no header: its faces are counted. 1.2 M faces of one vertex repeated (assimp
# holds ~230 B a face: ten million took 2.3 GB for no area), and one polygon of 20 M
# corners (more triangles than any scene may have).
python3 -c "
open('repeat.obj', 'w').write('v 0 0 0\\nv 1 0 0\\nv 0 0 1\\n' + 'f 1 1 1\\n' * 1200000 + 'f 1 2 3\\n')
open('polygon.obj', 'w').write('v 0 0 0\\nv 1 0 0\\nv 0 0 1\\nf' + ' 1 2' * 10000002 + '\\n')
open('repeat_cr.obj', 'w', newline='').write('v 0 0 0\\rv 1 0 0\\rv 0 0 1\\r' + 'f 1 1 1\\r' * 1200000)
open('two_corners.obj', 'w').write('v 0 0 0\\nv 1 0 0\\nv 0 0 1\\n' + 'f 1 2\\n' * 1200000 + 'f 1 2 3\\n')
open('continued.obj', 'w').write('v 0 0 0\\nv 1 0 0\\nv 0 0 1\\n' + 'f 1 \\\\\\n1 1\\n' * 1200000)
open('odd_blanks.obj', 'w').write('v 0 0 0\\nv 1 0 0\\nv 0 0 1\\nf 1\\v2\\f3 1 2 3\\x00f 1 2 3\\n')
"
# The same counted where assimp splits lines (\r alone, \f, \0, a backslash continuing
# one), for faces of fewer than three corners, and never stuck on an odd blank.
for f in huge.off huge.ply repeat.obj polygon.obj repeat_cr.obj two_corners.obj continued.obj \
    odd_blanks.obj; do
    ($limit; timeout 20 "$BIN/gi-bake" "$f" -o out.vdb) >/dev/null 2>err
    echo "gi-bake $f: exit $?, $(wc -l < err) line(s): $(head -n 1 err)"
    rm -f out.*
done
