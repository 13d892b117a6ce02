#!/bin/bash
# A run never destroys a finished result and never leaves a partial one
# looking final (lem_fracture at 1 rank, a small random lattice).
# Usage: check_outputs.sh MODE LEM_FRACTURE WORKDIR
#   keep_finished  runs that fail (bad sample file, bad option, unknown solver,
#                  other options) leave a finished output folder byte-identical
#   rerun          the same command again says the result is complete and
#                  computes nothing; -output_overwrite computes it again
#   concurrent     a run on a folder locked by another run is refused (exit 1)
#   disk_full      a full disk (a 16 KiB tmpfs) gives exit 3 naming the file
#                  and no final-looking result; skipped (77) if mount fails
#   commit_kill    kill -9 at each step of the commit (LEM_FAULT_KILL), then
#                  the same command: the complete result, equal to a run
#                  never killed
#   short_log      a resume whose broken.csv.part is shorter than the
#                  checkpoint records is refused, naming the file
set -u
mode="$1"; prog="$2"; work="$3"
args=(-lattice_bonds 6000 -lattice_seed 3 -strength_disorder uniform
      -fracture_stop_fraction 0.3 -checkpoint_steps 4 -checkpoint_seconds 0)
fail() { echo "FAIL: $*"; exit 1; }
run() {  # run DIR [extra args]: the driver at 1 rank, output in DIR.log
  local dir="$1"; shift
  "$prog" "${args[@]}" -output_dir "$dir" "$@" > "$dir.log" 2>&1
}
digest() { (cd "$1" && find . -type f ! -name .lock -exec md5sum {} + | sort); }
same_result() {  # same_result A B: curve (but the wall time) and log identical
  diff <(cut -d, -f1-21 "$1/curve.csv") <(cut -d, -f1-21 "$2/curve.csv") > /dev/null ||
    fail "$2/curve.csv differs from $1/curve.csv"
  cmp -s "$1/broken.csv" "$2/broken.csv" || fail "$2/broken.csv differs from $1/broken.csv"
  [ -s "$2/manifest.txt" ] || fail "no manifest in $2"
  [ ! -e "$2/checkpoint.bin" ] || fail "a committed run left its checkpoint in $2"
}
# A tmpfs left mounted by an aborted disk_full run.
while mountpoint -q "$work/full" 2> /dev/null; do umount -l "$work/full"; done
rm -rf "$work"; mkdir -p "$work"

case "$mode" in
keep_finished)
  run "$work/done" || fail "first run: $(tail -3 "$work/done.log")"
  before=$(digest "$work/done")
  grep -q "fields.h5" <<< "$before" || fail "no fields to protect"
  expect() {  # expect PATTERN ARGS...: fails with PATTERN, the folder unchanged
    local pattern="$1"; shift
    "$prog" "$@" -output_dir "$work/done" > "$work/bad.log" 2>&1 && fail "accepted: $*"
    grep -qE -- "$pattern" "$work/bad.log" || fail "message for '$*': $(tail -2 "$work/bad.log")"
    [ "$(digest "$work/done")" = "$before" ] || fail "'$*' changed the finished result"
    echo "ok: $(grep -E -- "$pattern" "$work/bad.log" | head -1)"
  }
  expect "sample file '/nonexistent.h5' does not exist" -sample_file /nonexistent.h5
  expect "is not a readable HDF5 file" -sample_file "$0"
  expect "-fracture_increment = 0 is out of range" "${args[@]}" -fracture_increment 0
  expect "-ksp_type = 'cgg' is not a KSP type" "${args[@]}" -ksp_type cgg
  expect "unknown option" "${args[@]}" -fracture_incremnt 2e-4
  expect "holds the finished result of another run" "${args[@]}" -fracture_increment 2e-4
  ;;
rerun)
  run "$work/done" || fail "first run: $(tail -3 "$work/done.log")"
  before=$(digest "$work/done")
  run "$work/done" || fail "rerun: $(tail -3 "$work/done.log")"
  grep -q "is complete (manifest.txt): nothing to do" "$work/done.log" ||
    fail "the rerun did not say the result is complete: $(tail -3 "$work/done.log")"
  grep -q "^lattice:" "$work/done.log" && fail "the rerun computed again"
  [ "$(digest "$work/done")" = "$before" ] || fail "the rerun changed the result"
  echo "ok: $(grep 'is complete' "$work/done.log")"
  cp -r "$work/done" "$work/first"
  run "$work/done" -output_overwrite || fail "overwrite: $(tail -3 "$work/done.log")"
  grep -q "^lattice:" "$work/done.log" || fail "-output_overwrite did not compute again"
  same_result "$work/first" "$work/done"
  echo "ok: -output_overwrite computed the same result again"
  ;;
concurrent)
  mkdir -p "$work/busy"
  # -o: the lock stays with flock itself, not with sleep, so killing flock
  # releases it.
  flock -o "$work/busy/.lock" sleep 60 > /dev/null 2>&1 &
  holder=$!
  for _ in $(seq 1 100); do flock -n "$work/busy/.lock" true || break; sleep 0.05; done
  run "$work/busy"; status=$?
  sleeper=$(pgrep -P "$holder")
  kill "$holder" $sleeper; wait "$holder" 2> /dev/null
  [ "$status" -eq 1 ] || fail "exit status $status on a locked folder, expected 1"
  grep -q "is in use by another run" "$work/busy.log" || fail "message: $(tail -2 "$work/busy.log")"
  [ ! -e "$work/busy/curve.csv.part" ] || fail "the refused run wrote results"
  echo "ok: $(grep 'in use' "$work/busy.log")"
  run "$work/busy" || fail "the run after the lock was released: $(tail -3 "$work/busy.log")"
  echo "ok: the lock is taken once released"
  ;;
disk_full)
  # The log stays outside: an MPI singleton's helper keeps it open a while.
  mkdir -p "$work/full"
  mount -t tmpfs -o size=16k tmpfs "$work/full" 2> /dev/null ||
    { echo "SKIP: cannot mount a tmpfs"; exit 77; }
  trap 'umount -l "$work/full"' EXIT
  # No checkpoint: the curve and the log are what fills the disk.
  run "$work/full" -output_fields false -checkpoint_steps 0; status=$?
  [ "$status" -eq 3 ] || fail "exit status $status on a full disk, expected 3: $(tail -2 "$work/full.log")"
  grep -qE "cannot (write|sync|close|move) '$work/full/(curve|broken)\.csv" "$work/full.log" ||
    fail "the message does not name the file: $(tail -2 "$work/full.log")"
  for f in curve.csv broken.csv summary.json summary.csv manifest.txt; do
    [ ! -e "$work/full/$f" ] || fail "a full disk left $f"
  done
  echo "ok: $(grep -E 'cannot' "$work/full.log" | head -1)"
  ;;
commit_kill)
  run "$work/whole" || fail "uninterrupted run: $(tail -3 "$work/whole.log")"
  for point in between_renames before_manifest after_manifest; do
    LEM_FAULT_KILL=$point run "$work/$point"; status=$?
    [ "$status" -eq 137 ] || fail "$point: exit status $status, expected 137 (SIGKILL)"
    if [ "$point" = after_manifest ]; then
      [ -e "$work/$point/checkpoint.bin" ] || fail "$point: no checkpoint left to clean up"
    else
      [ ! -e "$work/$point/manifest.txt" ] || fail "$point: a manifest before the commit"
    fi
    run "$work/$point" || fail "$point: the rerun failed: $(tail -3 "$work/$point.log")"
    if [ "$point" = after_manifest ]; then
      grep -q "is complete" "$work/$point.log" || fail "$point: the rerun computed again"
    else
      grep -q "^resumed from" "$work/$point.log" || fail "$point: the rerun did not resume"
    fi
    same_result "$work/whole" "$work/$point"
    echo "ok: killed at $point; the rerun gives the complete result"
  done
  ;;
short_log)
  LEM_FAULT_KILL=before_manifest run "$work/cut"
  [ -s "$work/cut/checkpoint.bin" ] || fail "no checkpoint to resume"
  mv "$work/cut/broken.csv" "$work/cut/broken.csv.part"
  truncate -s 100 "$work/cut/broken.csv.part"
  run "$work/cut" && fail "a resume with a short broken.csv.part was accepted"
  grep -q "broken.csv.part' has 100 bytes, fewer than" "$work/cut.log" ||
    fail "message: $(tail -2 "$work/cut.log")"
  [ "$(tr -d '\000' < "$work/cut/broken.csv.part" | wc -c)" -eq 100 ] || fail "the log was padded"
  echo "ok: $(grep 'fewer than' "$work/cut.log")"
  ;;
*) fail "unknown mode $mode" ;;
esac
