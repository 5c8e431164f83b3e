#!/usr/bin/env bash
# End-to-end test of the Slurm recipe on this machine: installs Slurm and MUNGE (Debian's slurm-wlm, munge) if
# needed, starts a single-node cluster (munged, slurmctld, slurmd as root, configuration in a temporary directory),
# renders a scene in one process and as a 4-task job array plus the dependent merge job (submit.sh), and checks that
# the merged EXR is byte-identical to the one-process render. Prints the wall time. `.ci/run` calls it.
#
#   deploy/slurm/e2e.sh [path/to/prism]      (default: target/release/prism, built if missing)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
PRISM="$(realpath "${1:-$ROOT/target/release/prism}")"
[ -x "$PRISM" ] || (cd "$ROOT" && cargo build --release --bin prism)
start=$(date +%s)

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    echo "installing slurm-wlm and munge ..."
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null
    apt-get install -y -qq slurm-wlm munge >/dev/null
fi

WORK="$(mktemp -d /tmp/prism-slurm-XXXXXX)"
pids=()
cleanup() {
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    sleep 1
    for p in "${pids[@]}"; do kill -9 "$p" 2>/dev/null || true; done
    rm -rf "$WORK"
}
trap cleanup EXIT

# MUNGE: a fresh key and socket under $WORK.
mkdir -p "$WORK/munge" "$WORK/state" "$WORK/spool" "$WORK/log"
chmod 700 "$WORK/munge"
dd if=/dev/urandom of="$WORK/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$WORK/munge/munge.key"
munged --key-file="$WORK/munge/munge.key" --socket="$WORK/munge/munge.socket" \
    --pid-file="$WORK/munge/munged.pid" --log-file="$WORK/log/munged.log" --seed-file="$WORK/munge/seed" \
    --force --foreground >"$WORK/log/munged.out" 2>&1 &
pids+=($!)

NODE="$(hostname -s)"
CPUS="$(nproc)"
MEM="$(($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2))"
cat > "$WORK/slurm.conf" <<CONF
ClusterName=prism-e2e
SlurmctldHost=$NODE
AuthType=auth/munge
AuthInfo=socket=$WORK/munge/munge.socket
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/log/slurmctld.log
SlurmdLogFile=$WORK/log/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
SchedulerType=sched/backfill
NodeName=$NODE CPUs=$CPUS RealMemory=$MEM State=UNKNOWN
PartitionName=prism Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$WORK/slurm.conf"
slurmctld -D -f "$SLURM_CONF" >"$WORK/log/slurmctld.out" 2>&1 &
pids+=($!)
sleep 2
slurmd -D -f "$SLURM_CONF" >"$WORK/log/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 60); do
    state="$(sinfo -h -N -o '%t' 2>/dev/null | head -1 || true)"
    [ "$state" = "idle" ] && break
    sleep 1
done
if [ "$state" != "idle" ]; then
    echo "slurm node did not come up (state '$state')" >&2
    tail -n 20 "$WORK"/log/* >&2 || true
    exit 1
fi

SCENE="$ROOT/scenes/cornell_box.ron"
ARGS=(--size 64x64 --spp 32 --passes 8)
"$PRISM" render "$SCENE" "${ARGS[@]}" -q -o "$WORK/single.exr"
out="$(PRISM="$PRISM" OUTPUT=merged.exr "$ROOT/deploy/slurm/submit.sh" "$SCENE" 4 "$WORK/run" "${ARGS[@]}")"
echo "$out"
merge_job="${out##* }"
for _ in $(seq 300); do
    if ! squeue -h -j "$merge_job" 2>/dev/null | grep -q .; then break; fi
    sleep 1
done
if [ ! -f "$WORK/run/merged.exr" ]; then
    echo "the merge job produced no image" >&2
    tail -n 20 "$WORK"/run/*.log "$WORK"/log/* >&2 || true
    exit 1
fi
if cmp -s "$WORK/single.exr" "$WORK/run/merged.exr"; then
    echo "slurm e2e: 4-shard array + merge is byte-identical to the one-process render ($(( $(date +%s) - start )) s wall)"
else
    echo "slurm e2e: the merged image differs from the one-process render" >&2
    exit 1
fi
