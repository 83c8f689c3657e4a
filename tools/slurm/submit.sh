#!/bin/sh
# submit.sh [--wait] SCENE OUTDIR TILES [gi-bake options...]: bake SCENE on Slurm in TILES
# tiles (a job array of bake.sbatch), then merge and convert them (merge.sbatch, after every
# tile succeeded) into OUTDIR/world.vdb and OUTDIR/world.gi.gz. Run it on the login node, from
# anywhere; the binaries are found beside gi-bake on PATH, or in $VDBGI_BIN. Run it again
# after a failure: tiles already baked are kept. --wait: return when the merge is done,
# with its exit status (a failed tile cancels it). Prints the two job IDs. $VDBGI_SBATCH:
# more sbatch options for both jobs (a partition, an account, a time limit, --hold).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
wait=""
[ "${1:-}" = "--wait" ] && { wait="--wait"; shift; }
[ $# -ge 3 ] || { echo "usage: submit.sh [--wait] SCENE OUTDIR TILES [gi-bake options...]" >&2; exit 2; }
scene=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
mkdir -p "$2"
out=$(cd "$2" && pwd)
tiles=$3
shift 3
case "$tiles" in '' | *[!0-9]*) echo "submit.sh: TILES must be a number (got '$tiles')" >&2; exit 2 ;; esac
if [ "$tiles" -lt 2 ] || [ "$tiles" -gt 4096 ]; then
    echo "submit.sh: TILES must be in 2..4096 (got $tiles)" >&2
    exit 2
fi
bin=${VDBGI_BIN:-$(dirname "$(command -v gi-bake)")}
if [ ! -x "$bin/gi-bake" ] || [ ! -x "$bin/gi-merge" ]; then
    echo "submit.sh: no gi-bake and gi-merge in '$bin': put them on PATH or set VDBGI_BIN" >&2
    exit 2
fi
export VDBGI_BIN="$bin" VDBGI_SCENE="$scene" VDBGI_OUT="$out" VDBGI_TILES="$tiles" VDBGI_OPTIONS="$*"
rm -f "$out/merge.log" # its last line says the merge ran: no stale one from a run before
# shellcheck disable=SC2086
array=$(sbatch --parsable --export=ALL ${VDBGI_SBATCH:-} --array="1-$tiles" \
    -o "$out/tile%a.log" -e "$out/tile%a.log" "$here/bake.sbatch")
echo "tiles: job $array"
# shellcheck disable=SC2086
merge=$(sbatch --parsable --export=ALL ${VDBGI_SBATCH:-} --dependency="afterok:$array" \
    --kill-on-invalid-dep=yes -o "$out/merge.log" -e "$out/merge.log" $wait \
    "$here/merge.sbatch") && status=0 || status=$?
echo "merge: job ${merge:-?}"
[ -z "$wait" ] && exit "$status"
# A merge cancelled because a tile failed leaves sbatch --wait's status at 0: its log says.
if ! grep -q '^vdbgi: ' "$out/merge.log" 2>/dev/null; then
    failed=$(grep -l 'failed twice' "$out"/tile*.log 2>/dev/null | tr '\n' ' ' | sed 's/ $//')
    echo "submit.sh: the merge did not run${failed:+: failed tiles, see $failed}" >&2
    exit 1
fi
exit "$status"
