#!/bin/bash
# One stage of a parametric study as a Slurm batch job (submitted by
# submit-study.sh; an array task makes the sample, the lattice's calibration
# or the run of its index; gather first reports what is missing and why).
# Usage (sbatch): study-task.sh STEP STUDY.yaml OUT_DIR    STEP: samples | calibrate | run | gather
#
# Before the time limit Slurm sends SIGUSR1 (--signal=B:USR1@...): it is passed
# on to lem_fracture (through srun or mpirun), which writes a checkpoint and
# exits 4; the task then requeues itself and the requeued task resumes from
# the checkpoint.  Logs are appended to (--open-mode=append, and study.py
# appends to the runs' logs), so a requeued task keeps the earlier part.
#SBATCH --job-name=lem-study
#SBATCH --output=%x-%A_%a.out
#SBATCH --open-mode=append
set -uo pipefail
step="$1"; study="$2"; out="$3"
root="${LEM_ROOT:-$(cd "$(dirname "$0")/../.." && pwd)}"
source "$root/jobs/python.sh"
task="${SLURM_ARRAY_JOB_ID:+${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}}"
task="${task:-${SLURM_JOB_ID:-}}"
echo "study-task: $step, job $task, start $((${SLURM_RESTART_COUNT:-0} + 1)), $(date -Iseconds) on $(hostname)"
index=()
[ -n "${SLURM_ARRAY_TASK_ID:-}" ] && [ "$step" != gather ] &&
  index=(--index "$SLURM_ARRAY_TASK_ID")
ranks=()
{ [ "$step" = run ] || [ "$step" = calibrate ]; } && [ -n "${SLURM_NTASKS:-}" ] &&
  ranks=(--ranks "$SLURM_NTASKS")

if [ "$step" = gather ]; then
  # A failed stage cancels the stages after it (--kill-on-invalid-dep); this
  # job runs anyway and says what is missing.
  if [ -n "${LEM_CHAIN_JOBS:-}" ] &&
     states=$(sacct -n -X -j "$LEM_CHAIN_JOBS" -o JobID,JobName,State,ExitCode 2> /dev/null); then
    echo "study-task: jobs of the chain (sacct):"; echo "$states"
  fi
  "$LEM_PYTHON" "$root/tools/study.py" status "$study" "$out" ||
    echo "study-task: the study is incomplete: above, what failed or did not run"
fi
"$LEM_PYTHON" "$root/tools/study.py" "$step" "$study" "$out" "${index[@]}" "${ranks[@]}" &
child=$!
trap 'kill -USR1 "$child" 2> /dev/null' USR1
trap 'kill -TERM "$child" 2> /dev/null' TERM
# wait returns early when a trapped signal arrives: wait again for the exit status.
while :; do
  wait "$child"; status=$?
  kill -0 "$child" 2> /dev/null || break
done
if [ "$status" -eq 4 ] && [ -n "$task" ]; then
  echo "study-task: checkpoint written; requeueing $task"
  scontrol requeue "$task"
fi
exit "$status"
