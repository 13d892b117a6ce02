#!/bin/bash
# A one-node Slurm cluster on this machine (controller and compute daemon on
# localhost, munge authentication), for CI and for trying the Slurm path on a
# workstation.  Needs root and Debian's slurm-wlm and munge packages.
# Usage: local-cluster.sh start | stop
set -euo pipefail
conf=/etc/slurm/slurm.conf
case "${1:-}" in
start)
  command -v slurmctld > /dev/null || { echo "local-cluster.sh: slurm-wlm is not installed" >&2; exit 1; }
  host=$(hostname -s)
  cpus=$(nproc)
  mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 - 512 ))
  mkdir -p /var/spool/slurmctld /var/spool/slurmd /var/log/slurm /run/munge
  chown munge:munge /run/munge
  [ -s /etc/munge/munge.key ] || { dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2> /dev/null
                                   chown munge:munge /etc/munge/munge.key; chmod 400 /etc/munge/munge.key; }
  pgrep -x munged > /dev/null || runuser -u munge -- /usr/sbin/munged
  cat > "$conf" <<CONF
# Written by jobs/slurm/local-cluster.sh: one node, this machine.
ClusterName=lem-local
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MaxArraySize=10000
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
CONF
  pgrep -x slurmctld > /dev/null || slurmctld -c
  pgrep -x slurmd > /dev/null || slurmd
  for _ in $(seq 30); do
    sinfo -h -o "%T" 2> /dev/null | grep -qE "idle|mixed|alloc" && { sinfo; exit 0; }
    sleep 1
  done
  echo "local-cluster.sh: the node did not come up; logs in /var/log/slurm" >&2
  sinfo >&2 || true
  exit 1
  ;;
stop)
  pkill -x slurmd || true
  pkill -x slurmctld || true
  ;;
*) echo "usage: local-cluster.sh start | stop" >&2; exit 1 ;;
esac
