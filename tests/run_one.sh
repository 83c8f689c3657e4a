#!/bin/sh
# run_one.sh ITEM: run one test for tests/run.sh and leave its verdict in $RESULTS:
# NAME.out (what run.sh prints for it), NAME.count ("passed failed skipped") and
# NAME.time ("wall-seconds name CPU-seconds"). ITEM is a unit test program or a tests/cli/NAME.sh script.
set -u
item=$1
ROOT=${ROOT:?}
BIN="$ROOT/$BUILD/bin"
start=$(date +%s.%N)
case "$item" in
*.sh)
    base=${item%.sh}
    name=cli/$(basename "$base")
    key=cli_$(basename "$base")
    dir=$(mktemp -d)
    # Run in an empty directory with BIN, DATA and ROOT set.
    (cd "$dir" && BIN="$BIN" DATA="$ROOT/data" ROOT="$ROOT" sh "$item" >"$dir/.stdout" 2>"$dir/.stderr")
    status=$?
    if [ "$status" = 77 ]; then
        # Exit 77 (automake's convention): the script cannot run here, and says why.
        echo "skip $name: $(head -n 1 "$dir/.stdout")" >"$RESULTS/$key.out"
        echo "0 0 1" >"$RESULTS/$key.count"
    else
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
            echo "ok   $name" >"$RESULTS/$key.out"
            echo "1 0 0" >"$RESULTS/$key.count"
        else
            { echo "---- $name: $why"; echo "stdout:"; cat "$dir/.stdout"; echo "stderr:"; cat "$dir/.stderr"; } \
                >"$RESULTS/$key.out"
            echo "0 1 0 $name" >"$RESULTS/$key.count"
        fi
    fi
    rm -rf "$dir"
    ;;
*)
    name=$(basename "$item")
    key=$name
    log=$(mktemp)
    (cd "$ROOT" && "$item") >"$log" 2>&1
    status=$?
    p=$(grep -c '^ok - ' "$log")
    f=$(grep -c '^not ok - ' "$log")
    if [ "$f" -gt 0 ] || [ "$status" -ne 0 ] || [ "$p" -eq 0 ]; then
        # A program that failed without a failed test counts as one failure of its own.
        names=$(sed -n 's/^not ok - //p' "$log" | tr '\n' ' ')
        [ "$f" -gt 0 ] || { f=1; names="$name"; }
        { echo "---- $name (exit $status)"; cat "$log"; } >"$RESULTS/$key.out"
        echo "$p $f 0 $names" >"$RESULTS/$key.count"
    else
        echo "ok   $name ($p tests)" >"$RESULTS/$key.out"
        echo "$p 0 0" >"$RESULTS/$key.count"
    fi
    rm -f "$log"
    ;;
esac
end=$(date +%s.%N)
# The CPU seconds of the test and all it waited for (a browser its node closed
# included): the children's user and system time, the second line of times.
# (Into a file: in a pipe or $(...) times runs in a child, whose children are none.)
tf=$(mktemp)
times >"$tf"
cpu=$(awk 'NR == 2 { for (i = 1; i <= 2; i++) { split($i, t, "m"); c += 60 * t[1] + t[2] } print c }' "$tf")
rm -f "$tf"
echo "$start $end $name $cpu" | awk '{ printf "%.1f %s %.1f\n", $2 - $1, $3, $4 }' >"$RESULTS/$key.time"
# The verdict's first line as the test ends, so a long run shows its progress.
echo "$(head -n 1 "$RESULTS/$key.out") [$(cut -d' ' -f1 "$RESULTS/$key.time") s]"
