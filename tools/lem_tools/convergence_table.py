"""The convergence part of a study's gather step, for a study with a bond
axis or replicates (study_axes): samples.csv (one row per sample: its
lattice, L_n, calibration and elastic pulls), the extrapolation of every
quantity to L_n -> 0 at every point of the grid (convergence.csv,
convergence_levels.csv, convergence.md; the numbers in convergence.py) and
the figures (convergence_plots)."""
import csv
import math
import os

from .convergence import bonds_of_mesh_density, extrapolate
from .files import atomic_open
from .phases import broken_column
from .results import SUMMARY, ResultsError, read_json
from .study_axes import DEFAULT_SAMPLE_PARTICLES, bond_axis

NAN = float("nan")
RUN_AXIS_COLUMNS = ("lattice", "level", "lattice_bonds", "pack_seed", "lattice_seed", "bonds",
                    "L_n", "share_broken_m", "share_broken_pp", "share_broken_pm")
SAMPLE_COLUMNS = ("sample", "lattice", "level", "lattice_bonds", "pack_seed", "lattice_seed",
                  "rho_m", "rho_m_measured", "rho_v", "nodes", "bonds", "L_n", "E_hom",
                  "sigma_hom", "E_bare_over_E_unit", "nu_bare", "E_adhesive_over_E_unit",
                  "nu_adhesive")
# (column, axis label, heading): per sample (a point is a matrix fraction)
# and per run (a point is a matrix fraction and an adhesion).
SAMPLE_QUANTITIES = (
    ("E_bare_over_E_unit", r"$E_{\rm eff}/E^{[p]}$, bare contacts",
     "E_eff/E^[p], bare contacts (lem_tension, E^pp = 0)"),
    ("E_adhesive_over_E_unit", r"$E_{\rm eff}/E^{[p]}$, adhesive contacts",
     "E_eff/E^[p], adhesive contacts (lem_tension, E^pp = E^pm)"),
    ("nu_bare", r"$\nu$, bare contacts", "ν, bare contacts"),
    ("nu_adhesive", r"$\nu$, adhesive contacts", "ν, adhesive contacts"),
)
RUN_QUANTITIES = (
    ("E_eff_over_E_unit", r"$E_{\rm eff}/E^{[p]}$ at the first step",
     "E_eff/E^[p] at the first step of lem_fracture"),
    ("sigma_eff_over_sigma_unit", r"$\sigma_{\rm eff}/\sigma^{[p]}$", "σ_eff/σ^[p]"),
    ("strain_at_peak", r"$\varepsilon_{zz}$ at the peak", "ε_zz at the peak"),
    ("beta", r"tail exponent $\beta$ of the node stresses", "β, node-stress tail (eq. 2)"),
    ("n_b", r"$n_b$ after failure", "n_b after failure"),
    ("n_b_without_bare_contacts", r"$n_b$ without the bare contacts",
     "n_b without the bare contacts"),
    ("share_broken_m", "share of broken bonds in the matrix",
     "share of the broken bonds in the matrix"),
    ("share_broken_pm", "share of broken bonds at the interfaces",
     "share of the broken bonds at the interfaces (pm)"),
)
LEVEL_COLUMNS = ("quantity", "rho_m", "sigma_pm_ratio", "level", "L_n", "replicates", "mean",
                 "std", "min", "max", "scatter", "error")
POINT_COLUMNS = ("quantity", "rho_m", "sigma_pm_ratio", "levels", "runs", "fit", "extrapolated",
                 "extrapolated_se", "slope", "slope_se", "chi2_reduced", "finest_level",
                 "finest_L_n", "finest_mean", "finest_std", "finest_relative_error", "scatter",
                 "scatter_from_level", "L_n_scatter_dominates", "bonds_scatter_dominates",
                 "bonds_per_particle_scatter_dominates")


def optional_json(path):
    """The JSON object in `path`, or {} if the file is not there (yet)."""
    try:
        return read_json(path)
    except ResultsError:
        return {}


def number(mapping, key):
    value = mapping.get(key)
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) \
        else NAN


def lattice_columns(lattice):
    return {"lattice": lattice["tag"], "level": lattice["level"],
            "lattice_bonds": lattice["sample_options"].get("lattice_bonds", ""),
            "pack_seed": lattice["pack_seed"], "lattice_seed": lattice["lattice_seed"]}


def sample_rows(study):
    """One row per sample of `study` (a study.Study): its lattice, what
    lem_sample measured, the calibration and the elastic pulls (NaN where
    not there yet)."""
    pulls = {(p["lattice"], p["rho_m"], p["contacts"]): p for p in study.elastic_pulls()}
    rows = []
    for sample in study.samples():
        lattice, rho = sample["lattice"], sample["rho_m"]
        made = (optional_json(os.path.join(study.out, "samples", sample["stem"] + "_summary.json"))
                or kept_sample(study, sample["stem"]))
        calibration = study.calibration(lattice) or {}
        bonds = number(made, "bonds")
        row = dict(lattice_columns(lattice), sample=sample["stem"], rho_m=rho,
                   rho_m_measured=number(made, "rho_m"), rho_v=number(made, "rho_v"),
                   nodes=number(made, "nodes"), bonds=bonds,
                   L_n=bonds ** (-1 / 3) if bonds > 0 else NAN,
                   E_hom=number(calibration, "E_hom"), sigma_hom=number(calibration, "sigma_hom"))
        for contacts in ("bare", "adhesive"):
            pull = pulls.get((lattice["tag"], rho, contacts))
            summary = {}
            if pull is not None and study.state(pull) == "complete":
                summary = read_json(os.path.join(study.pull_dir(pull), SUMMARY))
            row["E_%s_over_E_unit" % contacts] = number(summary, "E_eff") / row["E_hom"]
            row["nu_%s" % contacts] = number(summary, "nu")
        rows.append(row)
    return rows


def kept_sample(study, stem):
    """What a row of the data folder keeps of sample `stem` (nodes, bonds,
    rho_m, rho_v), for a sample that was not made here because every run
    on it is kept there; {} when none is."""
    if study.data is None:
        return {}
    for run in study.runs():
        if study.sample_stem(study.lattice_of(run), run["rho_m"]) != stem:
            continue
        if os.path.exists(study.data.run_path(run["id"])):
            return study.data.row(run["id"])["sample"]
    return {}


def run_axis_columns(study, run, samples):
    """What results.csv adds to a run's row in a study with axes: its lattice
    and the sample's bonds and L_n (add_shares adds the rest)."""
    lattice = study.lattice_of(run)
    sample = samples[study.sample_stem(lattice, run["rho_m"])]
    return dict(lattice_columns(lattice), bonds=sample["bonds"], L_n=sample["L_n"])


def add_shares(row):
    """The broken bonds of the matrix, the contacts and the interfaces as
    shares of all the broken bonds (n_b is the particles' share)."""
    for phase in ("m", "pp", "pm"):
        row["share_broken_" + phase] = row[broken_column(phase)] / max(1, row["broken"])
    return row


def write_csv(path, columns, rows):
    with atomic_open(path, newline="") as f:
        writer = csv.DictWriter(f, fieldnames=columns, extrasaction="ignore")
        writer.writeheader()
        for r in rows:
            writer.writerow(r)


def collect_points(run_rows, samples):
    """{(quantity, rho^m, sigma^pm/sigma^p or None): {level: [(L_n, value), ...]}}."""
    points = {}

    def add(quantity, rho, ratio, row):
        value = row[quantity]
        if isinstance(value, (int, float)) and math.isfinite(value):
            by_level = points.setdefault((quantity, rho, ratio), {})
            by_level.setdefault(row["level"], []).append((row["L_n"], value))
    for quantity, *_ in SAMPLE_QUANTITIES:
        for row in samples:
            add(quantity, row["rho_m"], None, row)
    for quantity, *_ in RUN_QUANTITIES:
        for row in run_rows:
            add(quantity, row["rho_m"], row["sigma_pm_ratio"], row)
    return points


def analyse(points):
    """Every point's extrapolation (convergence.extrapolate), keyed as
    collect_points; a level's L_n is the mean of its runs'."""
    out = {}
    for key, by_level in points.items():
        levels = [(sum(l for l, _ in pairs) / len(pairs), [v for _, v in pairs])
                  for pairs in by_level.values()]
        out[key] = extrapolate(levels, list(by_level))
    return out


def level_rows(results):
    rows = []
    for (quantity, rho, ratio), r in results.items():
        for e in r["levels"]:
            rows.append(dict(e, quantity=quantity, rho_m=rho, sigma_pm_ratio=ratio,
                             level=e["label"], replicates=e["n"]))
    return rows


def point_rows(results, particles):
    rows = []
    for (quantity, rho, ratio), r in results.items():
        fit, finest = r["fit"], r["levels"][-1]
        crossing = r["L_n_scatter_dominates"]
        bonds = bonds_of_mesh_density(crossing) if math.isfinite(crossing) else NAN
        value = r["extrapolated"]
        rows.append({
            "quantity": quantity, "rho_m": rho, "sigma_pm_ratio": ratio,
            "levels": len(r["levels"]), "runs": sum(e["n"] for e in r["levels"]),
            "fit": "none" if not fit else "weighted" if fit["weighted"] else "unweighted",
            "extrapolated": value, "extrapolated_se": r["extrapolated_se"],
            "slope": fit["slope"] if fit else NAN, "slope_se": fit["slope_se"] if fit else NAN,
            "chi2_reduced": (fit["chi2"] / fit["dof"] if fit and fit["weighted"] and fit["dof"] > 0
                             else NAN),
            "finest_level": finest["label"], "finest_L_n": finest["L_n"],
            "finest_mean": finest["mean"], "finest_std": finest["std"],
            "finest_relative_error": (finest["mean"] - value) / value if value else NAN,
            "scatter": r["scatter"],
            "scatter_from_level": ("" if r["scatter_from"] is None
                                   else r["levels"][r["scatter_from"]]["label"]),
            "L_n_scatter_dominates": crossing, "bonds_scatter_dominates": bonds,
            "bonds_per_particle_scatter_dominates": bonds / particles})
    return rows


def g(value, digits=4):
    """A number for the markdown table: `digits` significant digits, - for NaN."""
    if value is None or value == "" or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    return "%.*g" % (digits, value)


def level_cell(level):
    """mean ± standard deviation (runs) of one size, or – if it has no run."""
    if level is None:
        return "–"
    if level["n"] == 1:
        return "%s (1)" % g(level["mean"])
    return "%s ± %s (%d)" % (g(level["mean"]), g(level["std"], 2), level["n"])


def crossing_cell(crossing, axis, particles):
    """L_n* and the lattice size it means; 0 when the replicates agree
    exactly, infinite when the fitted line is flat."""
    if crossing == math.inf:
        return "∞ (flat fit)"
    if not (math.isfinite(crossing) and crossing > 0):
        return g(crossing)
    bonds = float("%.2g" % bonds_of_mesh_density(crossing))
    if axis == "lattice_bonds_per_particle":
        return "%s (%d bonds/particle)" % (g(crossing, 3), float("%.2g" % (bonds / particles)))
    return "%s (%d bonds)" % (g(crossing, 3), bonds)


def level_label(level, axis):
    if level is None:
        return "single size"
    return "%g bonds/particle" % level if axis == "lattice_bonds_per_particle" \
        else "%g bonds" % level


def markdown(results, labels, spec, level_l_n, made_by="tools/study.py gather"):
    """convergence.md of the study `spec`: one table per quantity, a row per
    point of the grid, a column per resolution (mean ± standard deviation of
    single runs, and their number), then the extrapolation."""

    axis, levels = bond_axis(spec)
    particles = spec["sample"].get("sample_particles", DEFAULT_SAMPLE_PARTICLES)
    ordered = sorted(levels, key=lambda v: -level_l_n.get(v, 0.0))
    lines = ["# Convergence in L_n: study %s" % spec["name"], "",
             "Made by `%s`. L_n = M^(-1/3), M the lattice's bonds "
             "(columns: its mean over the replicates). Each cell: mean ± standard deviation "
             "of single runs (number of runs). L_n → 0: intercept of the linear fit ± its "
             "standard error. *error*: finest mean minus the extrapolated value, relative. "
             "*scatter ≥ error from*: the coarsest resolution from which on a single run's "
             "scatter is at least its distance to the extrapolated value; L_n\\*: where the "
             "fitted line is one scatter (pooled standard deviation) away from its intercept; "
             "docs/convergence.md." % made_by, ""]
    for quantity, _, heading in labels:
        keys = sorted((k for k in results if k[0] == quantity),
                      key=lambda k: (k[1], -1 if k[2] is None else k[2]))
        if not keys:
            continue
        lines += ["## " + heading, "",
                  "| ρ^m | σ^pm/σ^p | " + " | ".join(
                      "%s (L_n %s)" % (level_label(v, axis), g(level_l_n.get(v), 3))
                      for v in ordered)
                  + " | L_n → 0 | error | scatter ≥ error from | L_n* |",
                  "|---|---|" + "---|" * (len(ordered) + 4)]
        for key in keys:
            r = results[key]
            by_level = {e["label"]: e for e in r["levels"]}
            cells = [level_cell(by_level.get(v)) for v in ordered]
            value = r["extrapolated"]
            finest = r["levels"][-1]
            error = (finest["mean"] - value) / value if value else NAN
            scatter_from = "–" if r["scatter_from"] is None else level_label(
                r["levels"][r["scatter_from"]]["label"], axis)
            crossing_text = crossing_cell(r["L_n_scatter_dominates"], axis, particles)
            lines.append("| %s | %s | %s | %s ± %s | %s | %s | %s |" % (
                g(key[1], 3), "–" if key[2] is None else g(key[2], 3), " | ".join(cells),
                g(value), g(r["extrapolated_se"], 2),
                "–" if not math.isfinite(error) else "%+.1f %%" % (100 * error), scatter_from,
                crossing_text))
        lines.append("")
    return "\n".join(lines)


def reference_lattice(study, complete=None):
    """The lattice that sets where the paper's figures (study_plots) are
    drawn in a study with axes: the first pack and lattice seeds at the
    finest resolution that has fracture runs (figures_lattices adds its
    replicates).  `complete`: the tags of the lattices with complete runs,
    when only those count (a gather before the finest runs are done)."""
    first = study.lattices[0]
    chosen = [l for l in fracture_lattices(study, complete) if l["pack_seed"] == first["pack_seed"]
              and l["lattice_seed"] == first["lattice_seed"]]
    return max(chosen, key=lambda l: l["level"] if l["level"] is not None else 0) \
        if chosen else None


def fracture_lattices(study, complete=None):
    """The lattices of `study` with fracture runs (of those in `complete`,
    if given)."""
    return [l for l in study.lattices if l["fracture"] and (complete is None or l["tag"] in complete)]


def figures_lattices(study, complete=None):
    """The lattices whose runs the paper's figures and the fit of eq. 10 are
    drawn from in a study with axes: reference_lattice first, then its
    replicates (the other seeds at its size), whose mean and standard
    deviation the figures show."""
    reference = reference_lattice(study, complete)
    if reference is None:
        return []
    return [reference] + [l for l in fracture_lattices(study, complete)
                          if l is not reference and l["level"] == reference["level"]]


def write_convergence(out, spec, run_rows, samples, made_by="tools/study.py gather"):
    """samples.csv, convergence*.csv, convergence.md and the convergence
    figures in `out` of the runs and samples of the study `spec`; returns the
    per-point rows (convergence.csv)."""
    from . import convergence_plots

    write_csv(os.path.join(out, "samples.csv"), SAMPLE_COLUMNS, samples)
    results = analyse(collect_points(run_rows, samples))
    particles = spec["sample"].get("sample_particles", DEFAULT_SAMPLE_PARTICLES)
    points = point_rows(results, particles)
    write_csv(os.path.join(out, "convergence_levels.csv"), LEVEL_COLUMNS, level_rows(results))
    write_csv(os.path.join(out, "convergence.csv"), POINT_COLUMNS, points)
    level_l_n = {}
    for s in samples:
        if math.isfinite(s["L_n"]):
            level_l_n.setdefault(s["level"], []).append(s["L_n"])
    level_l_n = {k: sum(v) / len(v) for k, v in level_l_n.items()}
    with atomic_open(os.path.join(out, "convergence.md")) as f:
        f.write(markdown(results, SAMPLE_QUANTITIES + RUN_QUANTITIES, spec, level_l_n, made_by))
    convergence_plots.draw_all(results, SAMPLE_QUANTITIES, RUN_QUANTITIES, level_l_n,
                               spec, particles, os.path.join(out, "figures"))
    return points
