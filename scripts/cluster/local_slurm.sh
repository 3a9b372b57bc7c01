#!/usr/bin/env bash
# A throw-away single-node Slurm cluster on this machine, everything under one folder (the e2e test
# tests/e2e/build_db_slurm.sh runs build_db_slurm.sh through it; a person can try the cluster scripts with it):
#
#   scripts/cluster/local_slurm.sh start DIR   # munged, slurmctld -D, slurmd -D in the background; waits until
#                                              # the node is idle; writes DIR/env.sh (source it: SLURM_CONF)
#   scripts/cluster/local_slurm.sh stop DIR    # cancels the jobs left, stops the three daemons it started
#
# Debian packages: slurm-wlm munge (scripts/install_deps.sh). A fresh munge key, slurm.conf, state and spool
# folders, pid and log files all live in DIR; nothing in /etc is touched. One node (`hostname -s` at 127.0.0.1)
# with nproc CPUs, process tracking by /proc (no cgroups), no task plugin, no accounting; the controller and the
# node daemon listen on two free TCP ports. Runs as root (CI) or as any user (then SlurmUser is that user).
set -euo pipefail
cmd="${1:-}" dir="${2:-}"
say() { echo "[local_slurm] $*"; }
die() { echo "[local_slurm] error: $*" >&2; exit 1; }
[ -n "$cmd" ] && [ -n "$dir" ] || die "usage: local_slurm.sh start|stop DIR"

free_port() { /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }

stop() {
  [ -f "$dir/slurm.conf" ] || return 0
  export SLURM_CONF="$dir/slurm.conf"
  # Jobs first, while the daemons can still end them; then the daemons, each by the pid this script recorded.
  if [ -f "$dir/slurmctld.pid" ] && kill -0 "$(cat "$dir/slurmctld.pid")" 2>/dev/null; then
    scancel --quiet --user="$(id -un)" 2>/dev/null || true
    for _ in $(seq 20); do
      [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break
      sleep 0.5
    done
  fi
  for d in slurmd slurmctld munged; do
    local pidfile="$dir/$d.pid"
    [ -f "$pidfile" ] || continue
    local pid
    pid="$(cat "$pidfile")"
    if kill -0 "$pid" 2>/dev/null; then
      kill "$pid" 2>/dev/null || true
      for _ in $(seq 20); do kill -0 "$pid" 2>/dev/null || break; sleep 0.25; done
      kill -0 "$pid" 2>/dev/null && kill -9 "$pid" 2>/dev/null || true
    fi
    rm -f "$pidfile"
  done
  say "stopped (logs in $dir)"
}

start() {
  for p in munged slurmctld slurmd sinfo; do
    command -v "$p" >/dev/null || [ -x "/usr/sbin/$p" ] || die "$p not found (Debian: apt install slurm-wlm munge)"
  done
  export PATH="$PATH:/usr/sbin"
  mkdir -p "$dir"
  dir="$(cd "$dir" && pwd)"
  chmod 700 "$dir"
  mkdir -p "$dir/munge" "$dir/state" "$dir/spool"
  chmod 700 "$dir/munge"
  local user node cpus
  user="$(id -un)"
  node="$(hostname -s)"
  cpus="$(nproc)"

  # munge: its own key, socket, pid, log and seed files; --force accepts a key folder under /tmp.
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$dir/munge/munge.key"
  munged --foreground --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.sock" \
    --pid-file="$dir/munge/munged.pid.file" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed" \
    </dev/null >"$dir/munged.out" 2>&1 &
  echo $! > "$dir/munged.pid"
  for _ in $(seq 40); do [ -S "$dir/munge/munge.sock" ] && break; sleep 0.25; done
  [ -S "$dir/munge/munge.sock" ] || { cat "$dir/munged.out" "$dir/munge/munged.log" 2>/dev/null >&2; die "munged did not start"; }

  cat > "$dir/slurm.conf" <<EOF
# Single-node Slurm written by scripts/cluster/local_slurm.sh
ClusterName=quasiloc-local
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.sock
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid.file
SlurmdPidFile=$dir/slurmd.pid.file
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$dir/slurm.conf"
  echo "export SLURM_CONF='$dir/slurm.conf'" > "$dir/env.sh"
  slurmctld -D -i </dev/null >"$dir/slurmctld.out" 2>&1 &
  echo $! > "$dir/slurmctld.pid"
  slurmd -D -N "$node" </dev/null >"$dir/slurmd.out" 2>&1 &
  echo $! > "$dir/slurmd.pid"
  local state=""
  for _ in $(seq 60); do
    state="$(sinfo -h -n "$node" -o %T 2>/dev/null || true)"
    [ "$state" = idle ] && break
    sleep 0.5
  done
  if [ "$state" != idle ]; then
    tail -5 "$dir/slurmctld.out" "$dir/slurmd.out" >&2 || true
    stop
    die "the node did not become idle in 30 s (state '${state:-no answer}'); logs in $dir"
  fi
  say "node $node idle ($cpus CPUs); source $dir/env.sh to use it"
}

case "$cmd" in
  start) start ;;
  stop) stop ;;
  *) die "unknown command '$cmd' (start or stop)" ;;
esac
