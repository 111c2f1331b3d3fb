#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for testing `rbaa sweep --emit=slurm` against the real
# engine (tests/cli/test_cli_sweep.cpp). Debian 12's slurm-wlm (22.05) and munge; daemons are
# started directly (no systemd), as root, with their configuration, state and logs under
# $RBAA_SLURM_DIR (default /tmp/rbaa-slurm): nothing is written to /etc/slurm.
#
#   slurm_localhost.sh install   install slurm-wlm and munge (apt-get) if missing
#   slurm_localhost.sh start     write slurm.conf, start munged, slurmctld and slurmd; wait until the
#                                node takes jobs. Prints "export SLURM_CONF=..." on stdout; exit 0 if
#                                already running, 1 with the reason on stderr if it cannot start
#   slurm_localhost.sh status    exit 0 if this script's cluster is up and takes jobs
#   slurm_localhost.sh stop      stop the daemons this script started (by their pid files; a
#                                munged that was already running is left alone)
#
# Clients (sbatch, squeue) find the cluster through SLURM_CONF=$RBAA_SLURM_DIR/slurm.conf.
set -euo pipefail

DIR=${RBAA_SLURM_DIR:-/tmp/rbaa-slurm}
CTLD_PORT=${RBAA_SLURM_CTLD_PORT:-6817}
SLURMD_PORT=${RBAA_SLURM_SLURMD_PORT:-6818}
NODE=rbaa-local
CONF="$DIR/slurm.conf"

say() { echo "[slurm_localhost] $*" >&2; }
fail() { say "cannot start: $*"; exit 1; }

alive() { [ -f "$1" ] && kill -0 "$(cat "$1")" 2>/dev/null; }

install() {
  local missing=()
  for p in slurm-wlm munge; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ "${#missing[@]}" -eq 0 ] && return 0
  [ "$(id -u)" -eq 0 ] || fail "not root and ${missing[*]} not installed"
  say "installing: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

node_ready() {
  local state
  state=$(SLURM_CONF="$CONF" sinfo -h -n "$NODE" -o %T 2>/dev/null || true)
  case "$state" in idle* | mixed* | allocated*) return 0 ;; *) return 1 ;; esac
}

start() {
  [ "$(id -u)" -eq 0 ] || fail "slurmd must run as root (uid $(id -u))"
  for b in munged slurmctld slurmd sbatch sinfo; do
    command -v "$b" >/dev/null || fail "$b not found (run: $0 install)"
  done
  mkdir -p "$DIR/state" "$DIR/spool" "$DIR/munge"
  if alive "$DIR/slurmctld.pid" && alive "$DIR/slurmd.pid" && node_ready; then
    echo "export SLURM_CONF=$CONF"
    return 0
  fi

  # munge: a key (Debian's postinst makes one; make it if absent) and a daemon with its own socket.
  if [ ! -s /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    if command -v mungekey >/dev/null; then mungekey --create --keyfile=/etc/munge/munge.key
    else dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none; fi
    chown munge:munge /etc/munge/munge.key 2>/dev/null || true
    chmod 400 /etc/munge/munge.key
  fi
  mkdir -p /run/munge /var/lib/munge /var/log/munge
  chown munge:munge /run/munge /var/lib/munge /var/log/munge 2>/dev/null || true
  if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
    if id munge >/dev/null 2>&1; then
      runuser -u munge -- munged || fail "munged did not start"
    else
      munged --force || fail "munged did not start"
    fi
    cp /run/munge/munged.pid "$DIR/munged.pid" 2>/dev/null || true  # ours to stop
    for _ in $(seq 20); do munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && break; sleep 0.25; done
    munge -n | unmunge >/dev/null 2>&1 || fail "munge credentials do not round-trip"
  fi

  local cpus
  cpus=$(nproc)
  cat >"$CONF" <<EOF
# Written by scripts/slurm_localhost.sh: one node on this machine, for tests.
ClusterName=rbaa
SlurmctldHost=localhost
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/slurmctld.log
SlurmdLogFile=$DIR/slurmd.log
# No cgroups in a container without systemd: track processes by their parents, bind nothing.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
SlurmdTimeout=30
InactiveLimit=0
NodeName=$NODE NodeAddr=127.0.0.1 NodeHostname=$(hostname -s) CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF

  alive "$DIR/slurmctld.pid" || slurmctld -f "$CONF" -c || fail "slurmctld did not start (see $DIR/slurmctld.log)"
  alive "$DIR/slurmd.pid" || slurmd -f "$CONF" -N "$NODE" || fail "slurmd did not start (see $DIR/slurmd.log)"
  for _ in $(seq 60); do
    if node_ready; then
      echo "export SLURM_CONF=$CONF"
      return 0
    fi
    # A node that registered as down (e.g. after an unclean stop) is brought back once.
    SLURM_CONF="$CONF" scontrol update nodename="$NODE" state=resume >/dev/null 2>&1 || true
    sleep 0.5
  done
  fail "node $NODE not idle after 30 s: $(SLURM_CONF="$CONF" sinfo -h -N -o '%N %T %E' 2>&1 | head -1); see $DIR/*.log"
}

stop() {
  for d in slurmd slurmctld munged; do
    if alive "$DIR/$d.pid"; then
      kill "$(cat "$DIR/$d.pid")"
      for _ in $(seq 20); do alive "$DIR/$d.pid" || break; sleep 0.25; done
    fi
  done
}

case "${1:-}" in
  install) install ;;
  start) start ;;
  status) alive "$DIR/slurmctld.pid" && alive "$DIR/slurmd.pid" && node_ready ;;
  stop) stop ;;
  *) echo "usage: $0 install|start|stop" >&2; exit 2 ;;
esac
