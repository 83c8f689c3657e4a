#!/bin/sh
# scale.sh: `make bench-scale`, the figures of docs/scale.md in one run (about 10
# minutes on 2 cores). The 200 m world at 0.5 m in 1, 2, 4 and 8 tiles, one thread a
# tile, one after another: CPU seconds summed over the tiles, the largest tile's peak
# RSS, and the merge. Then the 4x world (400 m) at 0.25 m in 8 tiles on every core,
# merged and converted: each step's wall and CPU time and peak RSS, the peak the
# converter counts, and the conversion again under --memory-limit, at the figure
# it counted (the same bytes) and below it (refused); then region by region (--region
# 512, 256, 128), and under the limit the whole conversion was refused at. Writes
# build/bench/scale.md.
set -eu
BUILD=${BUILD:-build/release}
BIN=$BUILD/bin
OUT=build/bench
mkdir -p "$OUT/scale"
W=$OUT/scale
[ -f "$OUT/world200.glb" ] || python3 data/make_scenes.py --world 200 "$OUT/world200.glb"
[ -f "$OUT/world400.glb" ] || python3 data/make_scenes.py --world 400 "$OUT/world400.glb"

# run LABEL COMMAND...: COMMAND's wall seconds, CPU seconds and peak RSS (MB) into
# $wall $cpu $rss, and a row of the table.
run() {
    label=$1
    shift
    /usr/bin/time -f "%e %U %S %M" -o "$W/time.txt" "$@" >/dev/null
    read -r wall user sys kb < "$W/time.txt"
    cpu=$(echo "$user $sys" | awk '{printf "%.1f", $1 + $2}')
    rss=$((kb / 1000))
    echo "| $label | $wall s | $cpu s | $rss MB |"
}

{
    echo "## Tiles, $(date -u +%Y-%m-%d), $(nproc) cores: $(sed -n 's/^model name\t: //p' /proc/cpuinfo | head -n 1)"
    echo
    echo "### The 200 m world at 0.5 m, one thread a tile"
    echo
    echo "| tiles | CPU seconds, all tiles | against one process | largest tile's peak RSS | gi-merge |"
    echo "|---:|---:|---:|---:|---:|"
    whole=""
    for n in 1 2 4 8; do
        total=0 most=0
        i=1
        while [ "$i" -le "$n" ]; do
            if [ "$n" = 1 ]; then tile=""; else tile="--tile $i/$n"; fi
            # shellcheck disable=SC2086
            run tile "$BIN/gi-bake" -q "$OUT/world200.glb" -o "$W/t$i.vdb" --threads 1 $tile >/dev/null
            total=$(echo "$total $cpu" | awk '{print $1 + $2}')
            [ "$rss" -gt "$most" ] && most=$rss
            i=$((i + 1))
        done
        [ -z "$whole" ] && whole=$total
        merge=""
        if [ "$n" -gt 1 ]; then
            run merge "$BIN/gi-merge" "$W"/t*.vdb -o "$W/merged.vdb" >/dev/null
            merge="$wall s"
        fi
        echo "| $n | $total | $(echo "$total $whole" | awk '{printf "%.2f", $1 / $2}') | $most MB | $merge |"
        rm -f "$W"/t*.vdb
    done
    echo
    echo "### The 4x world (400 m) at 0.25 m in 8 tiles, each on $(nproc) threads"
    echo
    echo "| step | wall | CPU | peak RSS |"
    echo "|---|---:|---:|---:|"
    for i in 1 2 3 4 5 6 7 8; do
        run "tile $i of 8" "$BIN/gi-bake" -q "$OUT/world400.glb" -o "$W/t$i.vdb" --spacing 0.25 --tile "$i/8"
    done
    run gi-merge "$BIN/gi-merge" "$W"/t*.vdb -o "$W/world400.vdb"
    rm -f "$W"/t*.vdb
    run vdb-to-gi "$BIN/vdb-to-gi" "$W/world400.vdb" -o "$W/world400.gi.gz"
    echo
    "$BIN/vdb-to-gi" -v "$W/world400.vdb" -o "$W/again.gi.gz" | grep -e '^input' -e '^file' -e '^memory' |
        sed 's/^/    /'
    peak=$("$BIN/vdb-to-gi" -v "$W/world400.vdb" -o "$W/again.gi.gz" |
        sed -n 's/^memory *peak \([0-9.]*\) MiB.*/\1/p')
    limit=$(echo "$peak" | awk '{printf "%d", $1 + 1}')
    echo
    "$BIN/vdb-to-gi" -q "$W/world400.vdb" -o "$W/limited.gi.gz" --memory-limit "${limit}M"
    if cmp -s "$W/limited.gi.gz" "$W/world400.gi.gz"; then same="the same bytes"; else same="OTHER BYTES"; fi
    echo "--memory-limit ${limit}M (the counted peak, rounded up): $same"
    under=$((limit * 4 / 5))
    if "$BIN/vdb-to-gi" -q "$W/world400.vdb" -o "$W/refused.gi.gz" --memory-limit "${under}M" 2> "$W/err.txt"; then
        echo "--memory-limit ${under}M: NOT REFUSED"
    else
        echo "--memory-limit ${under}M: $(cat "$W/err.txt")"
    fi
    echo
    echo "### The same conversion region by region"
    echo
    echo "| --region | wall | CPU | peak RSS | counted peak | against the whole conversion |"
    echo "|---:|---:|---:|---:|---:|---|"
    for region in 512 256 128; do
        run "region $region" "$BIN/vdb-to-gi" "$W/world400.vdb" -o "$W/regions.gi.gz" --region "$region" >/dev/null
        counted=$("$BIN/vdb-to-gi" -v "$W/world400.vdb" -o "$W/regions.gi.gz" --region "$region" |
            sed -n 's/^memory *peak \([0-9.]*\) MiB.*/\1/p')
        if cmp -s "$W/regions.gi.gz" "$W/world400.gi.gz"; then same="the same bytes"; else same="OTHER BYTES"; fi
        echo "| $region | $wall s | $cpu s | $rss MB | $counted MiB | $same |"
    done
    if "$BIN/vdb-to-gi" -q "$W/world400.vdb" -o "$W/regions.gi.gz" --region 128 --memory-limit "${under}M" &&
        cmp -s "$W/regions.gi.gz" "$W/world400.gi.gz"; then
        echo
        echo "--region 128 --memory-limit ${under}M (the limit the whole conversion stopped at): the same bytes"
    else
        echo
        echo "--region 128 --memory-limit ${under}M: FAILED"
    fi
} | tee "$OUT/scale.md"
rm -f "$W"/*.vdb "$W"/*.gi.gz
