#!/bin/bash
# Scaling measurements on a Slurm cluster (docs/scaling.md): one job per rank
# count runs lem_bench on SAMPLE, set up in parallel (-sample_parallel: no
# rank reads the whole sample); a last job, once they have ended, writes
# OUT_DIR/scaling.csv and OUT_DIR/scaling.md (tools/scaling.py table).
# Usage: jobs/slurm/scaling.sh SAMPLE.h5 OUT_DIR RANKS... [-- SBATCH_OPTION...]
#   jobs/slurm/scaling.sh big.h5 results/scaling 16 32 64 128 -- --partition=compute --time=30
# The sbatch options after -- go to every job.  LEM_BENCH_OPTIONS (words)
# go to lem_bench (e.g. "-bench_repeat 1"); LEM_PYTHON, LEM_BIN,
# LEM_LAUNCHER, LEM_SRUN and LEM_MPIRUN reach the jobs as for a study.
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
source "$root/jobs/python.sh"
fail() { echo "scaling.sh: $*" >&2; exit 1; }
[ $# -ge 3 ] || fail "usage: jobs/slurm/scaling.sh SAMPLE.h5 OUT_DIR RANKS... [-- SBATCH_OPTION...]"
[ -f "$1" ] || fail "sample file $1 does not exist"
sample="$(realpath "$1")"; out="$(realpath -m "$2")"; shift 2
counts=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do
  [[ "$1" =~ ^[1-9][0-9]*$ ]] || fail "rank count '$1' is not a positive whole number"
  counts+=("$1"); shift
done
[ ${#counts[@]} -gt 0 ] || fail "no rank count given"
[ "${1:-}" != "--" ] || shift
user=("$@")
command -v sbatch > /dev/null || fail "sbatch not found: submit from a Slurm login node"
mkdir -p "$out/slurm"
common=(--parsable --chdir="$out/slurm" --output=%x-%j.out --export=ALL,LEM_ROOT="$root")
bench=(--bench="${LEM_BENCH_OPTIONS:-}")
ids=()
for n in "${counts[@]}"; do
  ids+=("$(sbatch "${common[@]}" --job-name="lem-scaling-$n" --ntasks="$n" "${user[@]}" \
           --wrap "exec $(printf '%q ' "$LEM_PYTHON" "$root/tools/scaling.py" run "$sample" "$out" --ranks "$n" "${bench[@]}")")")
done
table=$(sbatch "${common[@]}" --job-name=lem-scaling-table --ntasks=1 \
          --dependency="afterany:$(IFS=:; echo "${ids[*]}")" "${user[@]}" \
          --wrap "exec $(printf '%q ' "$LEM_PYTHON" "$root/tools/scaling.py" table "$out")")
echo "${ids[*]} $table" > "$out/slurm/job-ids"
echo "submitted: lem_bench on ${counts[*]} ranks (jobs ${ids[*]}), the table (job $table); logs in $out/slurm/"
