# Usage errors of vdb-to-gi and gi-inspect: one line and a hint, exit 2, nothing written.
for args in "in.vdb" "-o out.gi.gz" "a.vdb b.vdb -o out.gi.gz" "in.vdb -o o.gi.gz --eps -1" \
            "in.vdb -o o.gi.gz --eps x" "in.vdb -o o.gi.gz --max-level 4" \
            "in.vdb -o o.gi.gz --max-level -1" "in.vdb -o o.gi.gz --criterion best" \
            "in.vdb -o o.gi.gz --encoding bc6h" "in.vdb -o o.gi.gz --slice-axis w" \
            "in.vdb -o o.gi.gz --fill brightest" "in.vdb -o o.gi.gz --memory-limit 0" \
            "in.vdb -o o.gi.gz --memory-limit 2X" "in.vdb -o o.gi.gz --memory-limit 512K" \
            "in.vdb -o o.gi.gz --bogus"; do
    # shellcheck disable=SC2086
    "$BIN/vdb-to-gi" $args 2>err
    echo "$? $(head -n 1 err)"
done
"$BIN/gi-inspect" 2>err; echo "$? $(head -n 1 err)"
"$BIN/gi-inspect" f.gi --at 1,2 2>err; echo "$? $(head -n 1 err)"
ls
