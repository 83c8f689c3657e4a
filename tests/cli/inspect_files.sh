# gi-inspect reads a .vdb (metadata, --at) and a .gi.gz; it refuses a cut or damaged
# .gi.gz with one line and exit 1, never reading past the end.
# room.obj is closed and has no lamp: dark under the default physical model, lit by the
# seed model's ambient fill.
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --rays 16 --model seed >/dev/null
"$BIN/vdb-to-gi" -q room.vdb -o room.gi.gz
"$BIN/gi-inspect" room.vdb --at 0,1.5,0 | grep -E '^(probes|meta +(scene|rays)=|at )' | sed 's/-> .*/-> rgb/'
"$BIN/gi-inspect" room.gi.gz --at 0,1.5,0 | grep -E '^(encoding|at )' | sed 's/-> .*/-> rgb/'
size=$(wc -c < room.gi.gz)
head -c $((size / 2)) room.gi.gz > cut.gi.gz
"$BIN/gi-inspect" cut.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
cp room.gi.gz flip.gi.gz
printf '\377\377\377\377' | dd of=flip.gi.gz bs=1 seek=$((size / 2)) conv=notrunc 2>/dev/null
"$BIN/gi-inspect" flip.gi.gz >/dev/null 2>err; echo "exit $? lines $(wc -l < err)"
head -c $((size - 8)) room.gi.gz > notrailer.gi.gz
"$BIN/gi-inspect" notrailer.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
{ cat room.gi.gz; printf 'junk'; } > junk.gi.gz
"$BIN/gi-inspect" junk.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
head -c 20 room.gi.gz > tiny.gi.gz
"$BIN/gi-inspect" tiny.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
"$BIN/gi-inspect" room.vdb --at 500,500,500 >/dev/null 2>err; echo "exit $? $(cat err)"
# The volume budget (32 MiB by default, as the web loader's): an empty seed-layout volume
# of 60.8 MiB (version 1, a 1536x864x12 atlas) is refused from its header, saying how to
# lift it; --max-bytes lifts it.
python3 - <<'PY'
import gzip, struct
atlas = (1536, 864, 12)
h = b"vdbgi.gi" + struct.pack("<3If", 1, 112, 0, 8.0) + struct.pack("<6I", 4, 4, 4, *atlas)
h += struct.pack("<7f", 0, 0, 0, 16, 16, 16, 1) + struct.pack("<5I", 0, 0, 0, 0, 0)
h += struct.pack("<4I", 256, 4 * atlas[0] * atlas[1] * atlas[2], 0, 0)
with gzip.open("big.gi.gz", "wb", compresslevel=1) as f:
    f.write(h)
    left = 256 + 4 * atlas[0] * atlas[1] * atlas[2]
    while left:
        f.write(bytes(min(left, 1 << 24)))
        left -= min(left, 1 << 24)
PY
"$BIN/gi-inspect" big.gi.gz >/dev/null 2>err; echo "exit $? $(cat err)"
"$BIN/gi-inspect" big.gi.gz --max-bytes 64M | grep '^atlas'
