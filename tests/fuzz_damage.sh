#!/bin/sh
# fuzz_damage.sh: `make fuzz`. Generated damage: CUTS cuts (48) of a real .vdb
# (an ambient-cube bake) and .gi.gz at evenly spaced points, and FLIPS (150)
# seeded byte flips of each, read by vdb-to-gi and gi-inspect within 20 s and
# 4 GB. A flip may leave a file that still reads (a changed value), so each
# run must either succeed or fail with one line naming the file; never crash,
# hang or leave an output. Prints the deviations (each damaged file kept as
# kept-* in the working directory, which is removed when there are none) and
# the count of runs; exits 1 if any. `make check` runs a smaller sample
# (tests/cli/damaged_files.sh); tests/test_damage.c makes every cut in process.
set -u
BUILD=${BUILD:-build/release}
CUTS=${CUTS:-48}
FLIPS=${FLIPS:-150}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${BIN:-$ROOT/$BUILD/bin}
DATA=${DATA:-$ROOT/data}
WORK=$(mktemp -d)
cd "$WORK" || exit 1
[ -n "${QUIET:-}" ] || echo "fuzz: working in $WORK"
"$BIN/gi-bake" -q "$DATA/room.obj" -o good.vdb --rays 8 --basis ambient-cube
"$BIN/vdb-to-gi" -q good.vdb -o good.gi.gz
limit="ulimit -v 4000000"
case "$BIN" in */asan/* | */ubsan/*) limit=true ;; esac
runs=0
bad=0
try() { # damaged file, command...
    f=$1
    shift
    ($limit; timeout 20 "$@") >/dev/null 2>err
    rc=$?
    runs=$((runs + 1))
    lines=$(wc -l < err)
    if [ $rc -ge 124 ] || { [ $rc != 0 ] && { [ "$lines" != 1 ] || ! grep -q "$f" err; }; } ||
        { [ $rc != 0 ] && [ -e out.gi.gz ]; }; then
        echo "DEVIATION: $f by $(basename "$1"): exit $rc, $lines lines"
        head -n 2 err
        cp "$f" "kept-$f"
        bad=$((bad + 1))
    fi
    rm -f out.gi.gz
}
damage() { # source, kind (vdb|gi)
    src=$1 kind=$2
    size=$(wc -c < "$src")
    i=1
    while [ $i -le "$CUTS" ]; do
        head -c $((size * i / (CUTS + 1))) "$src" > "cut.$kind"
        [ $kind = vdb ] && try "cut.$kind" "$BIN/vdb-to-gi" "cut.$kind" -o out.gi.gz -q
        try "cut.$kind" "$BIN/gi-inspect" "cut.$kind"
        i=$((i + 1))
    done
    seed=12345
    i=0
    while [ $i -lt "$FLIPS" ]; do
        seed=$(( (seed * 1103515245 + 12345) % 2147483648 ))
        off=$((seed % size))
        seed=$(( (seed * 1103515245 + 12345) % 2147483648 ))
        byte=$(( (seed >> 8) % 255 + 1 ))
        cp "$src" "flip.$kind"
        orig=$(od -An -tu1 -j $off -N 1 "$src" | tr -d ' ')
        printf "$(printf '\\%03o' $(( orig ^ byte )))" | dd of="flip.$kind" bs=1 seek=$off conv=notrunc 2>/dev/null
        [ $kind = vdb ] && try "flip.$kind" "$BIN/vdb-to-gi" "flip.$kind" -o out.gi.gz -q
        try "flip.$kind" "$BIN/gi-inspect" "flip.$kind"
        i=$((i + 1))
    done
}
damage good.vdb vdb
damage good.gi.gz gi
echo "$runs runs, $bad deviations"
[ "$bad" = 0 ] || exit 1
cd / && rm -rf "$WORK"
