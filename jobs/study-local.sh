#!/bin/bash
# A parametric study on this machine, one run after the other (the plain
# mpirun path; jobs/slurm/submit-study.sh is the cluster path).  Rerunning
# skips complete runs and resumes interrupted ones from their checkpoints.
# Usage: jobs/study-local.sh STUDY.yaml OUT_DIR [--index I] [--ranks N] [--data DIR]
# (the options of tools/study.py `all`; --index I: only run I)
# LEM_BIN=DIR: the lem_* programs of DIR (e.g. the bin/ of an install), and
# nothing is built (docs/guide/building.md).  The launcher is jobs/mpirun.sh (this
# machine's flags) unless LEM_LAUNCHER / LEM_MPIRUN say otherwise; the Python
# is $LEM_PYTHON (jobs/python.sh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
[ $# -ge 2 ] || { echo "usage: study-local.sh STUDY.yaml OUT_DIR [--index I] [--ranks N] [--data DIR]" >&2; exit 1; }
source "$root/jobs/python.sh"
[ -n "${LEM_BIN:-}" ] || bash "$root/jobs/build.sh"
export LEM_MPIRUN="${LEM_MPIRUN:-$(printf %q "$root/jobs/mpirun.sh")}"
exec "$LEM_PYTHON" "$root/tools/study.py" all "$@"
