# run: early (among the slowest, so started first)
# Generated damage to a .glb (issue 27): gi-lightmap's own output for the room, which
# has a texture and two UV sets, cut at 24 lengths and with 60 seeded byte flips
# (one to four bytes each), through gi-bake and gi-lightmap: each file bakes or is
# refused in one line of its own, within 20 s and 2 GB, and a refusal leaves no output.
. "$ROOT/tests/cli/hostile.inc"
hostile_limit 2000
"$BIN/gi-lightmap" -q "$DATA/room.obj" -o room.glb --size 128 --rays 8 || echo "no room.glb"
/usr/bin/python3 - <<'PY'
import random
data = open("room.glb", "rb").read()
n = len(data)
for k in range(24):
    open("cut%02d.glb" % k, "wb").write(data[: n * k // 24 + k])
rng = random.Random(27)
for k in range(60):
    d = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        d[rng.randrange(n)] = rng.randrange(256)
    open("flip%02d.glb" % k, "wb").write(bytes(d))
PY
files=0
odd=0
baked=0
for f in cut*.glb flip*.glb; do
    files=$((files + 1))
    for tool in gi-bake gi-lightmap; do
        case $tool in
        gi-bake) out=out.vdb; args="--rays 1 --spacing 1" ;;
        *) out=out.glb; args="--size 64 --rays 1 --passes 1" ;;
        esac
        ($limit; timeout 20 "$BIN/$tool" "$f" -o $out -q $args) >/dev/null 2>err
        rc=$?
        left=$(ls out.* 2>/dev/null | wc -l)
        run_outcome $tool $rc $left
        [ $rc -eq 0 ] && baked=$((baked + 1))
        if [ $outcome = odd ]; then
            echo "$tool $f: exit $rc, $own line(s) of its own, $left output(s): $(head -n 1 err)"
            odd=$((odd + 1))
        fi
        rm -f out.*
    done
done
echo "$files damaged .glb files through gi-bake and gi-lightmap: $odd handled otherwise than baked or refused in one line"
echo "$baked of $((2 * files)) runs baked" >&2
