# Header values that are legal numbers but that no writer makes (issue 47, item 3), in a
# plain .gi of the compact layout (version 5) and of the seed layout (version 1): each
# reader refuses them naming the field, the C reader (gi-inspect), the JavaScript one
# (web/gi-format.js, through tests/js/read_gi.mjs) and the one written from
# docs/format.md (tests/gi_reader.py); the box moved whole by 1 km, and a range of 65504,
# still read. One line a case: what each reader said.
/usr/bin/python3 -c 'import numpy' 2>/dev/null || { echo "no numpy for /usr/bin/python3"; exit 77; }
"$BIN/gi-bake" -q "$DATA/room.obj" -o room.vdb --spacing 0.5 --rays 16 >/dev/null
for layout in compact seed; do
    "$BIN/vdb-to-gi" -q room.vdb -o room.gi.gz --layout $layout
    gzip -dc room.gi.gz > good.gi
    for case in rgbm_range=3.4e38 rgbm_range=1e-9 rgbm_range=65504 spacing=1e-6 \
        box_min=-3.4e38 box_far=1e10 box_twice=1 box_moved=1000; do
        /usr/bin/python3 - good.gi case.gi "$case" << 'PY'
import struct, sys
data = bytearray(open(sys.argv[1], 'rb').read())
name, value = sys.argv[3].split('=')
value = float(value)
f32 = lambda o: struct.unpack_from('<f', data, o)[0]  # noqa: E731
put = lambda o, v: struct.pack_into('<f', data, o, v)  # noqa: E731
lo, hi = [f32(48 + 4 * k) for k in range(3)], [f32(60 + 4 * k) for k in range(3)]
if name == 'rgbm_range':
    put(20, value)
elif name == 'spacing':
    put(72, value)
elif name == 'box_min':
    for k in range(3):
        put(48 + 4 * k, value)
elif name == 'box_far':
    put(48, value), put(60, 2 * value)
elif name == 'box_twice':
    put(60, hi[0] + (hi[0] - lo[0]))
elif name == 'box_moved':
    for k in range(3):
        put(48 + 4 * k, lo[k] + value), put(60 + 4 * k, hi[k] + value)
open(sys.argv[2], 'wb').write(data)
PY
        c=$("$BIN/gi-inspect" case.gi 2>&1 >/dev/null | sed 's/^gi-inspect: case.gi: //')
        js=$(node "$ROOT/tests/js/read_gi.mjs" case.gi | sed 's/^read .*//; s/^refused: //')
        py=$(/usr/bin/python3 "$ROOT/tests/gi_reader.py" case.gi 0,1,0 2>&1 >/dev/null | tail -n 1 |
            sed 's/^ValueError: //')
        echo "$layout $case: C: ${c:-read}; JS: ${js:-read}; Python: ${py:-read}"
    done
done
