#!/bin/sh
# run.sh: run every unit test program and CLI script; the last line is "N passed, N failed".
# Unit tests print "ok - name" / "not ok - name" per test; a CLI script is one test
# (tests/cli/NAME.sh, with NAME.exit, NAME.stdout and NAME.stderr as expectations, or
# exit 77 and a line saying why when it cannot run on this machine;
# in those, '*' matches anything and every other character stands for itself).
set -u
BUILD=${BUILD:-build/release}
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN="$ROOT/$BUILD/bin"
pass=0
fail=0
skip=0
failed_names=""

note_fail() {
    fail=$((fail + 1))
    failed_names="$failed_names $1"
}

for t in "$ROOT/$BUILD"/tests/test_*; do
    case "$t" in *.o | *.d) continue ;; esac
    [ -x "$t" ] || continue
    name=$(basename "$t")
    log=$(mktemp)
    (cd "$ROOT" && "$t") >"$log" 2>&1
    status=$?
    p=$(grep -c '^ok - ' "$log")
    f=$(grep -c '^not ok - ' "$log")
    pass=$((pass + p))
    fail=$((fail + f))
    if [ "$f" -gt 0 ] || [ "$status" -ne 0 ] || [ "$p" -eq 0 ]; then
        [ "$f" -gt 0 ] || note_fail "$name"
        echo "---- $name (exit $status)"
        cat "$log"
        failed_names="$failed_names $(sed -n 's/^not ok - //p' "$log" | tr '\n' ' ')"
    else
        echo "ok   $name ($p tests)"
    fi
    rm -f "$log"
done

# CLI scripts: run in an empty directory with BIN, DATA and ROOT set.
for s in "$ROOT"/tests/cli/*.sh; do
    [ -f "$s" ] || continue
    base=${s%.sh}
    name=$(basename "$base")
    dir=$(mktemp -d)
    (cd "$dir" && BIN="$BIN" DATA="$ROOT/data" ROOT="$ROOT" sh "$s" >"$dir/.stdout" 2>"$dir/.stderr")
    status=$?
    # Exit 77 (automake's convention): the script cannot run here, and says why.
    if [ "$status" = 77 ]; then
        skip=$((skip + 1))
        echo "skip cli/$name: $(head -n 1 "$dir/.stdout")"
        rm -rf "$dir"
        continue
    fi
    want=0
    [ -f "$base.exit" ] && want=$(cat "$base.exit")
    ok=1
    why=""
    if [ "$status" != "$want" ]; then ok=0; why="exit $status, expected $want"; fi
    for stream in stdout stderr; do
        if [ -f "$base.$stream" ]; then
            got=$(cat "$dir/.$stream")
            # Only '*' is a wildcard: brackets and '?' in expectations are literal.
            pattern=$(sed 's/[][?\\]/\\&/g' "$base.$stream")
            # shellcheck disable=SC2254
            case "$got" in $pattern) ;; *) ok=0; why="$why; $stream differs" ;; esac
        fi
    done
    if [ $ok = 1 ]; then
        pass=$((pass + 1))
        echo "ok   cli/$name"
    else
        note_fail "cli/$name"
        echo "---- cli/$name: $why"
        echo "stdout:"; cat "$dir/.stdout"
        echo "stderr:"; cat "$dir/.stderr"
    fi
    rm -rf "$dir"
done

[ -n "$failed_names" ] && echo "failed:$failed_names"
if [ "$skip" -gt 0 ]; then
    echo "$pass passed, $fail failed, $skip skipped"
else
    echo "$pass passed, $fail failed"
fi
[ "$fail" -eq 0 ]
