#!/bin/bash
# The example extensions (extended_fracture.cpp) compile, are listed by
# -help, and run: the break rule breaks one bond per relaxation cycle, the
# smallest-threshold critical one; the relaxation scheme, which delegates to
# the global one, breaks the same bonds in the same order as lem_fracture;
# the output is committed with each result and counts every broken bond.
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
  grep -q -- "-fracture_counted_label" "$work/help.log" || fail "-help does not list them"

"$extended" "${args[@]}" -fracture_break_rule weakest_first -output_dir "$work/weakest" \
  > "$work/weakest.log" 2>&1 || fail "weakest_first: $(tail -3 "$work/weakest.log")"
grep -q '"break_rule": "weakest_first"' "$work/weakest/summary.json" || fail "summary: no weakest_first"
most=$(tail -n +2 "$work/weakest/broken.csv" | cut -d, -f1,2 | sort | uniq -c | awk '$1 > m { m = $1 } END { print m + 0 }')
[ "$most" -eq 1 ] || fail "weakest_first broke $most bonds in one relaxation cycle"
broken=$(($(wc -l < "$work/weakest/broken.csv") - 1))
[ "$broken" -gt 10 ] || fail "weakest_first broke only $broken bonds"
echo "ok: weakest_first: $broken bonds, one per relaxation cycle"

"$extended" "${args[@]}" -fracture_relaxation counted_global -output_dir "$work/counted" \
  > "$work/counted.log" 2>&1 || fail "counted_global: $(tail -3 "$work/counted.log")"
grep -q "^counted_global: [1-9][0-9]* load steps relaxed" "$work/counted.log" ||
  fail "counted_global did not relax: $(tail -3 "$work/counted.log")"
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
echo "ok: counted_global: $(grep -o '[0-9]* load steps relaxed' "$work/counted.log"), the same ruptures as the global scheme"

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
