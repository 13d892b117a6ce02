#!/bin/bash
# A real small study kept as data (tools/study.py --data), with its load step
# given as a strain (strain_increment): every step is that strain; every run's row
# is kept; with one row's run folder and row deleted the study runs that row
# alone and gets the same numbers back; in a new output folder ("another
# machine") it builds only the sample of the row it lacks and reuses the kept
# calibration; the paper's figures redraw from the data folder alone.
# Usage: check_study_data.sh BUILD_DIR WORKDIR
source "$(dirname "$0")/study_setup.sh"
cat > "$work/s.yaml" <<'YAML'
name: data
ranks: 1
sample: {sample_particles: 8, lattice_bonds: 6000}
matrix_fractions: [0.13, 0.24]
sigma_pm_ratios: [0.6]
fracture: {fracture_stop_fraction: 0.7}
strain_increment: 3.0e-5
YAML
data="$work/data"
"${study[@]}" all "$work/s.yaml" "$work/here" --data "$data" --bin "$bin" > "$work/first.log" 2>&1 ||
  fail "the study failed: $(tail -3 "$work/first.log")"
row=rho_0.2400_spm_0.6000
[ "$(ls "$data/runs" | wc -l)" = 2 ] || fail "expected 2 kept rows: $(ls "$data/runs")"
cp "$data/runs/$row.json" "$work/kept.json"
# strain_increment: every step of every run is 3e-5 of strain (a / L of its sample)
/usr/bin/python3 - "$work"/here/runs/*/curve.csv <<'PY' || fail "the load step is not the strain_increment"
import csv, sys
for path in sys.argv[1:]:
    rows = list(csv.DictReader(open(path)))
    steps = [float(r["strain"]) / int(r["step"]) for r in rows]
    assert all(abs(s / 3e-5 - 1) < 1e-6 for s in steps), (path, min(steps), max(steps))
print("ok: strain per step 3e-5 in every run (%d runs)" % (len(sys.argv) - 1))
PY
count() { grep -c "^$1 .*: .*$2" "$3"; }

# the same folder: one row deleted, that row alone runs, with the same result
rm -r "$work/here/runs/$row" "$data/runs/$row.json"
"${study[@]}" all "$work/s.yaml" "$work/here" --data "$data" --bin "$bin" > "$work/again.log" 2>&1 ||
  fail "the resumed study failed: $(tail -3 "$work/again.log")"
[ "$(count run lem_fracture "$work/again.log")" = 1 ] || fail "expected one run: $(grep lem_ "$work/again.log")"
grep -q "^run $row: .*lem_fracture" "$work/again.log" || fail "the deleted row did not run"
/usr/bin/python3 - "$work/kept.json" "$data/runs/$row.json" <<'PY' || fail "the rerun row differs"
import json, sys
a, b = (json.load(open(p))["row"] for p in sys.argv[1:])
for k in ("sigma_eff_over_sigma_unit", "strain_at_peak", "n_b", "broken", "E_eff_over_E_unit"):
    assert a[k] == b[k], (k, a[k], b[k])
print("ok: the rerun row has the deleted row's numbers: sigma_eff/sigma^[p] %s, n_b %s"
      % (b["sigma_eff_over_sigma_unit"], b["n_b"]))
PY

# another machine: a new output folder and the data folder less one row
rm "$data/runs/rho_0.1300_spm_0.6000.json"
"${study[@]}" all "$work/s.yaml" "$work/elsewhere" --data "$data" --bin "$bin" > "$work/elsewhere.log" 2>&1 ||
  fail "the study elsewhere failed: $(tail -3 "$work/elsewhere.log")"
[ "$(count run lem_fracture "$work/elsewhere.log")" = 1 ] || fail "elsewhere: expected one run"
[ "$(count sample lem_sample "$work/elsewhere.log")" = 1 ] || fail "elsewhere: expected one sample"
grep -q "^sample rho_0.2400: not needed" "$work/elsewhere.log" || fail "elsewhere: the kept row's sample was built"
[ "$(grep -c '^calibration: .*lem_fracture' "$work/elsewhere.log")" = 0 ] || fail "elsewhere: calibrated again"
echo "ok: elsewhere one sample, no calibration, one run"

# gather there: the row kept only in the data joins the table and the figures
"${study[@]}" gather "$work/s.yaml" "$work/elsewhere" --data "$data" > "$work/gather.log" 2>&1 ||
  fail "gather elsewhere failed: $(tail -3 "$work/gather.log")"
[ "$(wc -l < "$work/elsewhere/results.csv")" = 3 ] || fail "results.csv elsewhere should hold 2 runs"
[ "$(ls "$work/elsewhere/figures/paper"/fig*.png | wc -l)" = 10 ] || fail "gather drew no paper figures"
echo "ok: gather elsewhere: 2 rows, one of them from the data alone"

# the figures from the data folder alone
/usr/bin/python3 "$root/tools/paper_figures.py" "$data" --out "$work/figures" > "$work/figures.log" 2>&1 ||
  fail "paper_figures failed: $(tail -3 "$work/figures.log")"
[ "$(ls "$work/figures"/fig*.png | wc -l)" = 10 ] || fail "expected 10 figures: $(ls "$work/figures")"
echo "ok: $(cat "$work/figures.log")"
