#!/usr/bin/env bash
# slurm-local.sh: a real, single-node Slurm cluster on this machine, for the
# integration tests that submit job arrays with sbatch and wait for them.
#
#   scripts/slurm-local.sh start    install (if missing), configure, start, wait until the node is idle
#   scripts/slurm-local.sh stop     stop the slurmd, slurmctld and munged this script started
#   scripts/slurm-local.sh status   exit 0 when sinfo answers and the node is idle/mixed/allocated
#
# Made for a fresh Debian/Ubuntu container run as root (CI) with no systemd:
# it installs slurm-wlm and munge with apt, and starts the daemons itself (no
# systemctl/service). The config is the default /etc/slurm/slurm.conf, so
# clients (sbatch, squeue, scontrol, sinfo) need no environment. Daemon state,
# logs and pid files live under $SLURM_LOCAL_STATE (default
# /var/lib/slurm-local); munged uses the standard /run/munge socket so that
# clients find it.
#
# Submitting and waiting (sacct needs slurmdbd, which is not set up here):
#   id=$(sbatch --parsable --array=0-3 --wrap '...')
#   dep=$(sbatch --parsable --dependency=afterok:$id --wrap '...')
#   while [ -n "$(squeue -h -j "$id,$dep" 2>/dev/null)" ]; do sleep 0.5; done
#   scontrol show job "$dep"    # JobState=COMPLETED / FAILED / CANCELLED ...
#
# Unusual settings in the generated slurm.conf, and why:
#   SlurmUser=root          no slurm-owned directories to prepare; fine for a throwaway test cluster.
#   SlurmctldHost=NAME(127.0.0.1), NodeAddr=127.0.0.1
#                           the short hostname need not resolve in a container.
#   ProctrackType=proctrack/linuxproc, TaskPlugin=task/none,
#   JobAcctGatherType=jobacct_gather/none
#                           no cgroup plugins: cgroups are usually not writable in a container.
#   SlurmdParameters=config_overrides
#                           trust CPUs/RealMemory from this file even if the hardware probe differs
#                           (otherwise a mismatch drains the node).
#   RealMemory              90% of MemTotal; memory is not a consumable resource (CR_Core), so
#                           it only needs to be <= the real memory.
#   ReturnToService=2       a node that was DOWN (e.g. slurmd restarted) comes back on registration.
#   DependencyParameters=kill_invalid_depend
#                           an afterok job whose dependency failed is cancelled (JobState=CANCELLED)
#                           instead of pending forever with Reason=DependencyNeverSatisfied. Since
#                           Slurm 20.11 it belongs here; under SchedulerParameters it is ignored
#                           silently (seen with 22.05). Per job: sbatch --kill-on-invalid-dep=yes.
#   SchedulerParameters=sched_interval=1,bf_interval=1
#                           run the periodic main and backfill passes every second (defaults 60 s
#                           and 30 s): a 4-task array on 2 CPUs plus an afterok job then takes 1-3 s
#                           end to end instead of 6-10 s (mostly thanks to bf_interval).
#   MinJobAge=600           finished jobs stay visible to squeue/scontrol show job for 10 min,
#                           which is how a test reads the final state without sacct.
#   KillWait=5, SlurmdTimeout=30
#                           quicker cancellation and quicker detection of a dead slurmd.
set -euo pipefail

STATE="${SLURM_LOCAL_STATE:-/var/lib/slurm-local}"
CONF=/etc/slurm/slurm.conf
MARKER="# written by scripts/slurm-local.sh"
HOST="$(hostname -s)"
TIMEOUT="${SLURM_LOCAL_TIMEOUT:-60}"

SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"

log() { echo "slurm-local: $*" >&2; }

# Is the process in pid file $1 alive and named $2?
alive() {
  local pf=$1 name=$2 pid
  [ -f "$pf" ] || return 1
  pid=$($SUDO cat "$pf" 2>/dev/null) || return 1
  [ -n "$pid" ] && [ -d "/proc/$pid" ] || return 1
  # A killed daemon may linger as a zombie until the container's init reaps it.
  [ "$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null)" != Z ] || return 1
  case "$(cat "/proc/$pid/comm" 2>/dev/null)" in "$name"*) return 0 ;; *) return 1 ;; esac
}

node_state() { { sinfo -h -n "$HOST" -o '%T' 2>/dev/null || true; } | head -n1; }

# Something listens on the slurmctld port (checked first: sinfo takes ~10 s to
# give up when no slurmctld runs).
ctld_listening() { (exec 3<>/dev/tcp/127.0.0.1/6817) 2>/dev/null; }

# A daemon this script started (its pid file exists) has died. sinfo alone
# would not tell: slurmctld reports a killed slurmd's node as idle for up to
# SlurmdTimeout.
ours_dead() {
  local d
  for d in slurmctld slurmd; do
    if [ -f "$STATE/run/$d.pid" ] && ! alive "$STATE/run/$d.pid" "$d"; then return 0; fi
  done
  return 1
}

cluster_ok() {
  ctld_listening || return 1
  ours_dead && return 1
  case "$(node_state)" in
    idle | mixed | allocated | completing | idle+* | mixed+* | allocated+*) return 0 ;;
    *) return 1 ;;
  esac
}

install_packages() {
  if command -v slurmctld >/dev/null 2>&1 && command -v slurmd >/dev/null 2>&1 \
    && command -v sbatch >/dev/null 2>&1 && command -v munged >/dev/null 2>&1; then
    return
  fi
  command -v apt-get >/dev/null 2>&1 || { log "slurm is not installed and apt-get is missing"; exit 1; }
  log "installing slurm-wlm and munge with apt"
  $SUDO apt-get update -qq
  # The postinst scripts try to start the services; in a container without
  # systemd that is refused (policy-rc.d) or fails harmlessly.
  $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    slurm-wlm munge >/dev/null
}

start_munge() {
  if [ -S /run/munge/munge.socket.2 ] && munge -n </dev/null | unmunge >/dev/null 2>&1; then
    return # already running (ours or the system's)
  fi
  if [ ! -s /etc/munge/munge.key ]; then
    log "creating /etc/munge/munge.key"
    $SUDO mkdir -p /etc/munge
    if command -v mungekey >/dev/null 2>&1; then
      $SUDO mungekey --create --keyfile=/etc/munge/munge.key --force
    else
      $SUDO dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
    fi
  fi
  $SUDO mkdir -p /run/munge /var/lib/munge /var/log/munge
  $SUDO chown munge:munge /etc/munge /etc/munge/munge.key /run/munge /var/lib/munge /var/log/munge
  $SUDO chmod 0700 /etc/munge /var/log/munge
  $SUDO chmod 0400 /etc/munge/munge.key
  $SUDO chmod 0755 /run/munge
  $SUDO rm -f /run/munge/munge.socket.2 /run/munge/munge.socket.2.lock /run/munge/munged.pid
  # munged refuses a key owned by another user, so it runs as munge (the key's owner).
  $SUDO runuser -u munge -- /usr/sbin/munged --force
  $SUDO touch "$STATE/run/munged.ours"
  local i
  for i in $(seq 1 50); do
    munge -n </dev/null | unmunge >/dev/null 2>&1 && return
    sleep 0.1
  done
  log "munged did not come up"; $SUDO tail -n 20 /var/log/munge/munged.log >&2 || true; exit 1
}

write_conf() {
  if [ -f "$CONF" ] && ! grep -qxF "$MARKER" "$CONF"; then
    log "$CONF exists and was not written by this script; refusing to overwrite it"; exit 1
  fi
  local cpus mem
  cpus=$(nproc)
  mem=$(awk '/^MemTotal:/ { printf "%d", $2 / 1024 * 0.9 }' /proc/meminfo)
  [ "$mem" -ge 1 ] 2>/dev/null || mem=1024
  $SUDO mkdir -p /etc/slurm
  $SUDO tee "$CONF" >/dev/null <<EOF
$MARKER
# (see the header of that script for why each setting is there)
ClusterName=local
SlurmctldHost=$HOST(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
SlurmctldPort=6817
SlurmdPort=6818
StateSaveLocation=$STATE/ctld
SlurmdSpoolDir=$STATE/slurmd
SlurmctldPidFile=$STATE/run/slurmctld.pid
SlurmdPidFile=$STATE/run/slurmd.pid
SlurmctldLogFile=$STATE/log/slurmctld.log
SlurmdLogFile=$STATE/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
MailProg=/bin/true
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
SchedulerParameters=sched_interval=1,bf_interval=1
DependencyParameters=kill_invalid_depend
SlurmdParameters=config_overrides
ReturnToService=2
MinJobAge=600
KillWait=5
SlurmdTimeout=30
InactiveLimit=0
NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
}

print_logs() {
  local f
  for f in "$STATE/log/slurmctld.log" "$STATE/log/slurmd.log" /var/log/munge/munged.log; do
    echo "----- tail $f" >&2
    $SUDO tail -n 30 "$f" >&2 2>/dev/null || echo "(missing)" >&2
  done
  echo "----- sinfo -N -l" >&2
  sinfo -N -l >&2 2>&1 || true
}

cmd_start() {
  local t0=$SECONDS
  if cluster_ok; then
    log "already running: node $HOST is $(node_state)"
    return 0
  fi
  install_packages
  $SUDO mkdir -p "$STATE/ctld" "$STATE/slurmd" "$STATE/run" "$STATE/log"
  start_munge
  write_conf
  if ! alive "$STATE/run/slurmctld.pid" slurmctld; then
    $SUDO slurmctld # forks into the background
  fi
  if ! alive "$STATE/run/slurmd.pid" slurmd; then
    $SUDO slurmd -N "$HOST"
  fi
  local resumed=0 st t1=$SECONDS
  while :; do
    if cluster_ok; then break; fi
    st=$(node_state)
    # A node left DOWN/DRAINED from an earlier run may not return by itself.
    if [ $resumed -eq 0 ] && [ $((SECONDS - t1)) -ge 2 ] && case "$st" in down* | drain* | *drain*) true ;; *) false ;; esac; then
      log "node $HOST is $st; resuming it"
      $SUDO scontrol update nodename="$HOST" state=resume || true
      resumed=1
    fi
    if [ $((SECONDS - t0)) -ge "$TIMEOUT" ]; then
      log "node $HOST not idle after ${TIMEOUT}s (state: '${st:-no answer}')"
      print_logs
      exit 1
    fi
    sleep 0.5
  done
  log "up: node $HOST is $(node_state) after $((SECONDS - t0))s (config $CONF, no environment needed)"
}

stop_pidfile() {
  local pf=$1 name=$2 pid i
  alive "$pf" "$name" || { $SUDO rm -f "$pf"; return 0; }
  pid=$($SUDO cat "$pf")
  $SUDO kill -TERM "$pid" 2>/dev/null || true
  for i in $(seq 1 100); do
    alive "$pf" "$name" || break
    sleep 0.1
  done
  if alive "$pf" "$name"; then
    log "$name ($pid) did not stop; killing it"
    $SUDO kill -KILL "$pid" 2>/dev/null || true
  fi
  $SUDO rm -f "$pf"
}

cmd_stop() {
  # Each takes 1-2 s to exit; stop both at once.
  stop_pidfile "$STATE/run/slurmd.pid" slurmd &
  stop_pidfile "$STATE/run/slurmctld.pid" slurmctld &
  wait
  if [ -f "$STATE/run/munged.ours" ]; then
    stop_pidfile /run/munge/munged.pid munged
    $SUDO rm -f "$STATE/run/munged.ours"
  fi
  log "stopped"
}

cmd_status() {
  if cluster_ok; then
    echo "node $HOST is $(node_state)"
    return 0
  fi
  if ours_dead; then
    echo "not running: a daemon this script started has died (pid files in $STATE/run)" >&2
  elif ctld_listening; then
    echo "not ready (node state: '$(node_state)')" >&2
  else
    echo "not running (nothing listens on port 6817)" >&2
  fi
  return 1
}

case "${1:-}" in
  start) cmd_start ;;
  stop) cmd_stop ;;
  status) cmd_status ;;
  *) echo "usage: $0 start|stop|status" >&2; exit 2 ;;
esac
