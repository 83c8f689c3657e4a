# Every damaged file of tests/hostile (copied from the reports that found them)
# is refused: exit 1 within 20 s under a 4 GB address-space limit, one line on
# stderr naming the file, no output left. The originals still convert, and a
# texture that is a device or claims 20000^2 pixels is a warning, not a hang or
# 6 GB.
H="$ROOT/tests/hostile"
# ASan reserves terabytes of address space, so under it the limit is its own:
# no single allocation above 4 GB.
limit="ulimit -v 4000000"
case "$BIN" in
*/asan/* | */ubsan/*)
    limit=true
    export ASAN_OPTIONS="allocator_may_return_null=1:max_allocation_size_mb=4000"
    ;;
esac
check() { # file, command...
    f=$1
    shift
    ($limit; timeout 20 "$@") >/dev/null 2>err
    rc=$?
    lines=$(wc -l < err)
    named=no
    grep -q "$(basename "$f")" err && named=yes
    left=$(ls out.* 2>/dev/null | wc -l)
    echo "$(basename "$f"): exit $rc, $lines line, names it: $named, outputs left: $left"
    rm -f out.*
}
for f in "$H"/vdb/*.vdb; do
    check "$f" "$BIN/vdb-to-gi" "$f" -o out.gi.gz -q
    check "$f" "$BIN/gi-inspect" "$f"
done
for f in "$H"/gi/*.gi.gz; do
    check "$f" "$BIN/gi-inspect" "$f"
done
for f in "$H"/scenes/*.obj; do
    ($limit; timeout 20 "$BIN/gi-bake" "$f" -o out.vdb --spacing 2 --rays 8) >/dev/null 2>err
    echo "$(basename "$f"): exit $?, $(sed -e 's/^gi-bake: warning: //' -e "s|$H/||g" err)"
    rm -f out.*
done
