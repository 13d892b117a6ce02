"""The gather step of a study: one row per complete run in results.csv, the
fits in fit.json, then the figures (study_plots); in a study with a bond
axis or replicates also the convergence tables and figures
(convergence_table)."""
import csv
import os

import numpy as np

from . import convergence_table, study_plots
from .analysis import (fit_eq10, k_c_r_eq14, replicate_means, sample_means,
                       share_without_bare_contacts)
from .convergence_table import number, optional_json
from .files import atomic_open, write_json
from .phases import BREAKABLE, broken_column
from .results import (CURVE, STRESS_FIT, STUDY_COLUMNS, SUMMARY, read_curve, read_stress_beta,
                      read_summary)
from .study_data import curve_of
from .study_axes import DEFAULT_SAMPLE_PARTICLES, has_axes, is_number


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


def folder_row(study, run):
    """The row of a run complete in its folder."""
    d = study.run_dir(run)
    return run_row(run, read_summary(os.path.join(d, SUMMARY)), study.spec["phases"],
                   read_stress_beta(os.path.join(d, STRESS_FIT)))


def kept_row(study, run):
    """The row of `run` kept in the study's data folder, with the columns
    of STUDY_COLUMNS (None where the data has none)."""
    row = study.data.row(run["id"])["row"]
    return {c: float("nan") if row.get(c) is None else row[c] for c in STUDY_COLUMNS}


def run_curve(study, run):
    """The curve of a complete run: from its folder, else the thinned one kept
    in the data folder."""
    if study.folder_complete(run):
        return read_curve(os.path.join(study.run_dir(run), CURVE))
    return curve_of(study.data.row(run["id"]))


def collect(study, samples=None):
    """Rows of the complete runs (from their folders, else from the data
    folder), and (id, state) of the others (elastic pulls included).  With
    `samples` (convergence_table.sample_rows by sample stem), each row also
    has the columns of its lattice."""
    rows, missing = [], []
    for run in study.runs() + study.elastic_pulls():
        state = study.state(run)
        if state != "complete":
            missing.append((run["id"], "failed" if state == "failed" else "not complete"))
            continue
        if "contacts" in run:
            continue  # an elastic pull: in samples.csv
        row = folder_row(study, run) if study.folder_complete(run) else kept_row(study, run)
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


def figures_candidates(study, rows, missing):
    """The tags of the lattices the paper's figures may be drawn from: those
    whose fracture runs are all complete, or if none is, those with any
    complete run (`rows`; `missing` as collect returns it)."""
    with_runs = {r["lattice"] for r in rows}
    missing_ids = {run_id for run_id, _ in missing}
    unfinished = {study.lattice_of(run)["tag"] for run in study.runs() if run["id"] in missing_ids}
    return (with_runs - unfinished) or with_runs


def figures_resolution(study, shown, points):
    """What the paper's figures are drawn at (fit.json "figures", their
    subtitle): the samples' particles (sample_particles), bonds M as
    lem_sample counted them (else the study's sample.lattice_bonds, as
    asked), bonds per particle, L_n = M^(-1/3) (means over the samples of
    the runs `shown`) and the least and most runs per grid point."""
    sample = study.spec["sample"]
    stems = sorted({study.sample_stem(study.lattice_of(r), r["rho_m"]) for r in shown})
    bonds = [number(optional_json(os.path.join(study.out, "samples", stem + "_summary.json")),
                    "bonds") for stem in stems]
    bonds, source = [b for b in bonds if b > 0], "samples"   # NaN where not there
    if not bonds and is_number(sample.get("lattice_bonds")):
        bonds, source = [float(sample["lattice_bonds"])], "study file (sample.lattice_bonds)"
    particles = sample.get("sample_particles", DEFAULT_SAMPLE_PARTICLES)
    runs = [p["replicates"] for p in points]
    return {"sample_particles": particles,
            "bonds": float(np.mean(bonds)) if bonds else None,
            "bonds_per_particle": float(np.mean(bonds)) / particles if bonds else None,
            "L_n": float(np.mean(np.power(bonds, -1 / 3))) if bonds else None,
            "bonds_from": source if bonds else None, "runs_per_point": [min(runs), max(runs)]}


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
    # The paper's figures and eq. 10: of one size if the study has several
    # (the finest whose runs are all complete, else the finest with any, so
    # that a gather before the finest runs are done draws a whole grid at a
    # coarser size rather than part of one), the mean over its replicates at
    # each grid point.
    lattices = convergence_table.figures_lattices(study, figures_candidates(study, rows, missing)) \
        if axes else []
    tags = [l["tag"] for l in lattices]
    shown = [r for r in rows if not axes or r["lattice"] in tags]
    points = replicate_means(shown, study_plots.COLUMNS)
    by_rho = sample_means(shown)
    fit = fit_eq10([p["rho_m"] for p in points], [p["sigma_eff_over_sigma_pm"] for p in points])
    record = {"eq10": fit,
              "eq10_fitted_to": "sigma_eff/sigma^pm of the %d grid points of the figures, %s"
              % (len(points), "each the mean over its replicates" if study_plots.replicated(points)
                 else "each a single run"),
              "beta_by_rho_m": {"%.4f" % p["rho_m"]: p["beta"] for p in by_rho},
              "complete_runs": len(rows), "missing_runs": [m[0] for m in missing]}
    if study_plots.replicated(by_rho):
        record["beta_std_by_rho_m"] = {"%.4f" % p["rho_m"]: p["std"]["beta"] for p in by_rho}
    if axes:
        record["figures_lattice"] = tags[0] if tags else None
        record["figures_lattices"] = tags
    resolution = figures_resolution(study, shown, points) if shown else None
    record["figures"] = resolution
    write_json(os.path.join(study.out, "fit.json"), record)
    if shown:
        runs = {run["id"]: run for run in study.runs()}
        curves = {run_id: run_curve(study, runs[run_id])
                  for p in study_plots.damage_curve_picks(points) for run_id in p["runs"]}
        study_plots.draw_all(points, by_rho, fit, curves, study.spec["phases"], resolution,
                             os.path.join(study.out, "figures"))
    print("gather: %d runs -> %s, fit.json, figures/ (eq. 10: %s)"
          % (len(rows), table, "A = %.3f, k = %.2f" % (fit["A"], fit["k"]) if fit
             else "not fitted: needs two matrix fractions"))
    if axes:
        extrapolated = convergence_table.write_convergence(study.out, study.spec, rows, samples)
        print("gather: %d samples -> samples.csv; %d quantity x grid points -> "
              "convergence.csv, convergence_levels.csv, convergence.md, "
              "figures/convergence_*.png" % (len(samples), len(extrapolated)))
    return 1 if missing else 0
