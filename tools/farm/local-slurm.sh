#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for trying the farm recipes and for the tests:
#   tools/farm/local-slurm.sh start DIR   # munged, slurmctld and slurmd with their files in DIR
#   export SLURM_CONF=DIR/slurm.conf      # then sbatch, squeue, scancel, sinfo talk to it
#   tools/farm/local-slurm.sh stop DIR    # stops the three daemons (by the PIDs they wrote)
# Needs root (the daemons run as root) and Debian's slurm-wlm and munge (ci/install-deps.sh).
set -euo pipefail
command=${1:-}
dir=${2:-}
if [ -z "$command" ] || [ -z "$dir" ]; then
  echo "usage: $0 start|stop DIR" >&2
  exit 2
fi
dir=$(mkdir -p "$dir" && cd "$dir" && pwd)

stop() {
  for pidfile in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
    [ -f "$pidfile" ] || continue
    pid=$(cat "$pidfile")
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
    rm -f "$pidfile"
  done
}

case "$command" in
  stop)
    stop
    ;;
  start)
    if [ "$(id -u)" -ne 0 ]; then echo "$0: needs root to start munged, slurmctld and slurmd" >&2; exit 77; fi
    PATH=$PATH:/usr/sbin:/sbin  # the daemons live there, which a user's PATH may leave out
    for tool in munged slurmctld slurmd sinfo; do
      command -v "$tool" >/dev/null || { echo "$0: $tool not found (apt-get install slurm-wlm munge)" >&2; exit 77; }
    done
    host=$(hostname)
    mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
    chmod 700 "$dir/munge"
    [ -f "$dir/munge/munge.key" ] || { head -c 1024 /dev/urandom > "$dir/munge/munge.key"; chmod 400 "$dir/munge/munge.key"; }
    # Ports of their own, so that a cluster already on this machine is not disturbed.
    port=$((20000 + $$ % 20000))
    cat > "$dir/slurm.conf" <<CONF
ClusterName=ivgi-local
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.sock
CredType=cred/munge
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=main Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
    munged --force --socket="$dir/munge/munge.sock" --key-file="$dir/munge/munge.key" \
      --log-file="$dir/log/munged.log" --pid-file="$dir/munge/munged.pid" --seed-file="$dir/munge/munged.seed"
    export SLURM_CONF="$dir/slurm.conf"
    slurmctld -f "$SLURM_CONF"
    slurmd -f "$SLURM_CONF"
    for _ in $(seq 100); do
      if sinfo -h -o %T 2>/dev/null | grep -q idle; then exit 0; fi
      sleep 0.2
    done
    echo "$0: the node did not become idle; logs in $dir/log" >&2
    stop
    exit 1
    ;;
  *)
    echo "usage: $0 start|stop DIR" >&2
    exit 2
    ;;
esac
