# On a real Slurm (issue 28): a single-node cluster started here (munged, slurmctld, slurmd
# and a generated slurm.conf, all under a temporary directory, stopped at the end) bakes the
# bundled world in 4 tiles through tools/slurm/submit.sh: the merged grid equals a
# one-machine bake, bit for bit. Then a tile's job is killed: the merge never runs, and
# submitting again bakes that tile alone (the others are kept) and gives the same result.
# A tile that cannot be written fails twice and is reported by name.
for t in munged mungekey slurmctld slurmd sbatch squeue scancel scontrol sinfo; do
    command -v $t >/dev/null || { echo "no $t: make deps installs slurm-wlm and munge"; exit 77; }
done
[ "$(id -u)" = 0 ] || { echo "not root: the test cluster's daemons run as root"; exit 77; }
T=$(mktemp -d /tmp/vdbgi-slurm.XXXXXX)
chmod 700 "$T"
stop() {
    for d in slurmd slurmctld munged; do
        [ -f "$T/$d.pid" ] && kill "$(cat "$T/$d.pid")" 2>/dev/null
    done
    sleep 1
    rm -rf "$T"
}
trap stop EXIT
trap 'exit 1' INT TERM
mkdir -p "$T/state" "$T/spool"
mungekey -c -k "$T/munge.key" >/dev/null 2>&1
munged --force --key-file="$T/munge.key" --socket="$T/munge.sock" --pid-file="$T/munged.pid" \
    --log-file="$T/munged.log" --seed-file="$T/munged.seed" 2>/dev/null
port=$((20000 + $$ % 20000))
cat >"$T/slurm.conf" <<CONF
ClusterName=vdbgi
SlurmctldHost=$(hostname -s)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$T/munge.sock
CredType=cred/munge
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
NodeName=$(hostname -s) CPUs=$(nproc) RealMemory=$(free -m | awk '/^Mem:/ {print $2}') State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$T/slurm.conf"
slurmctld -f "$SLURM_CONF" 2>/dev/null
slurmd -f "$SLURM_CONF" 2>/dev/null
up=0
for _ in $(seq 30); do
    sinfo -h -o %t 2>/dev/null | grep -q idle && { up=1; break; }
    sleep 1
done
[ $up = 1 ] || { echo "the test cluster did not start: $(tail -n 1 "$T/slurmctld.log" 2>/dev/null)"; exit 77; }
echo "cluster up: $(sinfo -h -o '%P %D %t')"

opts="--spacing 1 --rays 16 --sampling random"
# shellcheck disable=SC2086
"$BIN/gi-bake" -q "$DATA/world.glb" -o whole.vdb $opts
submit() { VDBGI_BIN="$BIN" "$ROOT/tools/slurm/submit.sh" "$@"; }
# shellcheck disable=SC2086
submit --wait "$DATA/world.glb" run1 4 $opts | sed 's/job [0-9]*/job N/'
echo "first run:" run1/*
/usr/bin/python3 "$ROOT/tests/cli/same_vdb.py" whole.vdb run1/world.vdb

# Held, tile 3's job killed, the rest released: the merge is cancelled, nothing merged.
# shellcheck disable=SC2086
ids=$(VDBGI_SBATCH=--hold submit "$DATA/world.glb" run2 4 $opts | sed -n 's/.*job //p' | tr '\n' ' ')
# shellcheck disable=SC2086
set -- $ids
scancel "${1}_3"
scontrol release "$1"
scontrol release "$2"
for _ in $(seq 60); do
    [ -z "$(squeue -h -j "$1,$2" 2>/dev/null)" ] && break
    sleep 1
done
echo "killed tile 3:" run2/*.vdb "written"

# Resumed with a memory request: the merge and the conversion run under 4/5 of it.
# shellcheck disable=SC2086
VDBGI_SBATCH=--mem=1G submit --wait "$DATA/world.glb" run2 4 $opts | sed 's/job [0-9]*/job N/'
grep -h '^vdbgi tile' run2/tile*.log | sed 's|[^ ]*/run2/|run2/|; s/ (attempt 1)//'
grep -h '^vdbgi: --memory-limit' run2/merge.log
/usr/bin/python3 "$ROOT/tests/cli/same_vdb.py" whole.vdb run2/world.vdb

# A tile that cannot be written: tried twice, named, and the merge never runs.
mkdir -p run3/tile2.vdb
# shellcheck disable=SC2086
submit --wait "$DATA/world.glb" run3 4 $opts >/dev/null 2>err
echo "exit $?: $(sed 's|[^ ]*/run3/|run3/|' err)"
grep -h 'failed twice' run3/tile2.log | sed 's|[^ ]*/run3/|run3/|'
echo "world.vdb $([ -f run3/world.vdb ] && echo present || echo absent)"
