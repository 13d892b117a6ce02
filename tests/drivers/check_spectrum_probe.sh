#!/bin/bash
# The spectrum probe is a diagnostic: where it cannot write (here a full
# 16 KiB tmpfs), the run at 2 ranks goes on to the same result, says so,
# and leaves none of the probe's files; where it can, it writes all four.
# Usage: check_spectrum_probe.sh LEM_FRACTURE WORKDIR MPIEXEC [MPI flags...]
# Skipped (77) when a tmpfs cannot be mounted (under CI=true it fails: tmpfs.sh).
set -u
prog="$1"; work="$2"; shift 2
mpi=("$@")
fail() { echo "FAIL: $*"; exit 1; }
disk="$work/disk"
source "$(dirname "$0")/tmpfs.sh"
rm -rf "$work"; mkdir -p "$work"
trap 'while mountpoint -q "$disk" 2> /dev/null; do umount -l "$disk"; done' EXIT
args=(-lattice_bonds 3000 -solver_spectrum_solves 3)
"${mpi[@]}" -n 2 "$prog" "${args[@]}" -output_dir "$work/written" \
  -solver_spectrum_prefix "$work/probe" > "$work/written.log" 2>&1 || fail "the run failed: $(tail -3 "$work/written.log")"
for f in probe_3.txt probe_3.bin probe_3.bin.info probe_3_bonds.txt; do
  [ -s "$work/$f" ] || fail "the probe did not write $f"
done
mount_tmpfs_at "$disk" 16k
"${mpi[@]}" -n 2 "$prog" "${args[@]}" -output_dir "$work/full" \
  -solver_spectrum_prefix "$disk/probe" > "$work/full.log" 2>&1 || fail "a probe on a full disk ended the run: $(tail -3 "$work/full.log")"
grep -q "spectrum probe at solve 3: its files were not written (.*); the run goes on" "$work/full.log" ||
  fail "no note of the unwritten probe: $(grep -i spectrum "$work/full.log")"
[ -z "$(ls -A "$disk")" ] || fail "the probe left files on the full disk: $(ls "$disk")"
without_time() { sed 's/,[^,]*$//' "$1"; }  # the last column is the wall time
cmp -s <(without_time "$work/written/curve.csv") <(without_time "$work/full/curve.csv") ||
  fail "the run with an unwritten probe differs from the one with a written probe"
echo "PASS"
