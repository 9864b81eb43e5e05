#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for trying a sweep's job array (docs/sweeps.md):
# installs Debian's slurm-wlm and munge if missing, starts munged, slurmctld and slurmd on
# localhost with a configuration of their own in $LCJIT_SLURM (default /tmp/lcjit-slurm), and
# stops them on `cluster.sh stop`. Root only (the daemons run as root). Not part of the tests.
# Usage: bench/slurm/cluster.sh start | stop        (then: export SLURM_CONF=$LCJIT_SLURM/slurm.conf)
set -euo pipefail
dir=${LCJIT_SLURM:-/tmp/lcjit-slurm}
conf=$dir/slurm.conf

stop() {  # and wait for them to have ended (they write their state on the way out)
  local pids=()
  for p in slurmd slurmctld munged; do
    [ -f "$dir/$p.pid" ] && pids+=("$(cat "$dir/$p.pid")")
  done
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 1 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  done
  rm -f "$dir"/*.pid
}

case ${1:-} in
  stop) stop; exit 0 ;;
  start) ;;
  *) echo "usage: $0 start|stop" >&2; exit 2 ;;
esac

[ "$(id -u)" = 0 ] || { echo "cluster.sh: run as root (the daemons run as root)" >&2; exit 1; }
missing=()
for p in slurm-wlm munge; do dpkg-query -W -f='${Status}' $p 2>/dev/null | grep -q "install ok installed" || missing+=($p); done
if [ ${#missing[@]} -gt 0 ]; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
stop
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
# munge: a key of this cluster's own, a socket in $dir.
[ -f "$dir/munge/munge.key" ] || { mungekey --create --keyfile="$dir/munge/munge.key" --force; chmod 600 "$dir/munge/munge.key"; }
chmod 700 "$dir/munge"
munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" --pid-file="$dir/munged.pid" \
  --log-file="$dir/munged.log" --seed-file="$dir/munge/munge.seed" --force
host=$(hostname -s)
cpus=$(nproc)
cat > "$conf" <<CONF
ClusterName=lcjit
SlurmctldHost=$host
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=main Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$conf
slurmctld -f "$conf"
slurmd -f "$conf"
for _ in $(seq 1 50); do
  sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)' && break
  sleep 0.2
done
sinfo
echo "cluster.sh: up; export SLURM_CONF=$conf"
