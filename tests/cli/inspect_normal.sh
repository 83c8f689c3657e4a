# Directional probes (--basis sh2) read with a normal: over the open ground a
# surface facing down gets the lit ground, one facing up the black sky, one
# facing sideways lies between; the scalar reads the same whatever the normal.
# The bricks carry the terms (.gi version 7) and read alike.
# The L2 terms open in pyopenvdb as eight vec3s grids; a file missing one of
# them reads as scalar, one holding a NaN term is refused by name.
"$BIN/gi-bake" -q "$DATA/world.glb" -o sh.vdb --basis sh2 --rays 64 >/dev/null
"$BIN/gi-bake" -q "$DATA/world.glb" -o scalar.vdb --rays 64 >/dev/null
first() { "$BIN/gi-inspect" "$@" | sed -n 's/^at .*-> \([^ ]*\) \([^ ]*\) .*/\1 \2/p'; }
up=$(first sh.vdb --at 0,0.1,0 --normal 0,1,0)
down=$(first sh.vdb --at 0,0.1,0 --normal 0,-2,0)
side=$(first sh.vdb --at 0,0.1,0 --normal 1,0,0)
echo "$up|$down|$side" | awk -F'|' '{ split($1, u, " "); split($2, d, " "); split($3, s, " ");
    print "down > 5 x up:", (d[2] > 5 * u[2]) ? "yes" : "no";
    print "up < side < down:", (u[2] < s[2] && s[2] < d[2]) ? "yes" : "no" }'
a=$(first scalar.vdb --at 0,0.1,0 --normal 0,1,0)
b=$(first scalar.vdb --at 0,0.1,0 --normal 0,-1,0)
c=$(first scalar.vdb --at 0,0.1,0)
[ "$a" = "$b" ] && [ "$b" = "$c" ] && echo "scalar: one value for every normal"
"$BIN/gi-inspect" sh.vdb | grep -E '^meta +basis='
"$BIN/gi-inspect" sh.vdb --at 0,0.1,0 --normal 0,0,0 >/dev/null 2>err; echo "exit $? $(cat err)"
"$BIN/gi-inspect" sh.vdb --at 0,0.1,0 --normal 1,nan,0 >/dev/null 2>err; echo "exit $? $(cat err)"
# The same through the bricks (.gi version 7); a scalar .gi has no side to read.
"$BIN/vdb-to-gi" -q sh.vdb -o sh.gi.gz
"$BIN/vdb-to-gi" -q sh.vdb -o flat.gi.gz --basis scalar
up=$(first sh.gi.gz --at 0,0.1,0 --normal 0,1,0)
down=$(first sh.gi.gz --at 0,0.1,0 --normal 0,-1,0)
echo "$up|$down" | awk -F'|' '{ split($1, u, " "); split($2, d, " ");
    print "bricks: down > 5 x up:", (d[2] > 5 * u[2]) ? "yes" : "no" }'
"$BIN/gi-inspect" sh.gi.gz | sed -n 's/^\(basis  *L2: eight terms a texel beside the atlas\).*/\1/p'
"$BIN/gi-inspect" flat.gi.gz --at 0,0.1,0 --normal 0,1,0 >/dev/null 2>err; echo "exit $? $(cat err)"
/usr/bin/python3 - <<'PY'
import math
import pyopenvdb as vdb
grids, meta = vdb.readAll("sh.vdb")
sh = sorted(g.name for g in grids if g.name.startswith("irradiance_sh"))
print(sh[0], "..", sh[-1], len(sh), {g.valueTypeName for g in grids if g.name in sh})
vdb.write("seven.vdb", grids=[g for g in grids if g.name != "irradiance_sh5"], metadata=meta)
by = {g.name: g for g in grids}
item = next(by["irradiance"].citerOnValues())
by["irradiance_sh3"].getAccessor().setValueOn(item.min, (0.0, math.nan, 0.0))
vdb.write("nan.vdb", grids=grids, metadata=meta)
# A term five times its L0: no light that is nowhere negative gives it (the probes hold
# the terms as ratios to L0, which cannot pass +-4).
# (A lit probe: where L0 is under 1e-30 no terms are kept at all.)
by["irradiance_sh3"].getAccessor().setValueOn(item.min, (0.0, 0.0, 0.0))
lit = next(i for i in by["irradiance"].citerOnValues() if min(i.value) > 0.01)
by["irradiance_sh2"].getAccessor().setValueOn(lit.min, tuple(5 * c for c in lit.value))
vdb.write("beyond.vdb", grids=grids, metadata=meta)
by["irradiance_sh2"].getAccessor().setValueOn(lit.min, (0.0, 0.0, 0.0))
# A NaN L0 under sound terms: named as the L0 it is, not as the terms held relative to it.
by["irradiance_sh2"].getAccessor().setValueOn(item.min, (0.0, 0.0, 0.0))
by["irradiance"].getAccessor().setValueOn(item.min, (math.nan, 0.0, 0.0))
vdb.write("nanl0.vdb", grids=grids, metadata=meta)
PY
"$BIN/gi-inspect" seven.vdb --at 0,0.1,0 --normal 0,1,0 | sed -n 's/^at .*-> \([^ ]*\) \([^ ]*\) .*/\1 \2/p' > seven
[ "$(cat seven)" = "$(first scalar.vdb --at 0,0.1,0)" ] && echo "seven terms of eight: read as scalar"
"$BIN/gi-inspect" nan.vdb >/dev/null 2>err; echo "exit $? $(sed 's/probe [-0-9,]*/probe I,J,K/' err)"
"$BIN/gi-inspect" beyond.vdb >/dev/null 2>err; echo "exit $? $(sed 's/probe [-0-9,]*/probe I,J,K/' err)"
"$BIN/gi-inspect" nanl0.vdb >/dev/null 2>err; echo "exit $? $(sed 's/probe [-0-9,]*/probe I,J,K/; s/ (.*//' err)"
# The terms' rounding (--term-bits) and file version (--gi-version): every bit kept
# makes a larger file than the default 6 bits, which reads within half its step (2/127
# of each term's range R_k, times |p_k(n)|, times L0) of it; version 6 is larger still
# and reads the same (all three as version 7, every term in colour). Version 8 holds the
# second band in luminance: a smaller file still, and 14 bytes a texel on the GPU; the
# default writes it only where that moves a reading by under 4 %, which on this world's
# colours it does not. Nonsense is refused by name.
"$BIN/vdb-to-gi" -q sh.vdb -o eight.gi.gz --term-bits 8 --stats eight.json --gi-version 7
"$BIN/vdb-to-gi" -q sh.vdb -o six.gi.gz --gi-version 6 --term-bits 8
"$BIN/vdb-to-gi" -q sh.vdb -o sh.gi.gz --stats sh.json --gi-version 7
"$BIN/vdb-to-gi" -q sh.vdb -o luma.gi.gz --gi-version 8
[ "$(gzip -dc luma.gi.gz | od -An -tu4 -j8 -N4 | tr -d ' ')" = 8 ] && [ "$(wc -c < luma.gi.gz)" -lt "$(wc -c < sh.gi.gz)" ] &&
    echo "files: version 8 < version 7, both at 6 bits"
"$BIN/gi-inspect" luma.gi.gz | grep '^basis'
"$BIN/vdb-to-gi" sh.vdb -o auto.gi.gz | sed -n 's/.*bits kept; \(.*\)), .*; the second band in luminance moves a reading by \([0-9.]*\)%/default: \1 (luminance would move a reading by \2 %)/p'
cmp -s auto.gi.gz sh.gi.gz && echo "default: the same file as --gi-version 7"
sed -n 's/.*"term_bits": \([0-9]*\).*/term bits: default \1/p' sh.json
sed -n 's/.*"term_bits": \([0-9]*\).*/term bits: asked \1/p' eight.json
size() { wc -c < "$1"; }
[ "$(size sh.gi.gz)" -lt "$(size eight.gi.gz)" ] && [ "$(size eight.gi.gz)" -lt "$(size six.gi.gz)" ] &&
    echo "files: 6 bits < 8 bits < 8 bits as version 6"
for n in 0,-1,0 0.6,0.8,0 -1,0,0; do
    a=$(first eight.gi.gz --at 0,0.1,0 --normal $n) b=$(first six.gi.gz --at 0,0.1,0 --normal $n)
    c=$(first sh.gi.gz --at 0,0.1,0 --normal $n) l0=$(first sh.gi.gz --at 0,0.1,0)
    [ "$a" = "$b" ] && echo "normal $n: version 6 reads as version 7" ||
        echo "normal $n: version 6 reads $b, 7 $a"
    echo "$a|$c|$l0|$n" | awk -F'|' '{ split($1, a, " "); split($2, c, " "); split($3, l, " ");
        split($4, n, ","); s = sqrt(n[1] ^ 2 + n[2] ^ 2 + n[3] ^ 2); x = n[1] / s; y = n[2] / s; z = n[3] / s;
        split("2 2 2 1.875 1.875 0.625 1.875 0.9375", R, " ");
        p[1] = x; p[2] = y; p[3] = z; p[4] = x * y; p[5] = y * z; p[6] = 3 * z * z - 1; p[7] = x * z; p[8] = x * x - y * y;
        b = 0; for (k = 1; k <= 8; k++) b += R[k] * (p[k] < 0 ? -p[k] : p[k]);
        bound = l[2] * b * 2 / 127 + 1e-6; d = a[2] - c[2]; if (d < 0) d = -d;
        print "normal " $4 ": 6 bits within half a step of 8 bits:", (d <= bound) ? "yes" : "no " d " > " bound }'
done
"$BIN/vdb-to-gi" -q sh.vdb -o x.gi.gz --term-bits 9 2>&1; echo "exit $?"
"$BIN/vdb-to-gi" -q sh.vdb -o x.gi.gz --gi-version 5 2>&1; echo "exit $?"
"$BIN/vdb-to-gi" -q sh.vdb -o x.gi.gz --gi-version 6 --basis scalar 2>&1; echo "exit $?"
[ -e x.gi.gz ] || echo "no x.gi.gz written"
