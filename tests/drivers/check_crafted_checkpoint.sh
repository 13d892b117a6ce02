#!/bin/bash
# A checkpoint that passes its checksum but does not fit the run is refused
# (exit 1, the file and the bad value named) instead of being resumed: wrong
# sizes, non-finite values, ids out of range, batches out of order, a learnt
# space wider than -solver_ritz_deflation keeps or not finite.  The
# checkpoint comes from a run stopped by a failing solve (the 40th, by the
# test hook LEM_FAULT_SOLVE_FAIL: exit 2, no signal needed);
# tests/drivers/craft_checkpoint.py rewrites it with one value
# changed and a valid checksum.  Unchanged, it resumes.
# Usage: check_crafted_checkpoint.sh LEM_FRACTURE WORKDIR
set -u
prog="$1"; work="$2"
craft=(/usr/bin/python3 "$(dirname "$0")/craft_checkpoint.py")
args=(-lattice_bonds 6000 -lattice_seed 3 -strength_disorder uniform
      -fracture_stop_fraction 0.3 -output_fields false)
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"; mkdir -p "$work"
LEM_FAULT_SOLVE_FAIL=40 "$prog" "${args[@]}" -output_dir "$work/source" > "$work/source.log" 2>&1
status=$?
[ "$status" -eq 2 ] && [ -s "$work/source/checkpoint.bin" ] ||
  fail "no checkpoint from the failing run (exit $status): $(tail -2 "$work/source.log")"
# Each case in its own copy of the folder; the runs wait mostly for MPI to
# start, so they go side by side.
cases=(short_displacement nan_displacement short_check_field bond_broken_twice node_out_of_range
       batch_beyond_state bond_not_in_sample space_too_wide nan_in_space unchanged)
for case in "${cases[@]}"; do
  cp -r "$work/source" "$work/$case"
  "${craft[@]}" "$work/source/checkpoint.bin" "$work/$case/checkpoint.bin" "$case" ||
    fail "craft $case"
  ( "$prog" "${args[@]}" -output_dir "$work/$case" > "$work/$case.log" 2>&1
    echo $? > "$work/$case.status" ) &
done
wait
expect() {  # expect CASE PATTERN: the crafted checkpoint was refused with PATTERN
  local case="$1" pattern="$2" dir="$work/$1"
  status=$(cat "$dir.status")
  [ "$status" -eq 1 ] || fail "$case: exit $status, expected 1: $(tail -2 "$dir.log")"
  grep -qE -- "$pattern" "$dir.log" || fail "$case: message does not match '$pattern': $(tail -2 "$dir.log")"
  [ ! -e "$dir/summary.json" ] || fail "$case: a summary was written"
  echo "ok: $case: $(grep -E -- "$pattern" "$dir.log" | head -1)"
}
valid="checkpoint '[^']*/checkpoint.bin' is not a valid lem checkpoint"
expect short_displacement "$valid \(2850 displacement values for 951 nodes\)"
expect nan_displacement "$valid \(displacement 5 is not finite\)"
expect short_check_field "$valid \(2850 check field values for 951 nodes\)"
expect bond_broken_twice "$valid \(bond [0-9]+ is broken twice\)"
expect node_out_of_range "$valid \(node event 0 pins node 956, not one of the 951 nodes\)"
expect batch_beyond_state "$valid \(bond event [0-9]+ is in batch 1000000, out of order"
expect bond_not_in_sample "breaks bond 1000000000 \(its bond event 2\), which is not a bond of this sample"
expect space_too_wide "$valid \(65 learnt deflation vectors, more than the 64 -solver_ritz_deflation keeps\)"
expect nan_in_space "$valid \(learnt deflation vector 0 value 7 is not finite\)"
# The same file rewritten unchanged resumes and finishes.
[ "$(cat "$work/unchanged.status")" -eq 0 ] ||
  fail "the unchanged checkpoint did not resume: $(tail -2 "$work/unchanged.log")"
grep -q "^resumed from" "$work/unchanged.log" || fail "the unchanged checkpoint was not resumed"
echo "ok: the checkpoint rewritten unchanged resumes"
