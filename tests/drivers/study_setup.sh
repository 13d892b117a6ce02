# Sourced by the study checks (check_study*.sh BUILD_DIR WORKDIR): bin,
# work and root, the study command, the launcher as jobs/mpirun.sh starts
# the runs here (root, oversubscription), fail(), and an empty WORKDIR.
set -u
bin="$1"; work="$2"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
study=(/usr/bin/python3 "$root/tools/study.py")
export LEM_MPIRUN="$root/jobs/mpirun.sh" LEM_LAUNCHER=mpirun
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"; mkdir -p "$work"
