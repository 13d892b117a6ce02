#!/bin/bash
# sigma^[p] and E^[p] are calibrated once per lattice and options: a second
# run reuses the stored values (same units, no calibration run), a file made
# for another lattice or a damaged one is refused with a message naming it.
#   check_calibration.sh LEM_FRACTURE MESHES_DIR WORK_DIR MPIEXEC [MPI flags...]
set -uo pipefail
program=$1 meshes=$2 dir=$3
shift 3
mpi=("$@")
rm -rf "$dir" && mkdir -p "$dir"
cal=$dir/calibration.txt
run() {  # run NAME ARGS...: lem_fracture at 2 ranks, log in $dir/NAME.log
  local name=$1
  shift
  "${mpi[@]}" -n 2 "$program" -fracture_max_steps 1 -output_fields 0 \
    -output_dir "$dir/$name" -fracture_calibration_file "$cal" "$@" > "$dir/$name.log" 2>&1
}
fail() { echo "FAIL: $*"; exit 1; }
sigma_unit() { grep -o '"sigma_unit[^,]*' "$dir/$1/summary.json" | grep -o '[0-9.e+-]*$'; }

run first -sample_file "$meshes/mini.h5" || fail "first run: $(tail -3 "$dir/first.log")"
grep -q "calibration: the homogeneous lattice" "$dir/first.log" || fail "first run did not calibrate"
grep -q "^sigma_hom=" "$cal" || fail "no calibration stored in $cal"
run second -sample_file "$meshes/mini.h5" || fail "second run: $(tail -3 "$dir/second.log")"
grep -q "calibration: the homogeneous lattice" "$dir/second.log" && fail "second run calibrated again"
grep -q "from $cal" "$dir/second.log" || fail "second run did not say where sigma^[p] came from"
[ "$(sigma_unit first)" = "$(sigma_unit second)" ] ||
  fail "sigma_unit differs: $(sigma_unit first) then $(sigma_unit second)"
[ -n "$(sigma_unit first)" ] || fail "no sigma_unit in the summary"

# Another lattice: refused, naming the file and what differs.
run other -sample_file "$meshes/tiny.h5" && fail "a calibration of another lattice was accepted"
grep -q "calibration file '$cal' was made for another lattice" "$dir/other.log" ||
  fail "unclear message: $(grep -i error "$dir/other.log" | head -2)"
grep -q "file: nodes=" "$dir/other.log" || fail "the message does not name what differs"
[ -e "$dir/other/summary.json" ] && fail "a refused run left a summary"
# Other options change the results, so they are another calibration too.
run increment -sample_file "$meshes/mini.h5" -fracture_increment 2e-4 &&
  fail "a calibration made with another increment was accepted"
grep -q "increment=" "$dir/increment.log" || fail "the increment is not named"

# A value edited by hand (the format intact) is refused by the file's
# checksum, naming the value read and how to recompute.
cp "$cal" "$cal.orig"
sed -i 's/^sigma_hom=\(.*\)$/sigma_hom=\1e0/; s/^sigma_hom=0\.0/sigma_hom=0.1/' "$cal"
cmp -s "$cal" "$cal.orig" && fail "the test did not change sigma_hom"
run edited -sample_file "$meshes/mini.h5" && fail "a hand-edited calibration file was accepted"
grep -q "calibration file '$cal' is not as it was written: its content (sigma_hom=" "$dir/edited.log" ||
  fail "unclear message for an edited file: $(grep -i error "$dir/edited.log" | head -2)"
grep -q "remove it to calibrate again" "$dir/edited.log" || fail "the message does not say how to recompute"
[ -e "$dir/edited/summary.json" ] && fail "a refused run left a summary"
cp "$cal.orig" "$cal"

# A damaged file is refused.
sed -i '/^sigma_hom=/d' "$cal"
run damaged -sample_file "$meshes/mini.h5" && fail "a damaged calibration file was accepted"
grep -q "is damaged" "$dir/damaged.log" || fail "unclear message for a damaged file"
echo "calibration reuse: OK"
