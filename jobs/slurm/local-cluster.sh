#!/bin/bash
# A one-node Slurm cluster on this machine (controller and compute daemon on
# localhost, munge authentication), for CI and for trying the Slurm path on a
# workstation.  Needs root and Debian's slurm-wlm and munge packages.
# Usage: local-cluster.sh start | stop
# start writes /etc/slurm/slurm.conf (never over one it did not write) and
# records the pid of each daemon it starts in /run/lem-local-cluster/; stop
# stops those and only those (a daemon already running is left alone).
set -euo pipefail
conf=/etc/slurm/slurm.conf
state=/run/lem-local-cluster
mark="# Written by jobs/slurm/local-cluster.sh"
die() { echo "local-cluster.sh: $*" >&2; exit 1; }
wait_pid_file() {  # wait_pid_file FILE: until the daemon has written it
  for _ in $(seq 100); do [ -s "$1" ] && return 0; sleep 0.1; done
  die "no pid file $1 after 10 s; logs in /var/log/slurm and /var/log/munge"
}
case "${1:-}" in
start)
  [ "$(id -u)" -eq 0 ] || die "needs root"
  command -v slurmctld > /dev/null || die "slurm-wlm is not installed"
  if [ -e "$conf" ] && [ "$(head -1 "$conf")" != "$mark: one node, this machine." ]; then
    die "$conf was not written by this script: a Slurm installation is configured here, not overwritten"
  fi
  host=$(hostname -s)
  cpus=$(nproc)
  mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 512 ))
  mkdir -p /var/spool/slurmctld /var/spool/slurmd /var/log/slurm /run/munge /etc/slurm "$state"
  chown munge:munge /run/munge
  [ -s /etc/munge/munge.key ] || { dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2> /dev/null
                                   chown munge:munge /etc/munge/munge.key; chmod 400 /etc/munge/munge.key; }
  if ! pgrep -x munged > /dev/null; then
    rm -f /run/munge/munged.pid
    runuser -u munge -- /usr/sbin/munged
    wait_pid_file /run/munge/munged.pid
    cp /run/munge/munged.pid "$state/munged.pid"
  fi
  # MpiDefault=pmix: srun starts Debian's Open MPI programs through PMIx.
  # cred_expire: a requeued job may start again after 10 s, not 120 s.
  cat > "$conf" <<CONF
$mark: one node, this machine.
ClusterName=lem-local
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
AuthInfo=cred_expire=10
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=pmix
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MaxArraySize=10000
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
CONF
  if ! pgrep -x slurmctld > /dev/null; then rm -f "$state/slurmctld.pid"; slurmctld -c; wait_pid_file "$state/slurmctld.pid"
  else scontrol reconfigure; fi  # running with an earlier version of this file
  if ! pgrep -x slurmd > /dev/null; then rm -f "$state/slurmd.pid"; slurmd; wait_pid_file "$state/slurmd.pid"; fi
  for _ in $(seq 30); do
    sinfo -h -o "%T" 2> /dev/null | grep -qE "idle|mixed|alloc" && { sinfo; exit 0; }
    sleep 1
  done
  echo "local-cluster.sh: the node did not come up; logs in /var/log/slurm" >&2
  sinfo >&2 || true
  exit 1
  ;;
stop)
  # compute daemon first, munge last; a pid whose process is not that
  # daemon any more (the pid reused) is left alone
  for daemon in slurmd slurmctld munged; do
    file="$state/$daemon.pid"
    [ -s "$file" ] || continue
    pid=$(cat "$file")
    if [ "$(cat "/proc/$pid/comm" 2> /dev/null)" = "$daemon" ]; then
      kill "$pid"
      for _ in $(seq 100); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
      kill -0 "$pid" 2> /dev/null && echo "local-cluster.sh: $daemon ($pid) still running after 10 s" >&2
    fi
    rm -f "$file"
  done
  ;;
*) echo "usage: local-cluster.sh start | stop" >&2; exit 1 ;;
esac
