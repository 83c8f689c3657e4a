#!/bin/sh
# run.sh: run every unit test program and CLI script, JOBS at a time (default: one more
# than the cores, as many tests wait on a browser, python or the disk); print each
# test's verdict as it ends, then each failure's output, the times slowest first (wall
# and CPU), the whole run's, and last "N passed, N failed".
# Unit tests print "ok - name" / "not ok - name" per test; a CLI script is one test
# (tests/cli/NAME.sh, with NAME.exit, NAME.stdout and NAME.stderr as expectations, or
# exit 77 and a line saying why when it cannot run on this machine;
# in those, '*' matches anything and every other character stands for itself).
# The slowest start first: by the last run's times (build/test-times.txt) when there
# are some, else the scripts whose first lines say "run: early". A script whose first
# lines say "run: alone" runs after the others, by itself.
set -u
BUILD=${BUILD:-build/release}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
JOBS=${JOBS:-$(($(nproc 2>/dev/null || echo 1) + 1))}
RESULTS=$(mktemp -d)
started=$(date +%s)
export BUILD ROOT RESULTS
trap 'rm -rf "$RESULTS"' EXIT

items=""
alone=""
for t in "$ROOT/$BUILD"/tests/test_*; do
    case "$t" in *.o | *.d) continue ;; esac
    [ -x "$t" ] && items="$items $t"
done
for s in "$ROOT"/tests/cli/*.sh; do
    [ -f "$s" ] || continue
    if head -n 5 "$s" | grep -q 'run: alone'; then alone="$alone $s"; else items="$items $s"; fi
done

order="$ROOT/build/test-times.txt"
if [ ! -f "$order" ]; then
    early=""
    rest=""
    for i in $items; do
        if head -n 5 "$i" 2>/dev/null | grep -aq 'run: early'; then early="$early $i"; else rest="$rest $i"; fi
    done
    items="$early $rest"
else
    items=$(for i in $items; do
        n=$(basename "$i" .sh)
        printf '%s %s\n' "$(awk -v n="$n" '$2 == n || $2 == "cli/" n { print $1; exit }' "$order")" "$i"
    done | sort -k1,1gr | cut -d' ' -f2)
fi
# shellcheck disable=SC2086
printf '%s\n' $items | xargs -P "$JOBS" -n 1 sh "$ROOT/tests/run_one.sh"
for s in $alone; do
    sh "$ROOT/tests/run_one.sh" "$s"
done

pass=0 fail=0 skip=0 failed_names=""
for i in "$ROOT/$BUILD"/tests/test_* "$ROOT"/tests/cli/*.sh; do
    case "$i" in *.o | *.d) continue ;; esac
    case "$i" in
    *.sh) key=cli_$(basename "$i" .sh) name=cli/$(basename "$i" .sh) ;;
    *) key=$(basename "$i") name=$key ;;
    esac
    [ -x "$i" ] || [ "${i%.sh}" != "$i" ] || continue
    if [ ! -f "$RESULTS/$key.count" ]; then # its runner died before the verdict
        echo "---- $name: no verdict"
        fail=$((fail + 1)) failed_names="$failed_names $name"
        continue
    fi
    read -r p f s names <"$RESULTS/$key.count"
    pass=$((pass + p)) fail=$((fail + f)) skip=$((skip + s))
    if [ "$f" -gt 0 ]; then
        cat "$RESULTS/$key.out"
        failed_names="$failed_names $names"
    fi
done
echo "times (seconds, slowest first, $JOBS at a time): wall, CPU, test"
cat "$RESULTS"/*.time | sort -k1,1gr | tee "$RESULTS/all-times" | awk '{ printf "  %6s  %6s  %s\n", $1, $3, $2 }'
# The whole run's wall time, and its CPU time over the cores: the least wall time any
# schedule of these tests could reach on this machine.
awk -v wall="$(($(date +%s) - started))" -v cores="$(nproc 2>/dev/null || echo 1)" \
    '{ cpu += $3 } END { printf "all: %d s wall; %.0f CPU-s, %.0f s a core on %d cores\n", wall, cpu, cpu / cores, cores }' \
    "$RESULTS/all-times"
mkdir -p "$ROOT/build" && cp "$RESULTS/all-times" "$order" 2>/dev/null

[ -n "$failed_names" ] && echo "failed:$failed_names"
if [ "$skip" -gt 0 ]; then
    echo "$pass passed, $fail failed, $skip skipped"
else
    echo "$pass passed, $fail failed"
fi
[ "$fail" -eq 0 ]
