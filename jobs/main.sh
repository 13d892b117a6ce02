#!/bin/bash
# The main job: quasi-static tension to complete failure of the shipped cemented
# sample meshes/mini.h5 on 2 ranks (paper sect. 2.3): calibrates sigma^[p]
# and E^[p] on the homogeneous lattice, breaks the sample, prints E_eff and
# sigma_eff, and writes results/main/{summary.json,summary.csv,curve.csv,
# broken.csv,fields.h5,fields.xmf,elastic.h5,elastic.xmf,manifest.txt,
# fracture.png,stress.png}.  Run again, it finds the result complete and
# computes nothing (pass -output_overwrite to compute it again).
# Extra arguments are passed to lem_fracture (PETSc options).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/jobs/build.sh"
cd "$root"
bash jobs/mpirun.sh "${LEM_RANKS:-2}" build/lem_fracture -options_file jobs/main.opts "$@"
dir=results/main
for ((i = 1; i <= $#; ++i)); do
  [ "${!i}" = "-output_dir" ] && { j=$((i + 1)); dir="${!j}"; }
done
/usr/bin/python3 tools/plot_fracture.py "$dir"
/usr/bin/python3 tools/plot_stress.py "$dir"
