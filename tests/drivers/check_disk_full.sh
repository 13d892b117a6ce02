#!/bin/bash
# A full disk during a collective write (parallel HDF5 at 2 ranks) ends the
# job within seconds with exit 3, naming the file and the error, and leaves
# nothing under a final name (docs/developer/reliability-results.md, "A full disk in
# a collective write").
# Usage: check_disk_full.sh MODE LEM_FRACTURE LEM_SAMPLE WORKDIR MPIEXEC [MPI flags...]
#   sizes      tmpfs of sizes chosen so that the disk fills in each writer:
#              the first-equilibrium fields (elastic.h5, in a dataset and in
#              the closing of the file), a snapshot, the checkpoint, the
#              final fields, the summary
#   overwrite  -output_overwrite of a finished result on a tmpfs too small
#              for a second one: exit 3, the finished result byte-identical
#   stop       a rank held in the write of elastic.h5 (LEM_FAULT_STALL):
#              SIGUSR1 ends the job after -output_write_grace (exit 4), the
#              same command then gives the complete result
#   sample     lem_sample at 2 ranks on a 16 KiB tmpfs: exit 3 naming the file
# Skipped (77) when a tmpfs cannot be mounted (under CI=true it fails
# instead: tmpfs.sh).
set -u
mode="$1"; prog="$2"; sampler="$3"; work="$4"; shift 4
mpi=("$@")
args=(-lattice_bonds 6000 -lattice_seed 3 -strength_disorder uniform -fracture_stop_fraction 0.3
      -checkpoint_steps 4 -checkpoint_seconds 0 -output_snapshot_steps 5)
fail() { echo "FAIL: $*"; exit 1; }
disk="$work/disk"
source "$(dirname "$0")/tmpfs.sh"
mount_tmpfs() { mount_tmpfs_at "$disk" "$1"; }  # mount_tmpfs SIZE: a fresh tmpfs at $disk
while mountpoint -q "$disk" 2> /dev/null; do umount -l "$disk"; done
rm -rf "$work"; mkdir -p "$work"
trap 'while mountpoint -q "$disk" 2> /dev/null; do umount -l "$disk"; done' EXIT
unset LEM_FAULT_KILL LEM_FAULT_PAUSE LEM_FAULT_STALL

# run LOG ARGS...: the driver at 2 ranks, at most 120 s; sets status, seconds
run() {
  local log="$1"; shift
  local start; start=$(date +%s.%N)
  timeout -s KILL 120 "${mpi[@]}" -n 2 "$prog" "${args[@]}" "$@" > "$log" 2>&1
  status=$?
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  [ "$status" -ne 137 ] || fail "the run hung (killed after 120 s): $(grep -vE '^(step|mca_)' "$log" | tail -3)"
}
# expect_full LOG DIR: exit 3 within 30 s, the message names a file of DIR and
# the error, nothing final or temporary of the failed write left; prints the
# file named
expect_full() {
  local log="$1" dir="$2"
  [ "$status" -eq 3 ] || fail "exit status $status, expected 3: $(grep -vE '^(step|mca_)' "$log" | tail -3)"
  [ "$(echo "$seconds < 30" | bc)" = 1 ] || fail "the job took $seconds s to end"
  local line file
  line=$(grep -E "^failure" "$log" | head -1)
  file=$(sed -n "s|.*cannot write[^']*'$dir/\([^'/]*\)'.*|\1|p" <<< "$line")
  [ -n "$file" ] || fail "the message does not name the file: $line"
  grep -qiE "no space left on device" <<< "$line" || fail "the message does not name the error: $line"
  file=${file%.tmp}
  for f in "$file" "$file.tmp" manifest.txt summary.json summary.csv; do
    [ ! -e "$dir/$f" ] || fail "a full disk left $f"
  done
  named="$file"
}

case "$mode" in
sizes)
  # Measured for this lattice (2026-11-26): elastic.h5 145 kB, each of the
  # five snapshots 146 kB, fields.h5 146 kB, the whole result 1.1 MB; with
  # the checkpoint of format 3 (the check field of a decided field beside
  # the displacement) 1150k fills in fields.h5, 1180k in the summary.
  declare -A hit=()
  for size in 16k 150k 200k 320k 600k 1000k 1150k 1180k; do
    mount_tmpfs "$size"
    run "$work/$size.log" -output_dir "$disk/r"
    expect_full "$work/$size.log" "$disk/r"
    echo "ok: $size: exit 3 after $seconds s naming $named"
    named=${named%%_0*}
    hit[${named%%.json}]=1
    hit[${named%%.csv}]=1
  done
  for writer in elastic.h5 snapshot checkpoint.bin fields.h5 summary; do
    [ -n "${hit[$writer]:-}" ] ||
      fail "no size made the disk full in $writer (got: ${!hit[*]}): the sizes need adjusting"
  done
  ;;
overwrite)
  mount_tmpfs 1250k
  run "$work/first.log" -output_dir "$disk/r"
  [ "$status" -eq 0 ] || fail "first run: $(tail -3 "$work/first.log")"
  before=$(cd "$disk/r" && md5sum manifest.txt $(sed -n 's/^file=\([^ ]*\) .*/\1/p' manifest.txt))
  run "$work/over.log" -output_dir "$disk/r" -output_overwrite
  expect_full "$work/over.log" "$disk/r.overwrite"
  after=$(cd "$disk/r" && md5sum manifest.txt $(sed -n 's/^file=\([^ ]*\) .*/\1/p' manifest.txt))
  [ "$after" = "$before" ] || fail "the finished result changed"
  [ ! -e "$disk/r/.superseded" ] || fail "the finished result was marked as replaced"
  echo "ok: -output_overwrite on a full disk: exit 3 after $seconds s naming $named; the result kept"
  ;;
stop)
  LEM_FAULT_STALL=elastic "${mpi[@]}" -n 2 "$prog" "${args[@]}" -output_dir "$work/r" \
    -output_write_grace 2 > "$work/stop.log" 2>&1 &
  leader=$!
  for _ in $(seq 1 600); do
    grep -q "stalls in the write" "$work/stop.log" && break
    kill -0 "$leader" 2> /dev/null || fail "the run ended before the stall: $(tail -3 "$work/stop.log")"
    sleep 0.1
  done
  grep -q "stalls in the write" "$work/stop.log" || { kill -KILL "$leader"; fail "no stall within 60 s"; }
  start=$(date +%s.%N)
  kill -USR1 "$leader"
  for _ in $(seq 1 300); do kill -0 "$leader" 2> /dev/null || break; sleep 0.1; done
  if kill -0 "$leader" 2> /dev/null; then
    kill -KILL "$leader"; fail "SIGUSR1 did not end a job held in a write within 30 s"
  fi
  wait "$leader"; status=$?
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  [ "$status" -eq 4 ] || fail "exit status $status, expected 4: $(tail -3 "$work/stop.log")"
  grep -q "stopped by SIGUSR1 while writing '$work/r/elastic.h5'" "$work/stop.log" ||
    fail "message: $(grep -E '^interrupted' "$work/stop.log")"
  for f in elastic.h5 elastic.h5.tmp manifest.txt; do
    [ ! -e "$work/r/$f" ] || fail "the stopped write left $f"
  done
  echo "ok: SIGUSR1 ended the job held in a write after $seconds s (exit 4)"
  run "$work/again.log" -output_dir "$work/r"
  [ "$status" -eq 0 ] || fail "the same command again: $(tail -3 "$work/again.log")"
  grep -qx end "$work/r/manifest.txt" || fail "the same command again left no finished result"
  echo "ok: the same command again finished the result"
  ;;
sample)
  mount_tmpfs 16k
  start=$(date +%s.%N)
  timeout -s KILL 120 "${mpi[@]}" -n 2 "$sampler" -sample_particles 27 -lattice_bonds 20000 \
    -output_dir "$disk/s" > "$work/sample.log" 2>&1
  status=$?
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  expect_full "$work/sample.log" "$disk/s"
  echo "ok: lem_sample on a full disk: exit 3 after $seconds s naming $named"
  ;;
*) fail "unknown mode $mode" ;;
esac
