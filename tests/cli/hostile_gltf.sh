# Hostile glTF files, made here (issue 27): each is refused in one line naming the file
# and the problem, or baked with a warning, by gi-bake and gi-lightmap, within 20 s and
# 4 GB, leaving no output; emission out of range refused or capped with a warning. Before the checks: nodes 40 000 deep and extras 100 000 deep
# crashed (SIGSEGV in assimp and tinygltf), a FIFO buffer or image hung, a .glb whose JSON
# chunk claims 3 GiB took 3 GB, a node cycle, and 20 000 instances asked for 13 GB.
. "$ROOT/tests/cli/hostile.inc"
hostile_limit 4000
/usr/bin/python3 - <<'PY'
import base64, json, struct
tri = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 0, 1)
def gltf(nodes, buffer_uri=None, images=None, emissive=False, factor=1, strength=None):
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes,
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
         "buffers": [{"byteLength": 36, "uri": buffer_uri or
                      "data:application/octet-stream;base64," + base64.b64encode(tri).decode()}],
         "bufferViews": [{"buffer": 0, "byteLength": 36}],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                        "min": [0, 0, 0], "max": [1, 0, 1]}]}
    if emissive:
        g["materials"] = [{"name": "lamp", "emissiveFactor": [factor, factor, factor]}]
        if strength is not None:
            g["materials"][0]["extensions"] = {
                "KHR_materials_emissive_strength": {"emissiveStrength": strength}}
            g["extensionsUsed"] = ["KHR_materials_emissive_strength"]
        g["meshes"][0]["primitives"][0]["material"] = 0
    if images:
        g["images"] = [{"uri": u} for u in images]
    return g
def save(name, g, tail=""):
    s = json.dumps(g)
    open(name, "w").write(s[:-1] + tail + "}" if tail else s)
save("deep_nodes.gltf", gltf([{"children": [i + 1]} for i in range(39999)] + [{"mesh": 0}]))
save("deep_extras.gltf", gltf([{"mesh": 0}], emissive=True),
     ', "extras": ' + "[" * 100000 + "]" * 100000)
save("cycle.gltf", gltf([{"children": [1], "mesh": 0}, {"children": [2]}, {"children": [1]}]))
save("fifo_buffer.gltf", gltf([{"mesh": 0}], buffer_uri="fifo.bin"))
save("fifo_image.gltf", gltf([{"mesh": 0}], images=["fifo.png"], emissive=True))
save("proc_buffer.gltf", gltf([{"mesh": 0}], buffer_uri="/proc/self/pagemap"))
# A mesh instanced by 20 000 000 nodes would be 80 MB of JSON: 2000 nodes of a mesh
# whose accessor claims 10 001 triangles (the buffer is checked later) say the same.
g = gltf([{"children": list(range(1, 2001))}] + [{"mesh": 0}] * 2000)
g["accessors"][0]["count"] = 30003
save("instances.gltf", g)
# A .glb of 1 kB whose JSON chunk claims 3 GiB.
js = json.dumps(gltf([{"mesh": 0}])).encode()
js += b" " * (-len(js) % 4)
glb = struct.pack("<4sII", b"glTF", 2, 12 + 8 + len(js)) + struct.pack("<I4s", 3 << 30, b"JSON") + js
open("huge_chunk.glb", "wb").write(glb)
open("good.gltf", "w").write(json.dumps(gltf([{"children": [1]}, {"mesh": 0}])))
# Emission out of range: a negative strength is refused, a huge strength or factor capped.
save("strength_negative.gltf", gltf([{"mesh": 0}], emissive=True, strength=-50))
save("strength_huge.gltf", gltf([{"mesh": 0}], emissive=True, strength=1e9))
save("factor_huge.gltf", gltf([{"mesh": 0}], emissive=True, factor=1e9))
# An image's data: URI whose base64 tinygltf would decode leniently (padding inside, '!').
save("lenient_base64.gltf", gltf([{"mesh": 0}], images=["data:image/png;base64,iVBORw0KGgo=AAAA!!"]))
PY
mkfifo fifo.bin fifo.png
for f in deep_nodes.gltf deep_extras.gltf cycle.gltf fifo_buffer.gltf proc_buffer.gltf \
    instances.gltf huge_chunk.glb lenient_base64.gltf fifo_image.gltf good.gltf; do
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
# A room and one triangle 1000 km away: rays would start 10 m off every surface and the
# maps bake black; a warning says why (the bake goes on: the geometry may be meant).
{ cat "$DATA/room.obj"; echo "v 1000000 0 0"; echo "v 1000001 0 0"; echo "v 1000000 0 1"; echo "f -3 -2 -1"; } > far.obj
cp "$DATA/room.mtl" . 2>/dev/null
for tool in gi-bake gi-lightmap; do
    ($limit; timeout 20 "$BIN/$tool" far.obj -o "out.$([ $tool = gi-bake ] && echo vdb || echo glb)") >/dev/null 2>err
    echo "$tool far.obj: exit $?: $(grep -m 1 'far from the rest' err)"
    rm -f out.*
done
# Headers that declare more than the file holds (assimp reserves what they say: its own
# invalid/OutOfMemory.off, 309 bytes declaring 3.5 x 10^11 vertices, took 4.6 GB).
printf 'OFF\n353535235358 6 0\n-0.5 -0.5 0.5\n0.5 -0.5 0.5\n' > huge.off
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n' > huge.ply
# OBJ has no header: its faces are counted. 1.2 M faces of one vertex repeated (assimp
# holds ~230 B a face: ten million took 2.3 GB for no area), and one polygon of 20 M
# corners (more triangles than any scene may have).
python3 -c "
open('repeat.obj', 'w').write('v 0 0 0\\nv 1 0 0\\nv 0 0 1\\n' + 'f 1 1 1\\n' * 1200000 + 'f 1 2 3\\n')
open('polygon.obj', 'w').write('v 0 0 0\\nv 1 0 0\\nv 0 0 1\\nf' + ' 1 2' * 10000002 + '\\n')
"
for f in huge.off huge.ply repeat.obj polygon.obj; do
    ($limit; timeout 20 "$BIN/gi-bake" "$f" -o out.vdb) >/dev/null 2>err
    echo "gi-bake $f: exit $?, $(wc -l < err) line(s): $(head -n 1 err)"
    rm -f out.*
done
