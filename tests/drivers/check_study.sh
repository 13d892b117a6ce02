#!/bin/bash
# tools/study.py on bad input: unknown keys, an empty grid, a results folder of
# another study, a run that fails (reported, left out of the table, rerun).
# Usage: check_study.sh BUILD_DIR WORKDIR
source "$(dirname "$0")/study_setup.sh"
expect_error() {  # expect_error PATTERN COMMAND...: exit 1 (bad input), message matching PATTERN
  local pattern="$1" status; shift
  "$@" > "$work/out" 2>&1
  status=$?
  [ "$status" -eq 1 ] || fail "exit $status, expected 1: $* ($(tail -1 "$work/out"))"
  grep -q "$pattern" "$work/out" || fail "message for '$*' lacks '$pattern': $(tail -2 "$work/out")"
  echo "ok: $(grep -m1 "$pattern" "$work/out")"
}
base='name: t
ranks: 1
sample: {sample_particles: 8, lattice_bonds: 6000}
matrix_fractions: [0.13]
sigma_pm_ratios: [0.6]'
printf '%s\nfracture_options: {}\n' "$base" > "$work/typo.yaml"
expect_error "unknown key(s) fracture_options" "${study[@]}" plan "$work/typo.yaml" "$work/a"
sed 's/^sigma_pm_ratios: .*/sigma_pm_ratios: []/' <<< "$base" > "$work/empty.yaml"
expect_error "the grid is empty" "${study[@]}" plan "$work/empty.yaml" "$work/a"
sed 's/^matrix_fractions: .*/matrix_fractions: [0.9]/' <<< "$base" > "$work/range.yaml"
expect_error "matrix_fractions value 0.9 outside" "${study[@]}" plan "$work/range.yaml" "$work/a"
expect_error "cannot read the study file" "${study[@]}" plan "$work/missing.yaml" "$work/a"
sed 's/^ranks: 1/ranks: true/' <<< "$base" > "$work/bool.yaml"
expect_error "ranks must be a positive integer, not True" "${study[@]}" plan "$work/bool.yaml" "$work/a"
printf '%s\nphases: {sigma_p: true}\n' "$base" > "$work/sigma.yaml"
expect_error "phases.sigma_p must be a number > 0, not True" "${study[@]}" plan "$work/sigma.yaml" "$work/a"
printf '%s\n' "$base" > "$work/ok.yaml"
expect_error "ranks 0 is not a positive integer" "${study[@]}" plan "$work/ok.yaml" "$work/a" --ranks 0

# A run that fails: lem_fracture crashes in the runs (not in the calibration).
mkdir -p "$work/bin"
ln -s "$(realpath "$bin")/lem_sample" "$work/bin/lem_sample"
printf '#!/bin/bash\ncase " $* " in *" -phase_sigma_pm "*) echo "Error: injected crash" >&2; exit 3;; esac\nexec %s/lem_fracture "$@"\n' \
  "$(realpath "$bin")" > "$work/bin/lem_fracture"
chmod +x "$work/bin/lem_fracture"
printf '%s\nfracture: {fracture_stop_fraction: 0.7}\n' "$base" > "$work/s.yaml"
"${study[@]}" all "$work/s.yaml" "$work/results" --bin "$work/bin" > "$work/bad.log" 2>&1 &&
  fail "a study with a failing run exited 0"
grep -q "FAILED (exit 3): Error: injected crash" "$work/bad.log" ||
  fail "failed run not reported: $(tail -3 "$work/bad.log")"
grep -q "left out" "$work/bad.log" || fail "gather did not report the missing run"
[ ! -e "$work/results/results.csv" ] || fail "results.csv written with no complete run"
"${study[@]}" status "$work/s.yaml" "$work/results" > "$work/status" 2>&1 && fail "status exit 0"
grep -q "0 complete, 1 failed" "$work/status" || fail "status: $(tail -1 "$work/status")"
echo "ok: failed run reported: $(grep -m1 FAILED "$work/bad.log")"
# Rerunning with a working program completes it; a complete run is skipped.
"${study[@]}" all "$work/s.yaml" "$work/results" --bin "$bin" > "$work/good.log" 2>&1 ||
  fail "the rerun failed: $(tail -3 "$work/good.log")"
[ "$(wc -l < "$work/results/results.csv")" = 2 ] || fail "results.csv should hold one run"
[ ! -e "$work/results/runs/"*/failed.json ] || fail "failed.json left after the rerun"
"${study[@]}" run "$work/s.yaml" "$work/results" --bin "$bin" | grep -q ": complete$" ||
  fail "a complete run was not skipped"
echo "ok: the failed run reran; complete runs are skipped"
# Another study in the same folder is refused.
sed -i 's/fracture_stop_fraction: 0.7/fracture_stop_fraction: 0.6/' "$work/s.yaml"
expect_error "holds the results of a different study" "${study[@]}" plan "$work/s.yaml" "$work/results"
echo "ok: study bad input handled"
