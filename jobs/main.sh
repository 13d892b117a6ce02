#!/bin/bash
# The main job: elastic uniaxial tension of a paper-size random lattice
# (about 1.3 million bonds) on 2 ranks; prints E and nu, writes
# results/main/{summary.json,summary.csv,fields.h5,fields.xmf,tension.png}.
# Extra arguments are passed to lem_tension (PETSc options).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/jobs/build.sh"
cd "$root"
bash jobs/mpirun.sh "${LEM_RANKS:-2}" build/lem_tension -options_file jobs/main.opts "$@"
/usr/bin/python3 tools/plot_tension.py results/main
