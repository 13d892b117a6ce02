#!/bin/bash
# One step of a parametric study as a Slurm batch job (submitted by
# submit-study.sh; an array task runs the sample, the lattice's calibration
# or the run of its index).
# Usage (sbatch): study-task.sh STEP STUDY.yaml OUT_DIR    STEP: samples | calibrate | run | gather
#
# Before the time limit Slurm sends SIGUSR1 (--signal=B:USR1@...): it is passed
# on to lem_fracture, which writes a checkpoint and exits 4; the task then
# requeues itself and the requeued task resumes from the checkpoint.
#SBATCH --job-name=lem-study
#SBATCH --output=%x-%A_%a.out
set -uo pipefail
step="$1"; study="$2"; out="$3"
root="${LEM_ROOT:-$(cd "$(dirname "$0")/../.." && pwd)}"
# Inside the allocation mpirun starts SLURM_NTASKS ranks; root needs the flags.
export LEM_MPIRUN="${LEM_MPIRUN:-mpirun --allow-run-as-root --oversubscribe}"
index=()
[ -n "${SLURM_ARRAY_TASK_ID:-}" ] && [ "$step" != gather ] &&
  index=(--index "$SLURM_ARRAY_TASK_ID")
ranks=()
{ [ "$step" = run ] || [ "$step" = calibrate ]; } && [ -n "${SLURM_NTASKS:-}" ] &&
  ranks=(--ranks "$SLURM_NTASKS")

/usr/bin/python3 "$root/tools/study.py" "$step" "$study" "$out" "${index[@]}" "${ranks[@]}" &
child=$!
trap 'kill -USR1 "$child" 2> /dev/null' USR1
trap 'kill -TERM "$child" 2> /dev/null' TERM
# wait returns early when a trapped signal arrives: wait again for the exit status.
while :; do
  wait "$child"; status=$?
  kill -0 "$child" 2> /dev/null || break
done
if [ "$status" -eq 4 ] && [ -n "${SLURM_JOB_ID:-}" ]; then
  task="${SLURM_ARRAY_JOB_ID:+${SLURM_ARRAY_JOB_ID}_${SLURM_ARRAY_TASK_ID}}"
  echo "study-task: checkpoint written; requeueing ${task:-$SLURM_JOB_ID}"
  scontrol requeue "${task:-$SLURM_JOB_ID}"
fi
exit "$status"
