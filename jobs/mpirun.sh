#!/bin/bash
# mpirun with the flags this machine needs: root may run MPI jobs, and more
# ranks than cores are allowed.  Usage: jobs/mpirun.sh NRANKS program [args]
set -euo pipefail
n="$1"; shift
flags=(--oversubscribe)
[ "$(id -u)" -eq 0 ] && flags+=(--allow-run-as-root)
exec mpirun "${flags[@]}" -n "$n" "$@"
