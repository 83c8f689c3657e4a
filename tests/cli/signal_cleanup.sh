# SIGTERM while an output is being written leaves no temporary file and no
# output, and the process ends by the signal; a temporary left by a killed run
# (SIGKILL cannot be caught) is removed by the next run that writes the output.
"$BIN/gi-bake" -q "$DATA/world.glb" -o world.vdb --spacing 1 --rays 8 --basis ambient-cube
"$BIN/vdb-to-gi" -q world.vdb -o once.gi.gz || echo "convert failed"
caught=0
for try in 1 2 3 4 5 6 7 8 9 10; do
    rm -f out.gi.gz
    "$BIN/vdb-to-gi" -q world.vdb -o out.gi.gz --bevy out.ktx2 --res 64,32,64 &
    pid=$!
    # Wait for a temporary to appear, then terminate the writer.
    while kill -0 $pid 2>/dev/null; do
        set -- out.*.tmp-*
        if [ -e "$1" ]; then
            kill -TERM $pid
            caught=1
            break
        fi
    done
    wait $pid
    status=$?
    [ $caught = 1 ] && break
done
echo "caught during a write: $caught, status $status"
ls out.* 2>/dev/null | wc -l | sed 's/^/files left: /'
# A stale temporary of a process that is gone (pid 1 is never ours, so a dead pid is made).
sh -c 'exit 0' & dead=$!
wait $dead
touch "once.gi.gz.tmp-$dead-abcdef"
"$BIN/vdb-to-gi" -q world.vdb -o once.gi.gz || echo "convert failed"
ls once.gi.gz*
