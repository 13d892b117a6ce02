#!/bin/bash
# Stop requests honoured at any time (docs/developer/reliability.md, "Stop signals"):
# lem_fracture on the mini sample at 2 ranks is paused at an exact point by
# the test hook LEM_FAULT_PAUSE, signalled there for real, and must end with
# exit 4 and a checkpoint (or its complete result); the same command again
# must give curve.csv and broken.csv byte-identical to an uninterrupted run.
# Usage: check_signals.sh MODE LEM_FRACTURE WORKDIR REFERENCE MPIEXEC [MPI flags...]
#   reference        the uninterrupted run (a fixture of the others), which
#                    calibrates into its own file
#   calibration      SIGUSR1 to mpirun in the middle of a calibration
#                    avalanche: the rerun resumes the calibration
#   calibration_kill kill -9 of both ranks in a calibration avalanche, with
#                    timed checkpoints at every step (-checkpoint_seconds
#                    1e-6): the rerun resumes the calibration from the last
#                    one
#   after_calibration SIGTERM to rank 1 once the calibration's last step is
#                    done: it is stored, exit 4; the rerun does not redo it
#   avalanche        SIGUSR1 to rank 0 between relaxation cycles of a step
#                    of the sample: the equilibrium before the step is saved
#   final_writes     SIGTERM to jobs/mpirun.sh (which hands mpirun SIGUSR1)
#                    before the final fields: the result is completed and
#                    committed, exit 4; the rerun has nothing to do
#   mpirun_term      SIGTERM to mpirun itself: Open MPI kills the ranks
#                    (SIGTERM, then SIGKILL 1 s later) and exits 1; the
#                    ranks still save a checkpoint the rerun resumes
#   anytime          SIGUSR1 to jobs/mpirun.sh with no pause, as soon as a
#                    log line appears (the calibration's first solve, where
#                    nothing can be saved yet; the sample's first steps):
#                    exit 4 (or 0 if the run ended first), then the same
#                    result
set -u
mode="$1"; prog="$2"; work="$3"; ref="$4"; shift 4
mpi=("$@")
root="$(cd "$(dirname "$0")/../.." && pwd)"
wrapper="$root/jobs/mpirun.sh"
args=(-sample_file "$root/meshes/mini.h5" -fracture_stop_fraction 0.5 -checkpoint_seconds 0)
leader=""
fail() {
  echo "FAIL: $*"
  [ -n "$leader" ] && kill -KILL "$leader" $(rank_pids) 2> /dev/null
  exit 1
}
run() {  # run DIR LAUNCHER...: the driver at 2 ranks in the foreground, log DIR.log
  local dir="$1"; shift
  "$@" "$prog" "${args[@]}" -output_dir "$dir" -fracture_calibration_file "$dir.cal" > "$dir.log" 2>&1
}
start() {  # start DIR LAUNCHER...: the same in the background (leader: the launcher)
  local dir="$1"; shift
  "$@" "$prog" "${args[@]}" -output_dir "$dir" -fracture_calibration_file "$dir.cal" > "$dir.log" 2>&1 &
  leader=$!
  cut_log="$dir.log"
}
rank_pids() { sed -n 's/^test hook: rank [0-9]* (pid \([0-9]*\)).*/\1/p' "$cut_log" 2> /dev/null; }
rank_pid() { sed -n "s/^test hook: rank $1 (pid \\([0-9]*\\)).*/\\1/p" "$cut_log"; }
wait_paused() {  # until both ranks say they are paused (or the run ended)
  for _ in $(seq 1 1200); do
    [ "$(grep -c '^test hook: rank .* paused at' "$cut_log")" -ge 2 ] && return 0
    kill -0 "$leader" 2> /dev/null || fail "the run ended before the pause: $(tail -3 "$cut_log")"
    sleep 0.1
  done
  fail "no pause within 120 s"
}
finish() {  # finish EXPECTED: collect the interrupted run's exit status
  wait "$leader"; local status=$?
  leader=""
  [ "$status" -eq "$1" ] || fail "exit status $status, expected $1: $(grep -v '^step' "$cut_log" | tail -4)"
}
same_result() {  # same_result DIR: curve (but the wall time) and log equal the reference's
  diff <(cut -d, -f1-22 "$ref/curve.csv") <(cut -d, -f1-22 "$1/curve.csv") > /dev/null ||
    fail "$1/curve.csv differs from the uninterrupted run's"
  cmp -s "$ref/broken.csv" "$1/broken.csv" || fail "$1/broken.csv differs from the uninterrupted run's"
  [ -s "$1/manifest.txt" ] || fail "no manifest in $1"
  [ ! -e "$1/checkpoint.bin" ] || fail "a committed run left its checkpoint in $1"
}
values() { grep -E '^(sigma|E)_hom=' "$1"; }  # the stored calibration, without provenance
resume() {  # resume DIR: the same command again, complete and equal to the reference
  run "$1" "${mpi[@]}" -n 2 || fail "the rerun failed: $(tail -3 "$1.log")"
  same_result "$1"
}
cycles_of() {  # cycles_of CURVE STEP: relaxation cycles of STEP in an uninterrupted run
  awk -F, -v s="$2" '$1 == s { print $13 }' "$1"
}
mid_step() {  # mid_step REF_CURVE: the stop message names a step that had more cycles
  local msg step done_cycles
  msg=$(grep -o "in the relaxation of step [0-9]* after [0-9]* cycles\?" "$cut_log") ||
    fail "no stop between relaxation cycles: $(grep interrupted "$cut_log")"
  step=$(awk '{print $6}' <<< "$msg"); done_cycles=$(awk '{print $8}' <<< "$msg")
  [ "$(cycles_of "$1" "$step")" -gt "$done_cycles" ] ||
    fail "step $step had $(cycles_of "$1" "$step") cycles: not stopped in its middle"
  echo "stopped $msg (of $(cycles_of "$1" "$step"))"
}
rm -rf "$work" "$work".*; mkdir -p "$work"
cut="$work/cut"

case "$mode" in
reference)
  rm -rf "$ref" "$ref".*
  run "$ref" "${mpi[@]}" -n 2 || fail "uninterrupted run: $(tail -3 "$ref.log")"
  [ -s "$ref/manifest.txt" ] && [ -s "$ref.cal" ] || fail "no complete result or calibration"
  echo "ok: $(grep '^end:' "$ref.log")"
  ;;
calibration)
  LEM_FAULT_PAUSE=relaxation_cycle:45 start "$cut" "${mpi[@]}" -n 2
  wait_paused
  kill -USR1 "$leader"
  finish 4
  grep -q "^interrupted: calibration stopped by SIGUSR1 in the relaxation" "$cut_log" ||
    fail "message: $(grep -v '^step' "$cut_log" | tail -3)"
  mid_step "$ref/calibration/curve.csv"
  [ -s "$cut/calibration/checkpoint.bin" ] || fail "no calibration checkpoint"
  [ ! -e "$cut.cal" ] || fail "a calibration stored before it was complete"
  resume "$cut"
  grep -q "^resumed from $cut/calibration/checkpoint.bin" "$cut.log" ||
    fail "the calibration was not resumed: $(grep calibration "$cut.log" | head -3)"
  [ "$(values "$cut.cal")" = "$(values "$ref.cal")" ] || fail "other calibration values"
  echo "ok: $(grep '^resumed' "$cut.log"); calibration and result identical"
  ;;
calibration_kill)
  args+=(-checkpoint_seconds 1e-6)  # after the 0 above: a timed checkpoint at every step
  LEM_FAULT_PAUSE=relaxation_cycle:45 start "$cut" "${mpi[@]}" -n 2
  wait_paused
  [ -s "$cut/calibration/checkpoint.bin" ] || fail "the calibration wrote no timed checkpoint"
  kill -KILL $(rank_pids)
  wait "$leader"; leader=""
  [ ! -e "$cut.cal" ] || fail "a calibration stored before it was complete"
  resume "$cut"
  grep -q "^resumed from $cut/calibration/checkpoint.bin" "$cut.log" ||
    fail "the calibration was not resumed: $(grep calibration "$cut.log" | head -3)"
  [ "$(values "$cut.cal")" = "$(values "$ref.cal")" ] || fail "other calibration values"
  echo "ok: $(grep '^resumed' "$cut.log"); calibration and result identical"
  ;;
after_calibration)
  LEM_FAULT_PAUSE=fracture_end:1 start "$cut" "${mpi[@]}" -n 2
  wait_paused
  grep -q "paused at fracture_end" "$cut_log" || fail "paused elsewhere"
  kill -TERM "$(rank_pid 1)"
  finish 4
  grep -q "^interrupted: stopped by SIGTERM after the calibration: sigma^\[p\] and E^\[p\] stored in $cut.cal" \
    "$cut_log" || fail "message: $(grep -v '^step' "$cut_log" | tail -3)"
  [ "$(values "$cut.cal")" = "$(values "$ref.cal")" ] || fail "other calibration values"
  [ ! -e "$cut/checkpoint.bin" ] && [ ! -e "$cut/curve.csv.part" ] || fail "the sample was started"
  resume "$cut"
  grep -q "homogeneous lattice" "$cut.log" && fail "the rerun calibrated again"
  grep -q "calibration: sigma.* from $cut.cal" "$cut.log" || fail "the rerun did not read the calibration"
  echo "ok: calibration stored, not redone; result identical"
  ;;
avalanche)
  cp "$ref.cal" "$cut.cal"  # the sample's relaxation cycles only
  LEM_FAULT_PAUSE=relaxation_cycle:15 start "$cut" "${mpi[@]}" -n 2
  wait_paused
  kill -USR1 "$(rank_pid 0)"
  finish 4
  grep -q "^interrupted: stopped by SIGUSR1 in the relaxation of step" "$cut_log" ||
    fail "message: $(grep -v '^step' "$cut_log" | tail -3)"
  mid_step "$ref/curve.csv"
  [ -s "$cut/checkpoint.bin" ] || fail "no checkpoint"
  [ ! -e "$cut/curve.csv" ] && [ ! -e "$cut/manifest.txt" ] || fail "an interrupted run looks complete"
  resume "$cut"
  grep -q "^resumed from $cut/checkpoint.bin" "$cut.log" || fail "the rerun did not resume"
  echo "ok: $(grep '^resumed' "$cut.log"); result identical"
  ;;
final_writes)
  cp "$ref.cal" "$cut.cal"
  LEM_FAULT_PAUSE=fields start "$cut" "$wrapper" 2
  wait_paused
  kill -TERM "$leader"
  finish 4
  # The wrapper hands mpirun SIGUSR1, which is what the ranks see.
  grep -q "^interrupted: stopped by SIGUSR1 while the results were written; they are complete" \
    "$cut_log" || fail "message: $(grep -v '^step' "$cut_log" | tail -3)"
  same_result "$cut"
  [ -s "$cut/fields.h5" ] || fail "no fields"
  run "$cut" "${mpi[@]}" -n 2 || fail "the rerun failed: $(tail -3 "$cut.log")"
  grep -q "is complete (manifest.txt): nothing to do" "$cut.log" || fail "the rerun computed again"
  echo "ok: complete result committed, exit 4; the rerun has nothing to do"
  ;;
mpirun_term)
  cp "$ref.cal" "$cut.cal"
  LEM_FAULT_PAUSE=load_step:20 start "$cut" "${mpi[@]}" -n 2
  wait_paused
  kill -TERM "$leader"
  # Open MPI 4.1: mpirun's own status after SIGTERM, whatever the ranks do.
  finish 1
  grep -q "^interrupted: stopped by SIGTERM at step" "$cut_log" ||
    fail "the ranks did not save a checkpoint in Open MPI's grace time: $(tail -3 "$cut_log")"
  [ -s "$cut/checkpoint.bin" ] || fail "no checkpoint"
  resume "$cut"
  grep -q "^resumed from $cut/checkpoint.bin" "$cut.log" || fail "the rerun did not resume"
  echo "ok: mpirun exited 1 (Open MPI), the ranks saved a checkpoint; result identical"
  ;;
anytime)
  # No pause: the signal lands wherever the run is when the line appears.
  n=0
  for line in "output $cut/calibration/" "output $cut/$"; do
    n=$((n + 1))
    [ $n -eq 2 ] && cp "$ref.cal" "$cut.cal"  # the sample only
    start "$cut" "$wrapper" 2
    end=$((SECONDS + 120))
    until grep -q -- "$line" "$cut_log" || [ $SECONDS -ge $end ]; do sleep 0.01; done
    grep -q -- "$line" "$cut_log" || fail "no line '$line'"
    kill -USR1 "$leader"
    wait "$leader"; status=$?; leader=""
    [ "$status" -eq 4 ] || [ "$status" -eq 0 ] ||
      fail "trial $n: exit status $status: $(grep -v '^step' "$cut_log" | tail -3)"
    echo "trial $n ('$line'): exit $status: $(grep '^interrupted' "$cut_log")"
    cp "$cut_log" "$work/trial$n.log"
    resume "$cut"
    rm -rf "$cut" "$cut".*
  done
  echo "ok: every trial ended with exit 4 and the rerun gave the uninterrupted result"
  ;;
*) fail "unknown mode $mode" ;;
esac
