#!/usr/bin/env bash
# A throwaway single-node Slurm cluster (slurmctld + slurmd on this machine,
# munge for authentication) for trying the recipes and for CI's integration
# test. Needs Debian's slurm-wlm and munge, and root (slurmd starts jobs as
# their submitting user).
#
#   deploy/slurm/single_node.sh start DIR   # writes DIR/slurm.conf, starts the daemons
#   export SLURM_CONF=DIR/slurm.conf        # then sbatch/squeue/scontrol use it
#   deploy/slurm/single_node.sh stop DIR
#
# `start` waits until the node is idle and exits non-zero, saying why, when
# the cluster cannot come up (the daemons' logs are in DIR).
set -euo pipefail

cmd=${1:?usage: single_node.sh start|stop DIR}
dir=$(mkdir -p "${2:?usage: single_node.sh start|stop DIR}" && cd "$2" && pwd)

stop() {
  for d in slurmd slurmctld munged; do
    if [ -f "$dir/$d.pid" ]; then
      kill "$(cat "$dir/$d.pid")" 2>/dev/null || true
      rm -f "$dir/$d.pid"
    fi
  done
}

if [ "$cmd" = stop ]; then
  stop
  exit 0
fi
[ "$cmd" = start ] || { echo "usage: single_node.sh start|stop DIR" >&2; exit 2; }
stop # a cluster left in DIR by an earlier run

for tool in slurmctld slurmd munged sbatch scontrol; do
  command -v "$tool" >/dev/null || { echo "single_node.sh: $tool not found (apt-get install slurm-wlm munge)" >&2; exit 1; }
done
if [ "$(id -u)" != 0 ]; then
  echo "single_node.sh: slurmd must run as root to start jobs" >&2
  exit 1
fi

host=$(hostname -s)
cpus=$(nproc)
mem_mb=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 512 ))
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"

# munge: its own key and socket, so nothing of the host's is touched.
if [ ! -f "$dir/munge/munge.key" ]; then
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1 count=1024 status=none
fi
chmod 700 "$dir/munge"
chmod 400 "$dir/munge/munge.key"
socket="$dir/munge/munge.socket"
munged --force --key-file="$dir/munge/munge.key" --socket="$socket" \
  --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" --seed-file="$dir/munge/seed"

cat > "$dir/slurm.conf" <<CONF
ClusterName=fogbank-ci
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
SlurmctldPort=${FOGBANK_SLURM_PORT:-16817}
SlurmdPort=$(( ${FOGBANK_SLURM_PORT:-16817} + 1 ))
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
MpiDefault=none
NodeName=$host CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=main Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"

slurmctld -i -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF" -N "$host"

for _ in $(seq 1 60); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -1 || true)
  case "$state" in
    idle|mix|alloc) echo "single-node Slurm up: node $host ($cpus CPUs), SLURM_CONF=$SLURM_CONF"; exit 0 ;;
  esac
  sleep 1
done
echo "single_node.sh: the node did not become idle within 60 s (state: ${state:-none})" >&2
tail -n 20 "$dir/slurmctld.log" "$dir/slurmd.log" "$dir/munged.log" >&2 || true
stop
exit 1
