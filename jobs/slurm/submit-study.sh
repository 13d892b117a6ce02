#!/bin/bash
# Submit a whole parametric study to Slurm as four dependent jobs:
#   samples (array over the lattices x rho^m) -> calibration (array over the
#   lattices; with `elastic: true` also the lem_tension pulls of that
#   lattice's samples) -> runs (array over the grid, each task one mpirun of
#   lem_fracture, requeued from its checkpoint when the time limit comes) ->
#   gather (tables and figures, also after failures).
# Usage: submit-study.sh STUDY.yaml OUT_DIR [sbatch options for the calibrations and runs...]
#   e.g. submit-study.sh jobs/studies/paper.yaml results/paper --time=02:00:00 -p compute
# Runs already complete are skipped, so resubmitting finishes a study.
# Prints the job ids; `tools/study.py status STUDY OUT_DIR` tells what is done.
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: submit-study.sh STUDY.yaml OUT_DIR [sbatch options...]" >&2; exit 1; }
study="$(realpath "$1")"; out="$(realpath -m "$2")"; shift 2
root="$(cd "$(dirname "$0")/../.." && pwd)"
task="$root/jobs/slurm/study-task.sh"
py=/usr/bin/python3
# Checks the study file and the output folder before anything is queued.
$py "$root/tools/study.py" plan "$study" "$out"
count() { PYTHONPATH="$root/tools" $py -c "from lem_tools.study import Study; s = Study('$study', '$out'); print($1)"; }
samples=$(count "len(s.samples())")
lattices=$(count "len(s.lattices)")
runs=$(count "len(s.runs())")
ranks=$(count "s.spec['ranks']")
mkdir -p "$out/slurm"
common=(--parsable --chdir="$out/slurm" --export=ALL,LEM_ROOT="$root")
j1=$(sbatch "${common[@]}" --job-name=lem-samples --array=0-$((samples - 1)) --ntasks=1 \
       "$task" samples "$study" "$out")
# The calibrations (a fracture of the homogeneous lattice each) and the runs
# take the given sbatch options and requeue themselves from their checkpoints.
resumable=(--ntasks="$ranks" --requeue --open-mode=append --signal=B:USR1@120 "$@")
j2=$(sbatch "${common[@]}" --job-name=lem-calibrate --dependency=afterok:"$j1" \
       --array=0-$((lattices - 1)) "${resumable[@]}" "$task" calibrate "$study" "$out")
j3=$(sbatch "${common[@]}" --job-name=lem-runs --dependency=afterok:"$j2" --array=0-$((runs - 1)) \
       "${resumable[@]}" "$task" run "$study" "$out")
j4=$(sbatch "${common[@]}" --output=%x-%j.out --job-name=lem-gather --dependency=afterany:"$j3" --ntasks=1 \
       "$task" gather "$study" "$out")
echo "submitted: samples $j1 ($samples tasks), calibration $j2 ($lattices tasks), runs $j3 ($runs tasks), gather $j4"
echo "$j1 $j2 $j3 $j4" > "$out/slurm/job-ids"
echo "logs in $out/slurm/ (job ids in job-ids)"
