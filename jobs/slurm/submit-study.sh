#!/bin/bash
# Submit a whole parametric study to Slurm as four dependent jobs:
#   samples (array over the lattices x rho^m) -> calibrate (array over the
#   lattices; with `elastic: true` also the lem_tension pulls of that
#   lattice's samples) -> runs (array over the grid, each task one srun of
#   lem_fracture) -> gather (tables and figures, and a report of what failed).
# Usage: submit-study.sh STUDY.yaml OUT_DIR [SBATCH_OPTION...] [STAGE:SBATCH_OPTION...]
#   SBATCH_OPTION    given to every job (account, partition, QOS, time...)
#   STAGE:OPTION     only to the jobs of STAGE (samples, calibrate, runs or
#                    gather), after the others so that it overrides them; one
#                    word each: runs:--time=12:00:00, not runs:-t 12:00:00
#   e.g. submit-study.sh jobs/studies/paper.yaml results/paper -A proj -p compute \
#          --time=00:30:00 calibrate:--time=02:00:00 runs:--time=12:00:00
# sbatch's own variables (SBATCH_ACCOUNT, SBATCH_PARTITION, SBATCH_QOS,
# SBATCH_TIMELIMIT...) apply to every job as well.  Environment (docs/guide/cluster.md):
# LEM_PYTHON, LEM_BIN, LEM_LAUNCHER, LEM_SRUN, LEM_MPIRUN reach the jobs.
# Calibration and run tasks requeue themselves from their checkpoints before
# their time limit; a failed stage cancels the ones after it but the gather
# job, which reports what failed.  Complete work is skipped, so submitting
# again finishes a study.  Prints the job ids (also in OUT_DIR/slurm/job-ids).
set -euo pipefail
usage="usage: submit-study.sh STUDY.yaml OUT_DIR [SBATCH_OPTION...] [STAGE:SBATCH_OPTION...]"
[ $# -ge 2 ] || { echo "$usage" >&2; exit 1; }
study="$(realpath "$1")"; out="$(realpath -m "$2")"; shift 2
root="$(cd "$(dirname "$0")/../.." && pwd)"
task="$root/jobs/slurm/study-task.sh"
fail() { echo "submit-study.sh: $*" >&2; exit 1; }
stages=(samples calibrate runs gather)
declare -A own=([samples]="" [calibrate]="" [runs]="" [gather]="")
everyone=()
for arg in "$@"; do
  case "${arg#*:}" in
    --array*|-a*|--dependency*|-d*|--chdir*|-D*|--parsable|--kill-on-invalid-dep*)
      fail "$arg: submit-study.sh sets this option itself" ;;
  esac
  if [[ "$arg" =~ ^([A-Za-z_]+):(.*)$ ]] &&
     { [[ "${BASH_REMATCH[2]}" == -* ]] || [ -n "${own[${BASH_REMATCH[1]}]+set}" ]; }; then
    stage="${BASH_REMATCH[1]}"; option="${BASH_REMATCH[2]}"
    [ -n "${own[$stage]+set}" ] || fail "unknown stage '$stage' in '$arg' (stages: ${stages[*]})"
    [[ "$option" =~ ^(--[A-Za-z-]+(=.+)?|-[A-Za-z].+)$ ]] ||
      fail "'$arg': a stage's option is one word, e.g. $stage:--time=01:00:00 or $stage:-t01:00:00"
    # one option per line: values may hold spaces
    own[$stage]+="$option"$'\n'
  else
    everyone+=("$arg")
  fi
done
source "$root/jobs/python.sh"
"$LEM_PYTHON" -c "import yaml, numpy, scipy, h5py, matplotlib" 2> /dev/null ||
  fail "$LEM_PYTHON lacks PyYAML, NumPy, SciPy, h5py or matplotlib: set LEM_PYTHON to a Python 3 that has them"
command -v sbatch > /dev/null || fail "sbatch not found: submit from a Slurm login node"
# Checks the study file and the output folder before anything is queued.
"$LEM_PYTHON" "$root/tools/study.py" plan "$study" "$out"
count() { PYTHONPATH="$root/tools" "$LEM_PYTHON" -c "from lem_tools.study import Study; s = Study('$study', '$out'); print($1)"; }
samples=$(count "len(s.samples())")
lattices=$(count "len(s.lattices)")
runs=$(count "len(s.runs())")
ranks=$(count "s.spec['ranks']")
mkdir -p "$out/slurm"
# Per stage: the chain's own options, then the user's (the last one wins).
declare -A chain=(
  [samples]="--job-name=lem-samples --array=0-$((samples - 1)) --ntasks=1"
  [calibrate]="--job-name=lem-calibrate --array=0-$((lattices - 1)) --ntasks=$ranks"
  [runs]="--job-name=lem-runs --array=0-$((runs - 1)) --ntasks=$ranks"
  [gather]="--job-name=lem-gather --output=%x-%j.out --ntasks=1"
)
declare -A step=([samples]=samples [calibrate]=calibrate [runs]=run [gather]=gather)
common=(--parsable --chdir="$out/slurm" --open-mode=append --export=ALL,LEM_ROOT="$root")
# Calibration and runs requeue themselves from a checkpoint (study-task.sh).
resumable=(--requeue --signal=B:USR1@120)
sbatch_stage() {  # sbatch_stage STAGE [extra sbatch options...]: prints the job id
  local stage="$1"; shift
  local -a chain_opts extra=() user=("${everyone[@]}")
  read -r -a chain_opts <<< "${chain[$stage]}"
  if [ "$stage" = calibrate ] || [ "$stage" = runs ]; then extra=("${resumable[@]}"); fi
  [ -z "${own[$stage]}" ] || mapfile -t -O "${#user[@]}" user < <(printf %s "${own[$stage]}")
  sbatch "${common[@]}" "${chain_opts[@]}" "${extra[@]}" "$@" "${user[@]}" \
    "$task" "${step[$stage]}" "$study" "$out"
}
# Every stage's options checked by Slurm before any job is queued.
for stage in "${stages[@]}"; do
  sbatch_stage "$stage" --test-only > "$out/slurm/test-only.log" 2>&1 ||
    fail "sbatch refuses the $stage job's options: $(grep -v '^sbatch: Job .* to start' "$out/slurm/test-only.log" | tail -2)"
done
rm -f "$out/slurm/test-only.log"
queued=()
trap '[ ${#queued[@]} -eq 0 ] || { scancel "${queued[@]}"; echo "submit-study.sh: cancelled ${queued[*]}" >&2; }' ERR
j1=$(sbatch_stage samples); queued+=("$j1")
# A failed stage cancels the dependent ones instead of leaving them pending.
j2=$(sbatch_stage calibrate --dependency=afterok:"$j1" --kill-on-invalid-dep=yes); queued+=("$j2")
j3=$(sbatch_stage runs --dependency=afterok:"$j2" --kill-on-invalid-dep=yes); queued+=("$j3")
j4=$(sbatch_stage gather --dependency=afterany:"$j3" --export=ALL,LEM_ROOT="$root",LEM_CHAIN_JOBS="$j1,$j2,$j3")
trap - ERR
echo "submitted: samples $j1 ($samples tasks), calibration $j2 ($lattices tasks), runs $j3 ($runs tasks), gather $j4"
echo "$j1 $j2 $j3 $j4" > "$out/slurm/job-ids"
echo "logs in $out/slurm/ (job ids in job-ids)"
