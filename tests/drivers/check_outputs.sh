#!/bin/bash
# A run never destroys a finished result and never leaves a partial one
# looking final (lem_fracture at 1 rank, a small random lattice).
# Usage: check_outputs.sh MODE LEM_FRACTURE WORKDIR
#   keep_finished  runs that fail (bad sample file, bad option, unknown solver,
#                  other options) leave a finished output folder byte-identical
#   rerun          the same command again says the result is complete and
#                  computes nothing; -output_overwrite computes it again
#   concurrent     a run on a folder locked by another run is refused (exit 1)
#   changed_content a finished result whose file changed at the same size
#                  (one byte of curve.csv, of fields.h5) is refused by the
#                  manifest's checksums, naming the file; -output_overwrite
#                  computes it again
#   disk_full      a full disk (a 16 KiB tmpfs) gives exit 3 naming the file
#                  and no final-looking result; skipped (77) if mount fails
#                  (under CI=true it fails instead: tmpfs.sh)
#   commit_kill    kill -9 at each step of the commit (LEM_FAULT_KILL), then
#                  the same command: the complete result, equal to a run
#                  never killed
#   short_log      a resume whose broken.csv.part is shorter than the
#                  checkpoint records, or whose broken.csv.part or curve.csv
#                  has other content than it recorded (one byte changed, the
#                  size kept), is refused, naming the file
#   overwrite_kill kill -9 of an -output_overwrite run mid-run (LEM_FAULT_PAUSE)
#                  and at each step of its commit and of putting the new
#                  result in place (LEM_FAULT_KILL): until the new result is
#                  complete the folder holds the old one, intact and valid;
#                  the same command without -output_overwrite finds a
#                  finished result and computes nothing; with it, the result
#                  of a run never killed, the staging folder gone and a
#                  study's files (run.json) kept
#   overwrite_kill_renames  the same on a filesystem taken to have no
#                  RENAME_EXCHANGE (LEM_FAULT_NO_EXCHANGE): two renames, and
#                  a kill between them leaves the new result to be put in
#                  place by the next run
#   overwrite_stale  staging folders in the way: a foreign one, one in use,
#                  one of other options (checkpoint or finished result), a
#                  symbolic link as -output_dir
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
valid() {  # valid DIR: a manifest with its end line, every file it lists of its size
  grep -qx end "$1/manifest.txt" 2> /dev/null || return 1
  local name size
  while read -r name size; do
    [ "$(stat -c %s "$1/$name" 2> /dev/null)" = "$size" ] || return 1
  done < <(sed -n 's/^file=//p' "$1/manifest.txt")
}
result_digest() {  # the manifest and the files it lists
  (cd "$1" && md5sum manifest.txt $(sed -n 's/^file=\([^ ]*\) .*/\1/p' manifest.txt))
}
pause_start() {  # pause_start POINT DIR [extra args]: a run in the background, held
  # where LEM_FAULT_PAUSE stops it (leader: its pid; paused: the pid it prints)
  local point="$1" dir="$2"; shift 2
  LEM_FAULT_PAUSE="$point" "$prog" "${args[@]}" -output_dir "$dir" "$@" > "$dir.log" 2>&1 &
  leader=$! paused=""
  for _ in $(seq 1 1200); do
    paused=$(sed -n 's/^test hook: rank 0 (pid \([0-9]*\)).*/\1/p' "$dir.log")
    [ -n "$paused" ] && return 0
    kill -0 "$leader" 2> /dev/null || fail "$point: the run ended before the pause: $(tail -2 "$dir.log")"
    sleep 0.1
  done
  kill -KILL "$leader"
  fail "$point: no pause within 120 s"
}
pause_kill() {  # pause_kill POINT DIR [extra args]: the same, then SIGKILL there
  pause_start "$@"
  kill -KILL "$paused"
  wait "$leader"
}
same_result() {  # same_result A B: curve (but the wall time) and log identical
  diff <(cut -d, -f1-22 "$1/curve.csv") <(cut -d, -f1-22 "$2/curve.csv") > /dev/null ||
    fail "$2/curve.csv differs from $1/curve.csv"
  cmp -s "$1/broken.csv" "$2/broken.csv" || fail "$2/broken.csv differs from $1/broken.csv"
  [ -s "$2/manifest.txt" ] || fail "no manifest in $2"
  [ ! -e "$2/checkpoint.bin" ] || fail "a committed run left its checkpoint in $2"
}
# A tmpfs left mounted by an aborted disk_full run.
while mountpoint -q "$work/full" 2> /dev/null; do umount -l "$work/full"; done
rm -rf "$work"; mkdir -p "$work"
unset LEM_FAULT_KILL LEM_FAULT_PAUSE LEM_FAULT_NO_EXCHANGE

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
  [ ! -e "$work/done.overwrite" ] || fail "-output_overwrite left its staging folder"
  echo "ok: -output_overwrite computed the same result again"
  ;;
changed_content)
  run "$work/done" || fail "first run: $(tail -3 "$work/done.log")"
  for f in curve.csv fields.h5; do
    cp "$work/done/$f" "$work/$f.orig"
    size=$(stat -c %s "$work/done/$f")
    # The byte in the middle, changed (and the size kept).
    offset=$((size / 2))
    byte=$(od -An -tu1 -j "$offset" -N1 "$work/done/$f" | tr -d ' ')
    printf "\\$(printf %o $(( (byte + 1) % 256 )))" |
      dd of="$work/done/$f" bs=1 seek="$offset" conv=notrunc 2> /dev/null
    [ "$(stat -c %s "$work/done/$f")" = "$size" ] || fail "the test changed the size of $f"
    cmp -s "$work/done/$f" "$work/$f.orig" && fail "the test did not change $f"
    run "$work/done"; status=$?
    [ "$status" -eq 1 ] || fail "$f changed at its size: exit $status, expected 1"
    grep -q "holds a finished result changed since it was written:" "$work/done.log" &&
      grep -q "$f has other content than was committed (checksum crc32:[0-9a-f]*, the manifest says crc32:[0-9a-f]*)" "$work/done.log" &&
      grep -q "pass -output_overwrite to compute it again" "$work/done.log" ||
      fail "message for $f: $(grep -A2 error "$work/done.log")"
    echo "ok: $f changed at its size is refused: $(grep 'other content' "$work/done.log")"
    cp "$work/$f.orig" "$work/done/$f"
  done
  run "$work/done" || fail "the restored result: $(tail -3 "$work/done.log")"
  grep -q "is complete (manifest.txt): nothing to do" "$work/done.log" || fail "the restored result is not complete"
  echo "ok: restored, the result is complete again"
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
  source "$(dirname "$0")/tmpfs.sh"
  mount_tmpfs_at "$work/full" 16k
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
  # One byte of a log changed within what the checkpoint recorded, at the
  # same size: broken.csv as the .part it is while the run goes on,
  # curve.csv under the final name the kill left (the resume takes it back).
  for f in broken.csv curve.csv; do
    d="$work/edited_${f%.csv}"
    cp -a "$work/cut" "$d"
    [ "$f" = broken.csv ] && mv "$d/$f" "$d/$f.part"
    log="$d/$f"; [ -e "$log" ] || log="$d/$f.part"
    byte=$(od -An -tu1 -j 150 -N1 "$log" | tr -d ' ')
    printf "\\$(printf %o $(( (byte + 1) % 256 )))" | dd of="$log" bs=1 seek=150 conv=notrunc 2> /dev/null
    cp "$log" "$d.edited"
    run "$d" && fail "a resume with an edited $f was accepted"
    grep -q "$f.part' has other content than the checkpoint recorded (checksum crc32:[0-9a-f]* of its first [0-9]* bytes, the checkpoint says crc32:[0-9a-f]*); remove the checkpoint to start over" "$d.log" ||
      fail "message for an edited $f: $(tail -2 "$d.log")"
    cmp -s "$d/$f.part" "$d.edited" || fail "the refused resume changed $f.part"
    echo "ok: $(grep -o "[^/]*.part' has other content.*" "$d.log")"
  done
  mv "$work/cut/broken.csv" "$work/cut/broken.csv.part"
  truncate -s 100 "$work/cut/broken.csv.part"
  run "$work/cut" && fail "a resume with a short broken.csv.part was accepted"
  grep -q "broken.csv.part' has 100 bytes, fewer than" "$work/cut.log" ||
    fail "message: $(tail -2 "$work/cut.log")"
  [ "$(tr -d '\000' < "$work/cut/broken.csv.part" | wc -c)" -eq 100 ] || fail "the log was padded"
  echo "ok: $(grep 'fewer than' "$work/cut.log")"
  ;;
overwrite_kill | overwrite_kill_renames)
  [ "$mode" = overwrite_kill_renames ] && export LEM_FAULT_NO_EXCHANGE=1
  run "$work/whole" || fail "uninterrupted run: $(tail -3 "$work/whole.log")"
  if [ "$mode" = overwrite_kill ]; then
    points="load_step:2 load_step:12 fields between_renames before_manifest after_manifest
            before_exchange after_exchange discarding"
  else
    points="load_step:12 after_manifest moved_aside after_install discarding"
  fi
  for point in $points; do
    d="$work/${point/:/_}"
    cp -a "$work/whole" "$d"
    echo '{"study": 1}' > "$d/run.json"   # not lem's: stays with the folder
    touch "$d/fracture.png" "$d/fracture.pdf" "$d/stress.pdf"  # drawn from the old result: go with it
    old=$(result_digest "$d")
    case "$point" in
    *:* | fields) pause_kill "$point" "$d" -output_overwrite; status=$? ;;
    *) LEM_FAULT_KILL=$point run "$d" -output_overwrite; status=$? ;;
    esac
    [ "$status" -eq 137 ] || fail "$point: exit status $status, expected 137 (SIGKILL): $(tail -2 "$d.log")"
    case "$point" in
    after_exchange | discarding | after_install)  # the new result is in place
      valid "$d" || fail "$point: $d holds no valid result"
      [ "$(result_digest "$d")" != "$old" ] || fail "$point: the old result is still there"
      same_result "$work/whole" "$d" ;;
    moved_aside)  # between the two renames: the new result waits beside
      [ ! -e "$d" ] || fail "$point: $d is still there"
      valid "$d.overwrite" || fail "$point: no complete new result in $d.overwrite"
      [ "$(result_digest "$d.overwrite/.replaced")" = "$old" ] || fail "$point: the old result changed" ;;
    *)
      valid "$d" || fail "$point: the old result is not valid any more"
      [ "$(result_digest "$d")" = "$old" ] || fail "$point: the old result changed" ;;
    esac
    grep -q "the one in $d/ stays until it is complete" "$d.log" || fail "$point: no staging"
    [ -d "$d.overwrite" ] || [ -d "$d/.replaced" ] || fail "$point: no staging folder"
    case "$point" in
    load_step:12 | fields | between_renames | before_manifest)
      [ -e "$d.overwrite/checkpoint.bin" ] || fail "$point: no checkpoint in the staging folder" ;;
    esac
    # The same command without -output_overwrite: a finished result, nothing computed.
    run "$d" || fail "$point: the rerun without -output_overwrite failed: $(tail -3 "$d.log")"
    grep -q "is complete (manifest.txt): nothing to do" "$d.log" || fail "$point: $(tail -2 "$d.log")"
    grep -q "^lattice:" "$d.log" && fail "$point: the rerun without -output_overwrite computed"
    case "$point" in
    after_exchange | discarding | after_install | moved_aside)
      [ ! -e "$d.overwrite" ] || fail "$point: the rerun left $d.overwrite"
      same_result "$work/whole" "$d" ;;
    *)
      [ "$(result_digest "$d")" = "$old" ] || fail "$point: the rerun changed the old result"
      grep -q "holds an -output_overwrite run of $d/ that did not end" "$d.log" ||
        fail "$point: no note of the staging folder" ;;
    esac
    # With it: the result of a run never killed.
    run "$d" -output_overwrite || fail "$point: the rerun failed: $(tail -3 "$d.log")"
    case "$point" in
    load_step:2)
      grep -q "held a run stopped before its first checkpoint: starting over" "$d.log" ||
        fail "$point: the rerun did not start over" ;;
    load_step:12 | fields | between_renames | before_manifest)
      grep -q "^resumed from" "$d.log" || fail "$point: the rerun did not resume" ;;
    after_manifest | before_exchange)
      grep -q "holds the complete result of this run, not yet in place" "$d.log" ||
        fail "$point: the rerun did not put the staged result in place"
      grep -q "^lattice:" "$d.log" && fail "$point: the rerun computed again" ;;
    esac
    same_result "$work/whole" "$d"
    valid "$d" || fail "$point: the result is not valid"
    [ ! -e "$d.overwrite" ] || fail "$point: $d.overwrite is left"
    for f in .superseded .overwrite_of .replaced fracture.png fracture.pdf stress.pdf; do
      [ ! -e "$d/$f" ] || fail "$point: $d/$f is left"
    done
    grep -q study "$d/run.json" 2> /dev/null || fail "$point: run.json was lost"
    echo "ok: killed at $point: the old result stayed until the new one was complete; the rerun gives the result of a run never killed"
  done
  ;;
overwrite_stale)
  run "$work/done" || fail "first run: $(tail -3 "$work/done.log")"
  old=$(result_digest "$work/done")
  unchanged() { [ "$(result_digest "$work/done")" = "$old" ] || fail "$1 changed the result"; }
  # Something else where the staging folder goes: refused, left alone.
  mkdir "$work/done.overwrite"; echo mine > "$work/done.overwrite/notes.txt"
  run "$work/done" -output_overwrite && fail "a foreign staging folder was used"
  grep -q "which holds something else: move or remove it" "$work/done.log" || fail "message: $(tail -2 "$work/done.log")"
  [ "$(cat "$work/done.overwrite/notes.txt")" = mine ] || fail "the foreign folder was changed"
  unchanged "the refused run"
  echo "ok: $(grep 'something else' "$work/done.log")"
  rm -r "$work/done.overwrite"
  # A symbolic link: the link would be replaced, not the folder.
  ln -s done "$work/link"
  run "$work/link" -output_overwrite && fail "a symbolic link was replaced"
  grep -q "it is a symbolic link" "$work/link.log" || fail "message: $(tail -2 "$work/link.log")"
  [ ! -e "$work/link.overwrite" ] || fail "a staging folder beside the link"
  unchanged "the link"
  echo "ok: $(grep 'symbolic link' "$work/link.log")"
  # In use: the folder and its staging folder are both locked.
  pause_start load_step:12 "$work/done" -output_overwrite
  "$prog" "${args[@]}" -output_dir "$work/done" > "$work/second.log" 2>&1 && fail "a second run on a busy folder"
  grep -q "is in use by another run" "$work/second.log" || fail "message: $(tail -2 "$work/second.log")"
  "$prog" "${args[@]}" -output_dir "$work/done.overwrite" > "$work/second.log" 2>&1 &&
    fail "a run on the staging folder in use"
  grep -q "is in use by another run" "$work/second.log" || fail "message: $(tail -2 "$work/second.log")"
  echo "ok: the folder and its staging folder are locked while the overwrite runs"
  kill -KILL "$paused"
  wait "$leader"; status=$?
  [ "$status" -eq 137 ] || fail "the paused run: exit status $status, expected 137 (SIGKILL)"
  unchanged "the killed run"
  # Its checkpoint belongs to other options than the next run's.
  other=(-fracture_increment 2e-4)
  run "$work/done" -output_overwrite "${other[@]}" && fail "a staged checkpoint of other options was resumed"
  grep -q "belongs to a different run" "$work/done.log" || fail "message: $(tail -2 "$work/done.log")"
  unchanged "the refused run"
  echo "ok: $(grep 'belongs to a different run' "$work/done.log")"
  run "$work/done" -output_overwrite "${other[@]}" -checkpoint_resume false ||
    fail "starting over: $(tail -3 "$work/done.log")"
  grep -q "emptied (-checkpoint_resume false)" "$work/done.log" || fail "not emptied"
  grep -q "increment=0.0002" "$work/done/manifest.txt" || fail "not the result of the new options"
  [ ! -e "$work/done.overwrite" ] || fail "the staging folder is left"
  echo "ok: -checkpoint_resume false starts the overwrite over"
  # A complete staged result of other options, not yet in place.
  old=$(result_digest "$work/done")
  LEM_FAULT_KILL=before_exchange run "$work/done" -output_overwrite
  run "$work/done" -output_overwrite "${other[@]}" && fail "a staged result of other options was discarded"
  grep -q "holds the finished result of another -output_overwrite run" "$work/done.log" ||
    fail "message: $(tail -2 "$work/done.log")"
  unchanged "the refused run"
  echo "ok: $(grep 'holds the finished result of another' "$work/done.log")"
  run "$work/done" -output_overwrite || fail "putting it in place: $(tail -3 "$work/done.log")"
  grep -q "not yet in place" "$work/done.log" || fail "the staged result was not put in place"
  grep -q "increment=0.00029" "$work/done/manifest.txt" || fail "not the staged result"
  echo "ok: the command that staged it puts it in place"
  ;;
*) fail "unknown mode $mode" ;;
esac
