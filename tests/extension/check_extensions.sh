#!/bin/bash
# The example extensions (extended_fracture.cpp) compile, are listed by
# -help, and run: the break rule breaks one bond per relaxation cycle, the
# smallest-threshold critical one; the relaxation scheme, which delegates to
# the global one, breaks the same bonds in the same order as lem_fracture.
# Usage: check_extensions.sh EXTENDED LEM_FRACTURE WORKDIR
set -u
extended="$1"; reference="$2"; work="$3"
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
args=(-lattice_bonds 6000 -lattice_seed 3 -strength_disorder uniform -strength_disorder_width 0.3
      -fracture_stop_fraction 0.3 -output_fields false)
"$extended" -help > "$work/help.log" 2>&1
grep -q "(all|most_critical|weakest_first)" "$work/help.log" &&
  grep -q "(global|local|counted_global)" "$work/help.log" || fail "-help does not list them"

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
"$reference" "${args[@]}" -output_dir "$work/global" > "$work/global.log" 2>&1 ||
  fail "lem_fracture: $(tail -3 "$work/global.log")"
cmp -s "$work/counted/broken.csv" "$work/global/broken.csv" ||
  fail "counted_global broke other bonds than the global scheme"
echo "ok: counted_global: $(grep -o '[0-9]* load steps relaxed' "$work/counted.log"), the same ruptures as the global scheme"
