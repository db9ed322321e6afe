#!/usr/bin/env bash
# A one-node Slurm on this machine, on localhost only, for trying the farm scripts and for the
# integration test (tests/farm/slurm_test.sh): munge with a fresh key, slurmctld and slurmd
# with their configuration, state and logs under DIR. Needs root and Debian's slurm-wlm and
# munge (scripts/setup.sh --farm installs them). Every wait is bounded.
# Usage: scripts/farm/local_slurm.sh start DIR   (prints: export SLURM_CONF=DIR/slurm.conf)
#        scripts/farm/local_slurm.sh stop DIR
set -euo pipefail
action=${1:-}
dir=${2:-}
[ -n "$action" ] && [ -n "$dir" ] || { echo "usage: local_slurm.sh start|stop DIR" >&2; exit 2; }
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
conf="$dir/slurm.conf"

stop_pidfile() {
  local file=$1
  [ -f "$file" ] || return 0
  local pid
  pid=$(cat "$file")
  if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  fi
  rm -f "$file"
}

if [ "$action" = stop ]; then
  stop_pidfile "$dir/slurmd.pid"
  stop_pidfile "$dir/slurmctld.pid"
  stop_pidfile "$dir/munged.pid"
  exit 0
fi
[ "$action" = start ] || { echo "local_slurm: unknown action '$action'" >&2; exit 2; }
for tool in munged slurmctld slurmd sinfo sbatch; do
  command -v "$tool" >/dev/null ||
    { echo "local_slurm: $tool not found: run scripts/setup.sh --farm" >&2; exit 2; }
done

# munge: a key of our own, a socket and pid under DIR.
mkdir -p "$dir/munge" "$dir/state" "$dir/spool" "$dir/log"
chmod 700 "$dir/munge"
head -c 1024 /dev/urandom >"$dir/munge/munge.key"
chmod 400 "$dir/munge/munge.key"
munge_user=$(id -un)
munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/socket" \
  --pid-file="$dir/munged.pid" --log-file="$dir/log/munged.log" --seed-file="$dir/munge/seed"
for _ in $(seq 50); do [ -S "$dir/munge/socket" ] && break; sleep 0.1; done
munge --socket="$dir/munge/socket" -n | unmunge --socket="$dir/munge/socket" >/dev/null ||
  { echo "local_slurm: munge does not work; $dir/log/munged.log:" >&2; cat "$dir/log/munged.log" >&2; exit 1; }

# Free ports for the controller and the node daemon.
free_port() {
  python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
host=$(hostname -s)
cpus=$(nproc)
cat >"$conf" <<CONF
ClusterName=penumbra-local
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$munge_user
SlurmdUser=$munge_user
AuthType=auth/munge
AuthInfo=socket=$dir/munge/socket
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
JobCompType=jobcomp/none
SchedulerType=sched/backfill
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$conf"
slurmctld -f "$conf"
slurmd -f "$conf"
for _ in $(seq 100); do
  if sinfo -h -o %T 2>/dev/null | grep -q idle; then
    echo "export SLURM_CONF=$conf"
    exit 0
  fi
  sleep 0.2
done
echo "local_slurm: the node did not come up idle within 20 s; logs:" >&2
tail -n 20 "$dir/log/"*.log >&2
"$0" stop "$dir"
exit 1
