"""The gather step of a study: one row per complete run in results.csv, the
fits in fit.json, then the figures (study_plots); in a study with a bond
axis or replicates also the convergence tables and figures
(convergence_table)."""
import csv
import os

from . import convergence_table, study_plots
from .analysis import fit_eq10, group_by_rho, k_c_r_eq14, share_without_bare_contacts
from .files import atomic_open, write_json
from .phases import BREAKABLE, broken_column
from .results import STUDY_COLUMNS, read_curve, read_stress_beta, read_summary
from .study_axes import has_axes


def run_row(run, summary, phases, beta):
    """The results.csv row of a complete run from its summary.json."""
    s, ratio = summary, run["sigma_pm_ratio"]
    row = dict(id=run["id"], rho_m=run["rho_m"], sigma_pm_ratio=ratio,
               E_eff_over_E_unit=s["E_eff_over_E_unit"],
               sigma_eff_over_sigma_unit=s["sigma_eff_over_sigma_unit"],
               # eq. 10's left side: both stresses in the units of the phase table.
               sigma_eff_over_sigma_pm=s["sigma_eff"] / (ratio * phases["sigma_p"]),
               strain_at_peak=s["strain_at_peak"], n_b=s["n_b"],
               n_b_without_bare_contacts=share_without_bare_contacts(
                   s["broken_p"], s["broken"], s["broken_pp"]),
               broken=s["broken"])
    row.update({broken_column(p): s[broken_column(p)] for p in BREAKABLE})
    # eq. 13: weakest link; eq. 14: reference medium E_eff.
    row.update(K_c_r_eq13=ratio, K_c_r_eq14=k_c_r_eq14(s["E_eff_over_E_unit"], ratio, phases),
               beta=beta, end_reason=s["end_reason"], solves=s["solves"], seconds=s["seconds"])
    return row


def collect(study, samples=None):
    """Rows of the complete runs, and (id, state) of the others (elastic
    pulls included).  With `samples` (convergence_table.sample_rows by
    sample stem), each row also has the columns of its lattice."""
    rows, missing = [], []
    for run in study.runs() + study.elastic_pulls():
        state = study.state(run)
        if state != "complete":
            missing.append((run["id"], "failed" if state == "failed" else "not complete"))
            continue
        if "contacts" in run:
            continue  # an elastic pull: in samples.csv
        d = study.run_dir(run)
        row = run_row(run, read_summary(os.path.join(d, "summary.json")),
                      study.spec["phases"], read_stress_beta(os.path.join(d, "stress.json")))
        if samples is not None:
            row.update(convergence_table.run_axis_columns(study, run, samples))
            convergence_table.add_shares(row)
        rows.append(row)
    return rows, missing


def write_table(path, rows, columns=STUDY_COLUMNS):
    with atomic_open(path, newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns)
        writer.writeheader()
        for r in rows:
            writer.writerow(r)


def gather(study):
    """Write results.csv, fit.json and figures/ of `study` (a study.Study);
    exit status 1 when a run is left out or none is complete."""
    axes = has_axes(study.spec)
    samples = convergence_table.sample_rows(study) if axes else None
    rows, missing = collect(study, None if samples is None else {s["sample"]: s for s in samples})
    for run_id, state in missing:
        print("gather: %s %s: left out" % (run_id, state))
    if not rows:
        print("gather: no complete run in %s" % study.out)
        return 1
    table = os.path.join(study.out, "results.csv")
    write_table(table, rows, STUDY_COLUMNS + (convergence_table.RUN_AXIS_COLUMNS if axes else ()))
    # The paper's figures and eq. 10: of one lattice if the study has several.
    reference = convergence_table.reference_lattice(study) if axes else None
    shown = [r for r in rows if reference is None or r["lattice"] == reference["tag"]]
    fit = fit_eq10([r["rho_m"] for r in shown], [r["sigma_eff_over_sigma_pm"] for r in shown])
    betas = {"%.4f" % rho: rs[0]["beta"] for rho, rs in group_by_rho(shown).items()}
    record = {"eq10": fit, "beta_by_rho_m": betas, "complete_runs": len(rows),
              "missing_runs": [m[0] for m in missing]}
    if axes:
        record["figures_lattice"] = reference["tag"] if reference else None
    write_json(os.path.join(study.out, "fit.json"), record)
    if shown:
        curves = {r["id"]: read_curve(os.path.join(study.run_dir(r), "curve.csv"))
                  for r in study_plots.damage_curve_picks(shown)}
        study_plots.draw_all(shown, fit, curves, study.spec["phases"],
                             os.path.join(study.out, "figures"))
    print("gather: %d runs -> %s, fit.json, figures/ (eq. 10: %s)"
          % (len(rows), table, "A = %.3f, k = %.2f" % (fit["A"], fit["k"]) if fit
             else "not fitted: needs two matrix fractions"))
    if axes:
        points = convergence_table.write_convergence(study, rows, samples)
        print("gather: %d samples -> samples.csv; %d quantity x grid points -> "
              "convergence.csv, convergence_levels.csv, convergence.md, "
              "figures/convergence_*.png" % (len(samples), len(points)))
    return 1 if missing else 0
