#!/bin/bash
# CI proof of the Slurm path (run as root on a fresh Debian 12 machine):
# installs slurm-wlm and munge, starts a one-node cluster on localhost,
# submits the CI study (jobs/studies/ci.yaml) with submit-study.sh, waits,
# and checks every run's outputs and the gathered table.  Then it deletes one
# run, resubmits, interrupts that run with SIGUSR1 (what Slurm sends before
# the time limit) and checks that the task requeued itself and the requeued
# task resumed from the checkpoint to the same result.
# Usage: jobs/slurm/ci-check.sh [WORK_DIR]   (needs build/ from jobs/build.sh)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(realpath -m "${1:-$root/build/slurm-ci}")"
study="$root/jobs/studies/ci.yaml"
py=/usr/bin/python3
fail() { echo "slurm-ci: FAIL: $*" >&2; exit 1; }
if ! command -v sbatch > /dev/null || ! command -v munged > /dev/null; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge > /dev/null
fi
bash "$root/jobs/slurm/local-cluster.sh" start
rm -rf "$work"

wait_jobs() {  # wait until none of the given jobs is queued or running
  for _ in $(seq 600); do
    [ -z "$(squeue -h -j "$(IFS=,; echo "$*")" 2> /dev/null)" ] && return 0
    sleep 1
  done
  squeue; fail "jobs $* still queued after 10 minutes"
}

# 1. The whole study through the job chain.
out=$(bash "$root/jobs/slurm/submit-study.sh" "$study" "$work")
echo "$out"
read -r -a ids < "$work/slurm/job-ids"
wait_jobs "${ids[@]}"
$py "$root/tools/study.py" status "$study" "$work" || fail "runs missing after the Slurm jobs"
$py - "$work" <<'PY' || exit 1
import csv, json, os, sys
work = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(work, "results.csv"))))
if len(rows) != 4:
    sys.exit(f"FAIL: results.csv has {len(rows)} rows, expected 4")
for r in rows:
    d = os.path.join(work, "runs", r["id"])
    for f in ("summary.json", "curve.csv", "broken.csv", "fields.h5", "elastic.h5", "stress.json"):
        if not os.path.exists(os.path.join(d, f)):
            sys.exit(f"FAIL: {r['id']}: {f} missing")
    if not 0 < float(r["sigma_eff_over_sigma_unit"]) < 1.5:
        sys.exit(f"FAIL: {r['id']}: sigma_eff/sigma^[p] = {r['sigma_eff_over_sigma_unit']}")
s = {(float(r["rho_m"]), float(r["sigma_pm_ratio"])): float(r["sigma_eff_over_sigma_unit"]) for r in rows}
# Paper fig. 9: the strength grows with the adhesion and with the matrix content.
if not (s[(0.13, 1.2)] > s[(0.13, 0.4)] and s[(0.24, 0.4)] > s[(0.13, 0.4)]):
    sys.exit(f"FAIL: strengths not ordered as in fig. 9: {s}")
for f in ("strength.png", "damage.png", "stiffness_stress.png"):
    if not os.path.getsize(os.path.join(work, "figures", f)):
        sys.exit(f"FAIL: figure {f} missing")
print("slurm-ci: 4 runs gathered; strengths", {k: round(v, 4) for k, v in s.items()})
PY

# 2. Requeue: redo one run and interrupt it as the time limit would.
victim=rho_0.2400_spm_1.2000
reference=$($py -c "import json; print(json.load(open('$work/runs/$victim/summary.json'))['broken'])")
rm -rf "$work/runs/$victim"
bash "$root/jobs/slurm/submit-study.sh" "$study" "$work" > /dev/null
read -r -a ids < "$work/slurm/job-ids"
runs_job=${ids[2]}
task="${runs_job}_3"   # the victim is the last run of the grid
log="$work/runs/$victim/log"
signalled=0
for _ in $(seq 600); do
  if [ -f "$log" ] && grep -q "^step" "$log"; then
    scancel --signal=USR1 --batch "$task" && signalled=1
    break
  fi
  sleep 0.1
done
[ "$signalled" = 1 ] || fail "the run never started"
wait_jobs "${ids[@]}"
grep -q "requeueing" "$work/slurm/lem-runs-${runs_job}_3.out" ||
  fail "task $task did not requeue itself: $(tail -3 "$work/slurm/lem-runs-${runs_job}_3.out")"
grep -q "^resumed from" "$log" || fail "the requeued run did not resume: $(tail -3 "$log")"
got=$($py -c "import json; print(json.load(open('$work/runs/$victim/summary.json'))['broken'])")
[ "$got" = "$reference" ] || fail "resumed run broke $got bonds, the uninterrupted one $reference"
$py "$root/tools/study.py" status "$study" "$work" > /dev/null || fail "study incomplete after the requeue"
echo "slurm-ci: ok (job chain, 4 runs, gather; SIGUSR1 -> checkpoint -> requeue -> resume, $got bonds as before)"
