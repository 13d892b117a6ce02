#!/bin/bash
# CI proof of the Slurm path (run as root on a fresh Debian 12 machine):
# installs slurm-wlm and munge, starts a one-node cluster on localhost
# (local-cluster.sh; stopped again at the end if it was not running) and
# submits the CI study (jobs/studies/ci.yaml) with submit-study.sh:
#   0. bad options (an unknown stage, a partition Slurm refuses) are refused
#      before anything is queued;
#   1. with a lem_sample that fails on one sample: that task fails, the
#      calibration and runs are cancelled, the gather job reports the failed
#      sample; per-stage sbatch options reach their jobs;
#   2. submitted again (the failed sample made): the launcher is srun; the
#      calibration is sent SIGUSR1 while it runs (what Slurm sends before the
#      time limit), checkpoints, requeues itself, resumes, and its logs hold
#      both attempts; then the 4 runs and the gathered table and figures;
#   3. one run deleted and submitted again with the mpirun fallback
#      (LEM_LAUNCHER=mpirun): interrupted the same way, requeued, resumed to
#      the same result as the uninterrupted run;
#   4. the scaling job (scaling.sh) on the mini sample at 1 and 2 ranks, and
#      its table.
# Usage: jobs/slurm/ci-check.sh [WORK_DIR]   (needs build/ from jobs/build.sh)
set -euo pipefail
root="$(cd "$(dirname "$0")/../.." && pwd)"
work="$(realpath -m "${1:-$root/build/slurm-ci}")"
study="$root/jobs/studies/ci.yaml"
submit="$root/jobs/slurm/submit-study.sh"
source "$root/jobs/python.sh"
py="$LEM_PYTHON"
start=$SECONDS
fail() { echo "slurm-ci: FAIL: $*" >&2; exit 1; }
ok() { echo "slurm-ci: ok: $* ($((SECONDS - start)) s)"; }
if ! command -v sbatch > /dev/null || ! command -v munged > /dev/null; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge > /dev/null
fi
if ! sinfo > /dev/null 2>&1; then
  trap 'bash "$root/jobs/slurm/local-cluster.sh" stop' EXIT
fi
bash "$root/jobs/slurm/local-cluster.sh" start
rm -rf "$work"
# The jobs of the chain take no launcher or program choice from this shell
# unless a phase sets one.
unset LEM_LAUNCHER LEM_SRUN LEM_MPIRUN LEM_BIN

wait_jobs() {  # wait until none of the given jobs is queued or running
  for _ in $(seq 600); do
    [ -z "$(squeue -h -j "$(IFS=,; echo "$*")" 2> /dev/null)" ] && return 0
    sleep 1
  done
  squeue; fail "jobs $* still queued after 10 minutes"
}
wait_for_line() {  # wait_for_line PATTERN FILE: until FILE has a line matching PATTERN
  for _ in $(seq 1200); do
    [ -f "$2" ] && grep -q "$1" "$2" && return 0
    sleep 0.1
  done
  fail "no line '$1' in $2 after 2 minutes"
}
expect_refused() {  # expect_refused PATTERN OPTIONS...: submit-study.sh exits 1 naming the problem
  local pattern="$1" status=0; shift
  bash "$submit" "$study" "$work" "$@" > "$work.refused" 2>&1 || status=$?
  [ "$status" = 1 ] && grep -q "$pattern" "$work.refused" ||
    fail "submit-study.sh $* gave exit $status: $(tail -2 "$work.refused")"
  [ -z "$(squeue -h)" ] || fail "a job was queued despite the bad options"
}
out_of() { echo "$work/slurm/$1"; }

# 0. Bad options, refused before anything is queued.
expect_refused "unknown stage 'run' in 'run:--time=10'" run:--time=10
expect_refused "sbatch refuses the samples job's options: .*invalid partition" --partition=nosuch
expect_refused "one word" runs:-t 10
rm -f "$work.refused"
ok "bad sbatch options refused, nothing queued"

# 1. A sample that fails: the chain cancels what depends on it, gather reports it.
fake="$work-bin"; rm -rf "$fake"; mkdir -p "$fake"
for p in "$root"/build/lem_*; do ln -s "$p" "$fake/"; done
rm "$fake/lem_sample"
printf '#!/bin/bash\ncase " $* " in *" -matrix_fraction 0.24 "*) echo "Error: injected failure" >&2; exit 3;; esac\nexec %q "$@"\n' \
  "$root/build/lem_sample" > "$fake/lem_sample"
chmod +x "$fake/lem_sample"
LEM_BIN="$fake" bash "$submit" "$study" "$work" --time=00:20:00 samples:--time=00:05:00 \
  gather:--time=00:04:00 > /dev/null
read -r -a ids < "$work/slurm/job-ids"
limits=$(for id in "${ids[@]}"; do scontrol show job "$id" | grep -o 'TimeLimit=[^ ]*' | head -1; done | tr '\n' ' ')
[ "$limits" = "TimeLimit=00:05:00 TimeLimit=00:20:00 TimeLimit=00:20:00 TimeLimit=00:04:00 " ] ||
  fail "per-stage time limits not applied: $limits"
wait_jobs "${ids[@]}"
grep -q "Error: injected failure" "$(out_of "lem-samples-${ids[0]}_1.out")" || fail "sample task 1 did not fail"
[ ! -e "$work/calibration/log" ] || fail "the calibration ran after a failed sample"
ls "$work/slurm/lem-runs-${ids[2]}"_* > /dev/null 2>&1 && fail "the runs ran after a failed sample"
gather_out=$(out_of "lem-gather-${ids[3]}.out")
grep -q "sample rho_0.2400 .*failed.*injected failure" "$gather_out" ||
  fail "the gather job did not report the failed sample: $(head -5 "$gather_out")"
grep -q "^calibration .*not started" "$gather_out" || fail "the gather job did not report the calibration"
ok "failed sample task: calibration and runs cancelled, gather reported it; per-stage options applied"

# 2. The whole chain under srun; the calibration interrupted and requeued.
bash "$submit" "$study" "$work" --time=00:20:00 > /dev/null
read -r -a ids < "$work/slurm/job-ids"
cal_log="$work/calibration/log"
wait_for_line "^step" "$cal_log"
scancel --signal=USR1 --batch "${ids[1]}_0"
cal_out=$(out_of "lem-calibrate-${ids[1]}_0.out")
wait_jobs "${ids[@]}"
grep -q "requeueing ${ids[1]}_0" "$cal_out" || fail "the calibration did not requeue itself: $(tail -3 "$cal_out")"
grep -q "start 2," "$cal_out" || fail "the requeued calibration's output is not appended: $(tail -3 "$cal_out")"
[ "$(grep -c "^--- study.py started" "$cal_log")" = 2 ] || fail "the calibration log lacks an attempt"
grep -q "^interrupted" "$cal_log" && grep -q "^resumed from" "$cal_log" ||
  fail "the calibration did not checkpoint and resume: $(tail -3 "$cal_log")"
grep -q "^--- study.py started .*: srun -n 2 " "$cal_log" || fail "the calibration did not run under srun"
"$py" "$root/tools/study.py" status "$study" "$work" || fail "runs missing after the Slurm jobs"
"$py" - "$work" <<'PY' || exit 1
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
    if " srun -n 2 " not in open(os.path.join(d, "log")).readline():
        sys.exit(f"FAIL: {r['id']}: not run under srun")
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
ok "chain under srun; calibration SIGUSR1 -> checkpoint -> requeue -> resume, logs appended"

# 3. The mpirun fallback: redo one run and interrupt it as the time limit would.
victim=rho_0.2400_spm_1.2000
reference=$("$py" -c "import json; print(json.load(open('$work/runs/$victim/summary.json'))['broken'])")
rm -rf "$work/runs/$victim"
# root asks mpirun for leave to run (a site's own user would not)
LEM_LAUNCHER=mpirun LEM_MPIRUN="mpirun --allow-run-as-root" bash "$submit" "$study" "$work" > /dev/null
read -r -a ids < "$work/slurm/job-ids"
task="${ids[2]}_3"   # the victim is the last run of the grid
log="$work/runs/$victim/log"
wait_for_line "^step" "$log"
scancel --signal=USR1 --batch "$task"
run_out=$(out_of "lem-runs-${task}.out")
wait_jobs "${ids[@]}"
grep -q "requeueing $task" "$run_out" || fail "task $task did not requeue itself: $(tail -3 "$run_out")"
grep -q "^--- study.py started .*: mpirun --allow-run-as-root -n 2 " "$log" ||
  fail "the run did not use the mpirun fallback: $(head -1 "$log")"
grep -q "^resumed from" "$log" || fail "the requeued run did not resume: $(tail -3 "$log")"
got=$("$py" -c "import json; print(json.load(open('$work/runs/$victim/summary.json'))['broken'])")
[ "$got" = "$reference" ] || fail "resumed run broke $got bonds, the uninterrupted one $reference"
"$py" "$root/tools/study.py" status "$study" "$work" > /dev/null || fail "study incomplete after the requeue"
ok "mpirun fallback; run SIGUSR1 -> checkpoint -> requeue -> resume, $got bonds as before"

# 4. The scaling job: lem_bench on the mini sample, set up in parallel, at 1
#    and 2 ranks under srun, and the table of both.
LEM_BENCH_OPTIONS="-bench_repeat 1 -bench_matmult 5" \
  bash "$root/jobs/slurm/scaling.sh" "$root/meshes/mini.h5" "$work/scaling" 1 2 > /dev/null
read -r -a ids < "$work/scaling/slurm/job-ids"
wait_jobs "${ids[@]}"
rows=$(grep -c '^| [12] |' "$work/scaling/scaling.md" 2> /dev/null || true)
[ "$rows" = 2 ] || fail "the scaling table has $rows of 2 rows: $(tail -3 "$work"/scaling/slurm/*.out)"
grep -q "srun.*-n 2 .*lem_bench" "$work/scaling/np2.log" || fail "lem_bench did not run under srun: $(head -1 "$work/scaling/np2.log")"
ok "scaling job at 1 and 2 ranks: $(tail -1 "$work/scaling/scaling.md")"
echo "slurm-ci: ok (all checks, $((SECONDS - start)) s)"
