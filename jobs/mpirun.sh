#!/bin/bash
# mpirun with the flags this machine needs: root may run MPI jobs, and more
# ranks than cores are allowed.  Usage: jobs/mpirun.sh [-n] NRANKS program [args]
# (with -n it can stand for mpirun in LEM_MPIRUN: jobs/study-local.sh)
#
# Stop requests (docs/developer/reliability.md, "Stop signals"): Open MPI 4.1's mpirun
# passes SIGUSR1 on to the ranks, but answers SIGTERM by killing them
# (SIGTERM 1 s later, SIGKILL 1 s after that) and exits 1 whatever they do.
# So this script runs mpirun as its child and hands it SIGUSR1 for either
# signal: lem_fracture then saves its state and exits 4, and so does this
# script.  (Being a background job, mpirun reads no terminal input; Ctrl-C
# still reaches it and aborts the run.)
set -uo pipefail
[ "${1:-}" = -n ] && shift
n="$1"; shift
flags=(--oversubscribe)
[ "$(id -u)" -eq 0 ] && flags+=(--allow-run-as-root)
mpirun "${flags[@]}" -n "$n" "$@" &
pid=$!
trapped=0
trap 'trapped=1; kill -USR1 "$pid" 2> /dev/null' TERM USR1
# wait returns early when a trapped signal arrives: wait again (bash keeps
# the status of a child that ended meanwhile).
while :; do
  trapped=0
  wait "$pid"; status=$?
  [ "$trapped" = 1 ] || break
done
exit "$status"
