#!/bin/bash
# The main job: quasi-static tension to complete failure of the shipped cemented
# sample meshes/mini.h5 on 2 ranks (paper sect. 2.3): calibrates sigma^[p]
# and E^[p] on the homogeneous lattice, breaks the sample, prints E_eff and
# sigma_eff, and writes results/main/{summary.json,summary.csv,curve.csv,
# broken.csv,fields.h5,fields.xmf,elastic.h5,elastic.xmf,manifest.txt,
# fracture.png,fracture.pdf,stress.png,stress.pdf}.  Run again, it finds the result complete and
# computes nothing (pass -output_overwrite to compute it again).
# Extra arguments are passed to lem_fracture (PETSc options).
#
# Executables (docs/guide/building.md, "Running the installed programs"): those
# of build/, built first by jobs/build.sh; with LEM_BIN=DIR (the bin/ of an
# install, or another build folder) those of DIR, and nothing is built.
# The copy installed as <prefix>/share/lem3d/jobs/main.sh runs <prefix>/bin
# (or LEM_BIN) on the installed sample and writes results/main under the
# current directory.  LEM_RANKS: the rank count (2); LEM_PYTHON: the Python
# of the plots (jobs/python.sh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin=build
[ -z "${LEM_BIN:-}" ] || bin="$(realpath "$LEM_BIN")"
if [ -e "$root/CMakeLists.txt" ]; then  # a source tree: run in it, as always
  [ -n "${LEM_BIN:-}" ] || bash "$root/jobs/build.sh" lem_fracture  # the tests build with jobs/test.sh
  cd "$root"
  root=.
  args=(-options_file jobs/main.opts)
else                                    # installed in <prefix>/share/lem3d
  [ -n "${LEM_BIN:-}" ] || bin="$(realpath "$root/../../bin")"
  args=(-options_file "$root/jobs/main.opts" -sample_file "$root/meshes/mini.h5")
fi
[ -x "$bin/lem_fracture" ] || { echo "main.sh: no $bin/lem_fracture (set LEM_BIN)" >&2; exit 1; }
bash "$root/jobs/mpirun.sh" "${LEM_RANKS:-2}" "$bin/lem_fracture" "${args[@]}" "$@"
dir=results/main
for ((i = 1; i <= $#; ++i)); do
  [ "${!i}" = "-output_dir" ] && { j=$((i + 1)); dir="${!j}"; }
done
source "$root/jobs/python.sh"
"$LEM_PYTHON" "$root/tools/plot_fracture.py" "$dir"
"$LEM_PYTHON" "$root/tools/plot_stress.py" "$dir"
"$LEM_PYTHON" "$root/tools/plot_crack.py" "$dir"
