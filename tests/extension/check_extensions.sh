#!/bin/bash
# The example extensions (extended_fracture.cpp) compile, are listed by
# -help, and run: the break rule breaks the -fracture_weakest_count
# smallest-threshold critical bonds per relaxation cycle (1 by default), its
# summary field weakest_bonds_per_cycle says how many, and its fingerprint
# line refuses a result or a checkpoint of another count; the relaxation
# scheme, which delegates to the global one, breaks the same bonds in the
# same order as lem_fracture and its summary field counted_steps counts what
# it relaxed; the output is committed with each result and counts every
# broken bond.
# Usage: check_extensions.sh EXTENDED LEM_FRACTURE WORKDIR
set -u
extended="$1"; reference="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
args=(-lattice_bonds 6000 -lattice_seed 3 -strength_disorder uniform -strength_disorder_width 0.3
      -fracture_stop_fraction 0.3 -output_fields false)
"$extended" -help > "$work/help.log" 2>&1
grep -q "(all|most_critical|weakest_first)" "$work/help.log" &&
  grep -q "(global|local|counted_global)" "$work/help.log" &&
  grep -q -- "-fracture_weakest_count" "$work/help.log" &&
  grep -q -- "-fracture_counted_label" "$work/help.log" || fail "-help does not list them"
value() { /usr/bin/python3 -c "import json, sys; print(json.load(open(sys.argv[1]))[sys.argv[2]])" "$1/summary.json" "$2"; }
per_cycle() { tail -n +2 "$1/broken.csv" | cut -d, -f1,2 | sort | uniq -c | awk '$1 > m { m = $1 } END { print m + 0 }'; }

# The break rule: by default one bond per relaxation cycle, the weakest.
"$extended" "${args[@]}" -fracture_break_rule weakest_first -output_dir "$work/weakest" \
  > "$work/weakest.log" 2>&1 || fail "weakest_first: $(tail -3 "$work/weakest.log")"
grep -q '"break_rule": "weakest_first"' "$work/weakest/summary.json" || fail "summary: no weakest_first"
[ "$(per_cycle "$work/weakest")" -eq 1 ] || fail "weakest_first broke $(per_cycle "$work/weakest") bonds in one relaxation cycle"
broken=$(($(wc -l < "$work/weakest/broken.csv") - 1))
[ "$broken" -gt 10 ] || fail "weakest_first broke only $broken bonds"
[ "$(value "$work/weakest" weakest_bonds_per_cycle)" = 1 ] ||
  fail "the rule's summary field: $(value "$work/weakest" weakest_bonds_per_cycle), not 1"
echo "ok: weakest_first: $broken bonds, one per relaxation cycle"

# Its option changes the result, and its summary field says by how much.
three=(-fracture_break_rule weakest_first -fracture_weakest_count 3)
"$extended" "${args[@]}" "${three[@]}" -output_dir "$work/three" > "$work/three.log" 2>&1 ||
  fail "-fracture_weakest_count 3: $(tail -3 "$work/three.log")"
[ "$(per_cycle "$work/three")" -eq 3 ] || fail "-fracture_weakest_count 3 broke at most $(per_cycle "$work/three") bonds in a cycle"
/usr/bin/python3 - "$work/three/summary.json" <<'PY' || fail "weakest_bonds_per_cycle is not broken / relaxation_cycles"
import json, sys
s = json.load(open(sys.argv[1]))
v, expected = s["weakest_bonds_per_cycle"], s["broken"] / s["relaxation_cycles"]
print(f"weakest_bonds_per_cycle = {v}, broken / relaxation_cycles = {expected:.10g}")
sys.exit(not (abs(v - expected) < 1e-9 and 1 < v <= 3))
PY
echo "ok: -fracture_weakest_count 3: up to 3 bonds per cycle, $(value "$work/three" weakest_bonds_per_cycle) in the summary"

# Its fingerprint line: a result and a checkpoint of another count are
# refused, naming it; the same count resumes to the uninterrupted result.
"$extended" "${args[@]}" "${three[@]}" -fracture_weakest_count 2 -output_dir "$work/three" \
  > "$work/other.log" 2>&1 && fail "a finished result of another -fracture_weakest_count was taken"
grep -q "weakest_count=3 .*this run: weakest_count=2" "$work/other.log" ||
  fail "the refused result does not name weakest_count: $(tail -3 "$work/other.log")"
mkdir -p "$work/cut"
LEM_FAULT_SOLVE_FAIL=30 "$extended" "${args[@]}" "${three[@]}" -output_dir "$work/cut" \
  > "$work/cut1.log" 2>&1
status=$?
[ "$status" -eq 2 ] && [ -s "$work/cut/checkpoint.bin" ] || fail "no checkpoint (exit $status): $(tail -3 "$work/cut1.log")"
"$extended" "${args[@]}" "${three[@]}" -fracture_weakest_count 2 -output_dir "$work/cut" \
  > "$work/cut2.log" 2>&1 && fail "a checkpoint of another -fracture_weakest_count was resumed"
grep -q "checkpoint: weakest_count=3 .*this run: weakest_count=2" "$work/cut2.log" &&
  grep -q "checkpoint: -fracture_weakest_count=3 .*this run: -fracture_weakest_count=2" "$work/cut2.log" ||
  fail "the refused checkpoint does not name weakest_count: $(tail -3 "$work/cut2.log")"
"$extended" "${args[@]}" "${three[@]}" -output_dir "$work/cut" > "$work/cut3.log" 2>&1 ||
  fail "resume: $(tail -3 "$work/cut3.log")"
grep -q "^resumed from" "$work/cut3.log" || fail "the rerun did not resume"
cmp -s "$work/three/broken.csv" "$work/cut/broken.csv" || fail "the resumed run broke other bonds"
[ "$(value "$work/cut" weakest_bonds_per_cycle)" = "$(value "$work/three" weakest_bonds_per_cycle)" ] ||
  fail "the resumed run reports another weakest_bonds_per_cycle"
echo "ok: weakest_count in the fingerprint: $(grep -o "checkpoint: weakest_count=3 .*" "$work/cut2.log" | head -1)"

"$extended" "${args[@]}" -fracture_relaxation counted_global -output_dir "$work/counted" \
  > "$work/counted.log" 2>&1 || fail "counted_global: $(tail -3 "$work/counted.log")"
grep -q "^counted_global: [1-9][0-9]* load steps relaxed" "$work/counted.log" ||
  fail "counted_global did not relax: $(tail -3 "$work/counted.log")"
steps=$(grep -o "^counted_global: [0-9]*" "$work/counted.log" | grep -o "[0-9]*$")
[ "$(value "$work/counted" counted_steps)" = "$steps" ] ||
  fail "counted_steps of the summary: $(value "$work/counted" counted_steps), the scheme counted $steps"
[ "$(value "$work/weakest" counted_steps)" = 0 ] || fail "counted_steps is not 0 under another scheme"
# The scheme's own option, read with the protocol's; a misspelt one is refused.
"$extended" "${args[@]}" -fracture_relaxation counted_global -fracture_counted_label tally \
  -output_dir "$work/labelled" > "$work/labelled.log" 2>&1 || fail "labelled: $(tail -3 "$work/labelled.log")"
grep -q "^tally: [1-9][0-9]* load steps relaxed" "$work/labelled.log" || fail "-fracture_counted_label was not read"
"$extended" "${args[@]}" -fracture_counted_lable x -output_dir "$work/typo" > "$work/typo.log" 2>&1 &&
  fail "a misspelt option of the scheme was accepted"
grep -q "fracture_counted_lable" "$work/typo.log" || fail "the misspelt option is not named"
"$reference" "${args[@]}" -output_dir "$work/global" > "$work/global.log" 2>&1 ||
  fail "lem_fracture: $(tail -3 "$work/global.log")"
cmp -s "$work/counted/broken.csv" "$work/global/broken.csv" ||
  fail "counted_global broke other bonds than the global scheme"
grep -q '"weakest_bonds_per_cycle"\|"counted_steps"' "$work/global/summary.json" &&
  fail "lem_fracture's summary has the extensions' fields"
echo "ok: counted_global: $(grep -o '[0-9]* load steps relaxed' "$work/counted.log"), the same ruptures as the global scheme"

# The solver lever (counted_lever.cpp): listed by -help, put around the
# multigrid by its option, and it changes no result.
grep -q -- "-solver_counted_applications" "$work/help.log" || fail "-help does not list the lever's option"
"$extended" "${args[@]}" -solver_counted_applications -output_dir "$work/lever" > "$work/lever.log" 2>&1 ||
  fail "-solver_counted_applications: $(tail -3 "$work/lever.log")"
grep -q "^counted_lever: [1-9][0-9]* applications of the multigrid" "$work/lever.log" ||
  fail "the lever was not put around the multigrid"
without_clock() { rev "$1" | cut -d, -f2- | rev; }  # curve.csv but its last column, elapsed_s
cmp -s "$work/lever/broken.csv" "$work/global/broken.csv" &&
  cmp -s <(without_clock "$work/lever/curve.csv") <(without_clock "$work/global/curve.csv") ||
  fail "the counting lever changed the result"
"$extended" "${args[@]}" -pc_type ext_counted -output_dir "$work/as_pc" > "$work/as_pc.log" 2>&1 &&
  fail "-pc_type ext_counted was accepted"
grep -q "choose it with -solver_counted_applications" "$work/as_pc.log" || fail "-pc_type ext_counted: $(tail -2 "$work/as_pc.log")"
echo "ok: the counting lever: $(grep -o '[0-9]* applications' "$work/lever.log" | head -1), the same result as lem_fracture"

# The output: in the manifest of each result of the extended program, its
# slabs summing to the ruptures plus the bonds of loose pieces; not in
# lem_fracture's.
profile="$work/counted/damage_profile.csv"
grep -q "^file=damage_profile.csv " "$work/counted/manifest.txt" || fail "damage_profile.csv is not committed"
in_slabs=$(tail -n +2 "$profile" | awk -F, '{ s += $3 } END { print s + 0 }')
expected=$(/usr/bin/python3 -c "import json, sys; s = json.load(open(sys.argv[1])); print(s['broken'] + s['detached_bonds'])" "$work/counted/summary.json")
[ "$in_slabs" -eq "$expected" ] || fail "damage_profile.csv counts $in_slabs broken bonds, the summary $expected"
[ "$(tail -n +2 "$profile" | wc -l)" -eq 10 ] || fail "damage_profile.csv has not 10 slabs"
[ ! -e "$work/global/damage_profile.csv" ] || fail "lem_fracture wrote the extension's output"
echo "ok: damage_profile.csv committed, $in_slabs broken bonds in its slabs as in the summary"
