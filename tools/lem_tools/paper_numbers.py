"""The numbers the paper pages (docs/paper*.md) quote from the kept studies,
computed from their rows (docs/data/<study>/), and the table of the
516-particle line, written from its rows.

    tools/paper_numbers.py            every number, by name, as the pages may quote it
    tools/paper_numbers.py --write    rewrite the generated tables of the pages
    tools/paper_numbers.py --check    exit 1 where a generated table differs from the data

tests/python/test_paper_numbers.py finds each named number on the pages at
the digits they quote, and fails when a page and its data differ.

The studies read: the 64-particle grid (paper-64 and paper-64-packings), the
516-particle line at sigma^pm = sigma^p (paper-516-line) and the paper-size
runs at the paper's increment (increment-516-x1).  Two derivations also use
values of docs/convergence.md (paper.CONVERGED_MODULI, paper.STRENGTH_516;
kept as docs/data/convergence-*.csv, which tests/python/test_convergence_data.py
holds them to): eq. 14 with the moduli at L_n -> 0, and k of eq. 10 against
the resolution.  The resolution matched to the paper's measures comes from
lem_tools.convergence_data.
"""
import os
import sys

import numpy as np

from . import cli, convergence_data
from .analysis import (converged_modulus, crossing, eq10_abscissa, eq10_residuals, fit_eq10,
                       eq14_frontier, group_by_rho, k_c_r_eq14, replicate_means,
                       sample_means)
from .convergence import fit_line
from .errors import ToolError
from .paper import CONVERGED_FIRST_STEP_MODULI, CONVERGED_MODULI, STRENGTH_516
from .paper_figures import read_folders
from .study_data import curve_of
from .study_plots import COLUMNS

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "docs", "data")
GRID = ("paper-64", "paper-64-packings")
LINE = ("paper-516-line",)
GRID_516 = ("paper-516-grid",)
COATING = ("coating-64",)
COATING_516 = ("coating-516",)
FIG3 = ("fig3-64",)
FIG3_PP = ("fig3-pp-64",)
INCREMENT = "increment-516-x1"
POINT_COLUMNS = COLUMNS + ("n_b_without_bare_contacts", "broken_p", "strain_at_peak")
NB_LEVEL = 0.01        # the n_b whose crossing is fig. 16's threshold
FALL = 0.1             # a fall: the stress drops by more than this share of the peak in a step
OUR_FILL = 0.357       # rho^m where our bridge protocol fills the pores (model/cemented-samples.md)
STRAIN_CAP = "strain beyond"          # the start of the end_reason of the strain cap
# The pages with generated blocks, each between a begin and an end comment.
PAGES = {"line": os.path.join(ROOT, "docs", "paper-grid.md"),
         "analysis": os.path.join(ROOT, "docs", "paper-analysis.md")}
BEGIN = "<!-- begin: %s; tools/paper_numbers.py --write rewrites it from docs/data -->"
END = "<!-- end: %s -->"


def tag(value):
    """A grid coordinate as a name part: 0.06 -> 006, 1.4 -> 140."""
    return "%03d" % round(value * 100)


class Study:
    """The kept rows of data folders read as one study: `phases`, `rows`,
    `kept` (paper_figures.read_folders), `points` (grid points, means over
    the packings) and `samples` (one per rho^m: first-step modulus, beta)."""

    def __init__(self, names, data=DATA):
        spec, self.rows, self.kept = read_folders([os.path.join(data, n) for n in names])
        self.phases = spec["phases"]
        self.points = replicate_means(self.rows, POINT_COLUMNS)
        self.samples = sample_means(self.rows)

    def find(self, rho, ratio):
        """The grid point (rho^m, sigma^pm / sigma^p), or None if not kept."""
        found = [p for p in self.points
                 if abs(p["rho_m"] - rho) < 1e-9 and abs(p["sigma_pm_ratio"] - ratio) < 1e-9]
        return found[0] if found else None

    def point(self, rho, ratio):
        found = self.find(rho, ratio)
        if found is None:
            raise ToolError("no kept point at rho^m = %g, sigma^pm/sigma^p = %g" % (rho, ratio))
        return found

    def between(self, rho, ratio):
        """The point (rho^m, sigma^pm / sigma^p), linear in sigma^pm between
        its two neighbours where the grid has none (0.6 between 0.5 and
        0.65), the standard deviations too."""
        found = self.find(rho, ratio)
        if found:
            return found
        row = sorted((q for q in self.points if abs(q["rho_m"] - rho) < 1e-9),
                     key=lambda q: q["sigma_pm_ratio"])
        lo = [q for q in row if q["sigma_pm_ratio"] < ratio][-1]
        hi = [q for q in row if q["sigma_pm_ratio"] > ratio][0]
        w = (ratio - lo["sigma_pm_ratio"]) / (hi["sigma_pm_ratio"] - lo["sigma_pm_ratio"])
        mixed = {"std": {}, "replicates": min(lo["replicates"], hi["replicates"])}
        for column in POINT_COLUMNS:
            mixed[column] = (1 - w) * lo[column] + w * hi[column]
            mixed["std"][column] = (1 - w) * lo["std"][column] + w * hi["std"][column]
        return mixed

    def sample(self, rho):
        (found,) = [s for s in self.samples if abs(s["rho_m"] - rho) < 1e-9]
        return found


# ---------------------------------------------------------------- the derivations
def modulus_line(samples, start=0.0):
    """(intercept, slope) of E_eff/E^[p] against rho^m through the samples
    from rho^m = `start` up: fig. 5's dotted line (least squares)."""
    chosen = [s for s in samples if s["rho_m"] >= start - 1e-9]
    line = fit_line([s["rho_m"] for s in chosen], [s["E_eff_over_E_unit"] for s in chosen])
    return line["intercept"], line["slope"]


def strength_over_adhesion(points):
    """(rho, sigma_eff/sigma^[p] / (sigma^pm/sigma^p)) of the points: eq. 10's
    left side with both stresses in units of the homogeneous lattice's
    strength sigma^[p], the bond threshold sigma^pm as the lattice turns
    sigma^p into sigma^[p]."""
    return ([p["rho_m"] for p in points],
            [p["sigma_eff_over_sigma_unit"] / p["sigma_pm_ratio"] for p in points])


def eq10_in_lattice_units(points):
    """Eq. 10 fitted to sigma_eff/sigma^pm in sigma^[p] units
    (strength_over_adhesion), with the standard errors of A and k."""
    return fit_eq10(*strength_over_adhesion(points), errors=True)


def low_point_gap(rho, strength):
    """The relative gap of the lowest rho^m's strength (mean of its points)
    from eq. 10 fitted to the other matrix fractions: negative below."""
    rho, strength = np.asarray(rho, dtype=float), np.asarray(strength, dtype=float)
    low = rho.min()
    fit = fit_eq10(rho[rho > low], strength[rho > low])
    return eq10_residuals(rho, strength, fit)[float(low)], fit


def onsets(points, column="broken_p"):
    """{rho^m: the lowest sigma^pm/sigma^p at which `column` > 0}: with
    point means, where any of the point's runs broke a particle bond."""
    return {rho: min((p["sigma_pm_ratio"] for p in ps if p[column] > 0), default=None)
            for rho, ps in group_by_rho(points).items()}


def k_c_r_converged(point, phases, moduli=CONVERGED_MODULI):
    """K_c^r of eq. 14 at a grid point with E_eff at L_n -> 0 (`moduli`,
    linear in rho^m between the measured fractions); None outside them."""
    e = converged_modulus(point["rho_m"], moduli)
    return None if e is None else k_c_r_eq14(e, point["sigma_pm_ratio"], phases)


def eq14_thresholds(study, column="n_b", level=NB_LEVEL, moduli=CONVERGED_MODULI):
    """{rho^m: (K_c^r of eq. 14 where `column` first reaches `level` with the
    sample's own E_eff, the same with E_eff at L_n -> 0)}, linear between
    the grid points.  K_c^r grows as the square root of E_eff, so the second
    is the first times sqrt(E_converged / E_sample)."""
    out = {}
    for rho, ps in group_by_rho(study.points).items():
        own = crossing([p["K_c_r_eq14"] for p in ps], [p[column] for p in ps], level)
        converged = [k_c_r_converged(p, study.phases, moduli) for p in ps]
        out[rho] = (own, None if own is None or None in converged else
                    crossing(converged, [p[column] for p in ps], level))
    return out


def k_against_resolution(strength=STRENGTH_516):
    """{bonds per particle (0: L_n -> 0): eq. 10 fitted to sigma_eff/sigma^[p]
    of one 516-particle sample at sigma^pm = sigma^p} (paper.STRENGTH_516)."""
    return {bpp: fit_eq10(sorted(values), [values[r] for r in sorted(values)])
            for bpp, values in strength.items()}


def falls(curve, share=FALL):
    """The steps after the peak whose stress falls by more than `share` of
    the peak: (before, after) in sigma^[p], the bonds broken since the
    previous kept row and the load steps that covers (1: the bonds of that
    step alone; a step's strain is the smallest strain between kept rows),
    the strain in units of the peak strain."""
    before, after, strain = curve["stress_before_norm"], curve["stress_norm"], curve["strain"]
    peak = int(np.argmax(before))
    # the strain of one load step: the smallest step between kept rows
    gaps = np.diff(np.concatenate([[0.0], strain]))
    increment = gaps[gaps > 0].min()
    out = []
    for i in range(max(peak, 1), len(before)):
        if before[i] - after[i] > share * before[peak]:
            out.append({"before": float(before[i]), "after": float(after[i]),
                        "bonds": int(curve["broken"][i] - curve["broken"][i - 1]),
                        "steps": int(round((strain[i] - strain[i - 1]) / increment)),
                        "strain_ratio": float(strain[i] / strain[peak])})
    return out


def run_end(curve):
    """(stress at the run's end / the peak, strain at the end / the peak strain)."""
    peak = int(np.argmax(curve["stress_before_norm"]))
    return (float(curve["stress_norm"][-1] / curve["stress_before_norm"][peak]),
            float(curve["strain"][-1] / curve["strain"][peak]))


def strain_cap(study):
    """The runs that stopped at the strain cap (-fracture_max_strain_ratio)
    before falling to the stop fraction: their ids and the stress at their
    end as a share of the peak."""
    capped = [r for r in study.rows if r["end_reason"].startswith(STRAIN_CAP)]
    return [(r["id"], run_end(curve_of(study.kept[r["id"]]))[0]) for r in capped]


def paper_a_in_lattice_units(strength=(1.0, 1.05), ratio=1.4, rho=0.28, k=2.5):
    """A of eq. 10 in sigma^[p] units that the paper's own statements imply:
    at rho^m = 0.28 (pores filled) and sigma^pm = 1.4 sigma^p its strength is
    "slightly above sigma^[p]" (sect. 5, taken as `strength` in sigma^[p]),
    with its k = 2.5; one A per strength."""
    return [s / ratio / float(eq10_abscissa(rho, k)) for s in strength]


def fixed_k_a(points, k):
    """A of eq. 10 in sigma^[p] units with k held at `k` (least squares)."""
    rho, y = strength_over_adhesion(points)
    x = eq10_abscissa(rho, k)
    return float(np.sum(x * y) / np.sum(x * x))


def onset_k(study, moduli=CONVERGED_MODULI):
    """{rho^m: (K_c^r of eq. 14 with the sample's E_eff, with E_eff at
    L_n -> 0)} at the first sigma^pm where the first packing's run breaks a
    particle bond (onsets of the paper-64 rows: one run per point, so that a
    single bond in one of three packings does not set the onset)."""
    first = replicate_means([r for r in study.rows if r["study"] == GRID[0]],
                            ("broken_p", "K_c_r_eq14"))
    out = {}
    for rho, ratio in onsets(first).items():
        (p,) = [p for p in first if p["rho_m"] == rho and p["sigma_pm_ratio"] == ratio]
        out[rho] = (p["K_c_r_eq14"], k_c_r_converged(p, study.phases, moduli))
    return out


def onset_steps(study, moduli=CONVERGED_MODULI):
    """{rho^m: the K_c^r (E_eff at L_n -> 0) between the last grid point
    without a broken particle bond and the first with one}: how finely the
    grid brackets the onset."""
    out = {}
    for rho, (_, k) in onset_k(study, moduli).items():
        below = [k_c_r_converged(p, study.phases, moduli) for p in study.points
                 if p["rho_m"] == rho and k_c_r_converged(p, study.phases, moduli) < k - 1e-12]
        out[rho] = k - max(below)
    return out


# ---------------------------------------------------------------- the page's tables
def thousands(n):
    return "{:,}".format(int(n)).replace(",", " ")


def strain_text(value):
    return "%.2f·10⁻³" % (value * 1e3)


def fall_text(f):
    bonds = thousands(f["bonds"]) + ("" if f["steps"] == 1 else " over %d steps" % f["steps"])
    return "%.3f → %.3f (%s) at %.2f" % (f["before"], f["after"], bonds, f["strain_ratio"])


def line_table(study):
    """The markdown table of the 516-particle line, one row per run."""
    lines = ["| ρ^m | σ_eff/σ^[p] | ε_zz at the peak | falls of more than %d %% of the peak in "
             "one step: σ^[p] before → after (bonds broken) at × the peak strain | end: stress "
             "/ peak at × the peak strain | n_b | n_b without bare contacts |" % (FALL * 100),
             "|---|---|---|---|---|---|---|"]
    for r in sorted(study.rows, key=lambda r: r["rho_m"]):
        curve = curve_of(study.kept[r["id"]])
        stress, strain = run_end(curve)
        lines.append("| %g | %.3f | %s | %s | %.2f at %.2f | %.3f | %.3f |" % (
            r["rho_m"], r["sigma_eff_over_sigma_unit"], strain_text(r["strain_at_peak"]),
            "; ".join(fall_text(f) for f in falls(curve)) or "–", stress, strain, r["n_b"],
            r["n_b_without_bare_contacts"]))
    return "\n".join(lines)


def grid_516_table(grid_516, grid):
    """The markdown table of the 516-particle grid beside the 64-particle
    one, one row per point of the study file (pending: not yet run)."""
    rhos, ratios = (0.06, 0.13, 0.28), (0.2, 0.6, 1.4)

    def mean_sd(q, column, digits, scale=1.0):
        """The mean ± the standard deviation over the packings (one packing:
        the value alone)."""
        if q["replicates"] == 1:
            return "%.*f" % (digits, q[column] * scale)
        return "%.*f ± %.*f" % (digits, q[column] * scale, digits, q["std"][column] * scale)
    lines = ["| ρ^m | σ^pm/σ^p | σ_eff/σ^[p]: 516 p | 64 p | ε_zz at the peak: 516 p | 64 p "
             "| n_b: 516 p | 64 p | n_b without bare contacts: 516 p | 64 p | solves (516 p) |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for rho in rhos:
        for ratio in ratios:
            big, small = grid_516.find(rho, ratio), grid.between(rho, ratio)
            cells = ["%.3f" % big["sigma_eff_over_sigma_unit"] if big else "pending",
                     mean_sd(small, "sigma_eff_over_sigma_unit", 3),
                     strain_text(big["strain_at_peak"]) if big else "–",
                     ("(%s)·10⁻³" if small["replicates"] > 1 else "%s·10⁻³")
                     % mean_sd(small, "strain_at_peak", 2, 1e3),
                     "%.3f" % big["n_b"] if big else "–", mean_sd(small, "n_b", 3),
                     "%.3f" % big["n_b_without_bare_contacts"] if big else "–",
                     mean_sd(small, "n_b_without_bare_contacts", 3)]
            run = [r for r in grid_516.rows if big and r["id"] in big["runs"]]
            cells.append(thousands(run[0]["solves"]) if run else "–")
            lines.append("| %g | %g | %s |" % (rho, ratio, " | ".join(cells)))
    return "\n".join(lines)


def eq14_table(grid):
    """The markdown table of eq. 14's thresholds (eq14_thresholds), per rho^m."""
    columns = [eq14_thresholds(grid, "n_b"), eq14_thresholds(grid, "n_b"),
               eq14_thresholds(grid, "n_b", moduli=CONVERGED_FIRST_STEP_MODULI),
               eq14_thresholds(grid, "n_b_without_bare_contacts"),
               eq14_thresholds(grid, "n_b_without_bare_contacts")]
    which = [0, 1, 1, 0, 1]    # the sample's E_eff, or E_eff at L_n -> 0

    def cell(value):
        return "–" if value is None else "%.2f" % value
    lines = ["| ρ^m | with the grid's E_eff | with E_eff at L_n → 0 | with the first-step moduli "
             "at L_n → 0 | without the bare contacts: grid's E_eff | without the bare "
             "contacts: at L_n → 0 |", "|---|---|---|---|---|---|"]
    for rho in sorted(columns[0]):
        lines.append("| %g | %s |" % (rho, " | ".join(cell(c[rho][w])
                                                      for c, w in zip(columns, which))))
    return "\n".join(lines)


def k_table(grid, line, strength=STRENGTH_516):
    """The markdown table of k of eq. 10 through rho^m = 0.06, 0.13, 0.28 at
    sigma^pm ~ sigma^p, by sample and resolution: the kept grid and line,
    and the 516-particle sample of paper.STRENGTH_516."""
    three = (0.06, 0.13, 0.28)

    def k_of(points):
        return fit_eq10(*strength_over_adhesion([p for p in points if p["rho_m"] in three]))["k"]
    near = [p for p in grid.points if abs(p["sigma_pm_ratio"] - 0.95) < 1e-9]
    fits = k_against_resolution(strength)
    size = resolution_of(grid, "g")
    rows = [("%d p, the grid at 0.95 σ^p" % size["g_particles"], thousands(round(size["g_bpp"])),
             k_of(near), "kept rows")]
    for bpp in sorted(b for b in fits if b):
        rows.append(("516 p, pack seed 1", thousands(bpp), fits[bpp]["k"],
                     "`STRENGTH_516` (convergence.md)"))
    rows.append(("516 p, the line", thousands(round(resolution_of(line, "l")["l_bpp"])),
                 k_of(line.points), "kept rows"))
    rows.sort(key=lambda r: (int(r[1].replace(" ", "")), r[3] != "kept rows"))
    rows.append(("516 p, pack seed 1, lines in L_n at L_n → 0", "–", fits[0]["k"],
                 "`STRENGTH_516` (the ρ^m = 0.06 value a lower bound)"))
    lines = ["| sample | bonds per particle | k | from |", "|---|---|---|---|"]
    lines += ["| %s | %s | %.2f | %s |" % r for r in rows]
    return "\n".join(lines)


def blocks(data=DATA):
    """{block name: (page, generated text)}."""
    grid, line = Study(GRID, data), Study(LINE, data)
    return {"line": (PAGES["line"], line_table(line)),
            "grid516": (PAGES["line"], grid_516_table(Study(GRID_516, data), grid)),
            "eq14": (PAGES["analysis"], eq14_table(grid)),
            "k": (PAGES["analysis"], k_table(grid, line)),
            "resolution": (PAGES["analysis"], convergence_data.resolution_table())}


def replace_block(text, name, content):
    begin, end = BEGIN % name, END % name
    if begin not in text or end not in text:
        raise ToolError("no block %r (%s ... %s)" % (name, begin, end))
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    return head + begin + "\n" + content + "\n" + end + tail


# ---------------------------------------------------------------- every number
def grid_numbers(grid):
    """The 64-particle grid's numbers, by name."""
    out = {"grid_runs": len(grid.rows), "grid_points": len(grid.points)}
    out.update(resolution_of(grid, "grid"))
    out["grid_replicated"] = sum(p["replicates"] > 1 for p in grid.points)
    out["grid_single"] = sum(p["replicates"] == 1 for p in grid.points)
    out["packings_runs"] = sum(r["study"] == "paper-64-packings" for r in grid.rows)
    out["grid_strength_unit"] = strength_unit(grid)
    out["grid_stop_fraction"] = stopping(grid)[0]
    out["grid_strain_cap"] = stopping(grid)[1]
    capped = strain_cap(grid)
    out.update(grid_capped=len(capped), grid_capped_end_min=min(e for _, e in capped),
               grid_capped_end_max=max(e for _, e in capped))
    ended = [run_end(curve_of(grid.kept[r["id"]]))[0] for r in grid.rows
             if not r["end_reason"].startswith(STRAIN_CAP)]
    out.update(grid_stopped=len(ended))
    seconds = sorted(r["seconds"] for r in grid.rows if r["study"] == "paper-64")
    out.update(grid_hours=sum(seconds) / 3600, grid_run_min_s=seconds[0],
               grid_run_max_min=seconds[-2] / 60, grid_run_longest_min=seconds[-1] / 60,
               packings_hours=sum(r["seconds"] for r in grid.rows
                                  if r["study"] == "paper-64-packings") / 3600)
    intercept, slope = modulus_line(grid.samples)
    out.update(fig05_intercept=intercept, fig05_slope=slope)
    for s in grid.samples:
        t = tag(s["rho_m"])
        out["beta_%s" % t], out["beta_sd_%s" % t] = s["beta"], s["std"]["beta"]
        out["E_%s" % t] = s["E_eff_over_E_unit"]
        out["E_m_%s" % t] = 3 * s["E_eff_over_E_unit"]   # in E^[m] = E^[p] / 3
        out["E_m_sd_%s" % t] = 3 * s["std"]["E_eff_over_E_unit"]
    ratio = grid.phases.get("E_m", 1.0) / grid.phases.get("E_p", 3.0)
    out["E_m_028"] = grid.sample(0.28)["E_eff_over_E_unit"] / ratio
    out["E_m_sd_028"] = grid.sample(0.28)["std"]["E_eff_over_E_unit"] / ratio
    for p in grid.points:
        t = "%s_%s" % (tag(p["rho_m"]), tag(p["sigma_pm_ratio"]))
        for column, name in (("sigma_eff_over_sigma_unit", "sigma"), ("n_b", "nb"),
                             ("n_b_without_bare_contacts", "nbw")):
            out["%s_%s" % (name, t)] = p[column]
            out["%s_sd_%s" % (name, t)] = p["std"][column]
    near = [r["strain_at_peak"] for r in grid.rows if abs(r["sigma_pm_ratio"] - 0.95) < 1e-9]
    out.update(fig03_peak_min=min(near), fig03_peak_max=max(near))
    high = [r["strain_at_peak"] for r in grid.rows if r["sigma_pm_ratio"] >= 0.8 - 1e-9]
    low = [r["strain_at_peak"] for r in grid.rows if abs(r["sigma_pm_ratio"] - 0.2) < 1e-9]
    out.update(peak_high_min=min(high), peak_high_max=max(high), peak_low_min=min(low),
               peak_low_max=max(low))
    interface = {}
    for r in grid.rows:
        interface[(r["lattice"], r["rho_m"])] = grid.kept[r["id"]]["sample"][
            "interface_ratio_Spm_Sp"]
    for rho in sorted({k[1] for k in interface}):
        out["Spm_%s" % tag(rho)] = float(np.mean([v for k, v in interface.items() if k[1] == rho]))
    # eq. 10, as fig. 12 fits it (sigma_eff / sigma^pm in the phases' units)
    rho = [p["rho_m"] for p in grid.points]
    strength = [p["sigma_eff_over_sigma_pm"] for p in grid.points]
    fit = fit_eq10(rho, strength)
    out.update(eq10_k=fit["k"], eq10_A=fit["A"], eq10_rms=fit["rms_relative_residual"])
    residuals = eq10_residuals(rho, strength, fit)
    out["eq10_low"] = residuals[0.06]
    others = [v for r, v in residuals.items() if r > 0.06]
    out.update(eq10_others_min=min(others), eq10_others_max=max(others))
    ours = fit_eq10(rho, strength, rho_filled=OUR_FILL)
    out.update(eq10_fill_k=ours["k"], eq10_fill_A=ours["A"])
    lattice = eq10_in_lattice_units(grid.points)
    out.update(eq10_lattice_A=lattice["A"], eq10_lattice_k=lattice["k"],
               eq10_lattice_A_se=lattice["A_se"], eq10_lattice_k_se=lattice["k_se"])
    near = [p for p in grid.points if abs(p["sigma_pm_ratio"] - 0.95) < 1e-9]
    fit95 = fit_eq10([p["rho_m"] for p in near], [p["sigma_eff_over_sigma_pm"] for p in near],
                     errors=True)
    out.update(eq10_095_k=fit95["k"], eq10_095_k_se=fit95["k_se"], eq10_095_A=fit95["A"])
    lattice95 = eq10_in_lattice_units(near)
    out.update(eq10_095_lattice_A=lattice95["A"])
    out["eq10_095_low"], _ = low_point_gap([p["rho_m"] for p in near],
                                           [p["sigma_eff_over_sigma_pm"] for p in near])
    three = [p for p in near if p["rho_m"] in (0.06, 0.13, 0.28)]
    out["k_064_1250_three"] = fit_eq10(*strength_over_adhesion(three))["k"]
    for rho, ratio in onsets(grid.points).items():
        out["onset_%s" % tag(rho)] = ratio
    first = [r for r in grid.rows if r["study"] == "paper-64"]
    for rho, ratio in onsets(replicate_means(first, ("broken_p",))).items():
        out["onset_first_%s" % tag(rho)] = ratio
    low = [r for r in grid.rows if abs(r["sigma_pm_ratio"] - 0.2) < 1e-9 and r["broken_p"] > 0]
    out.update(onset_low_runs=len(low), onset_low_bonds=sum(r["broken_p"] for r in low),
               onset_low_nb=max((r["n_b"] for r in low), default=0.0))
    for column, name in (("n_b", "nb"), ("n_b_without_bare_contacts", "nbw")):
        for rho, (own, converged) in eq14_thresholds(grid, column).items():
            out["k14_%s_%s" % (name, tag(rho))] = own
            out["k14c_%s_%s" % (name, tag(rho))] = converged
        for rho, (_, check) in eq14_thresholds(grid, column,
                                               moduli=CONVERGED_FIRST_STEP_MODULI).items():
            out["k14f_%s_%s" % (name, tag(rho))] = check
    for rho in CONVERGED_MODULI:
        out["E_factor_%s" % tag(rho)] = CONVERGED_MODULI[rho] / grid.sample(rho)["E_eff_over_E_unit"]
        out["E_conv_%s" % tag(rho)] = CONVERGED_MODULI[rho]
        out["E_conv_m_%s" % tag(rho)] = 3 * CONVERGED_MODULI[rho]
        out["E_first_%s" % tag(rho)] = CONVERGED_FIRST_STEP_MODULI[rho]
    for name in ("k14_nb", "k14c_nb", "k14c_nbw"):
        values = [v for k, v in out.items() if k.startswith(name + "_")]
        out.update({name + "_min": min(values), name + "_max": max(values)})
    out["paper_low_gap"] = 1 - 0.2 / 0.3      # the paper's slope 0.2 against its A = 0.3
    first = [r for r in grid.rows if r["study"] == GRID[0]]
    low = min(first, key=lambda r: (r["rho_m"], r["sigma_pm_ratio"]))
    out["beta_first_006"] = low["beta"]
    (r013,) = [r for r in first if r["rho_m"] == 0.13 and r["sigma_pm_ratio"] == 0.2]
    edges = grid.kept[r013["id"]]["stress_pdf"]["edges"]
    out.update(pdf_min_013=edges[0], pdf_max_013=edges[-1])
    out["onset_low_k_conv"] = k_c_r_converged(grid.point(0.28, 0.2), grid.phases)
    for rho in CONVERGED_MODULI:
        out["eq14c_frontier_%s" % tag(rho)] = eq14_frontier(CONVERGED_MODULI[rho], grid.phases)
    onset = onset_k(grid)
    out.update(onset_k_own_min=min(k for k, _ in onset.values()),
               onset_k_own_max=max(k for k, _ in onset.values()),
               onset_k_conv_min=min(k for _, k in onset.values()),
               onset_k_conv_max=max(k for _, k in onset.values()))
    intercept, slope = modulus_line(grid.samples, start=0.1)
    out["grid_E_gap_006"] = grid.sample(0.06)["E_eff_over_E_unit"] / (intercept + 0.06 * slope) - 1
    out["grid_fixed_k_A"] = fixed_k_a(grid.points, 2.5)
    low, high = paper_a_in_lattice_units()
    out.update(paper_A_low=low, paper_A_high=high,
               paper_abscissa_028=float(eq10_abscissa(0.28, 2.5)))
    steps = onset_steps(grid).values()
    out.update(onset_step_min=min(steps), onset_step_max=max(steps))
    for rho in (0.06, 0.13, 0.28):
        t = tag(rho)
        out["sigma_pm1_%s" % t] = grid.point(rho, 0.95)["sigma_eff_over_sigma_unit"] / 0.95
    ratios = [p["n_b_without_bare_contacts"] / p["n_b"] for p in grid.points if p["n_b"] > 0]
    out.update(nb_ratio_min=min(ratios), nb_ratio_max=max(ratios))
    return out


def resolution_of(study, name):
    """Particles, bonds, bonds per particle and L_n of a study's samples
    (means over them, as the figures' subtitle has them)."""
    samples = {(r["lattice"], r["rho_m"]): study.kept[r["id"]]["sample"] for r in study.rows}
    bonds = np.array([s["bonds"] for s in samples.values()], dtype=float)
    particles = min(s["sample_particles"] for s in samples.values())
    return {name + "_particles": particles, name + "_bonds": float(bonds.mean()),
            name + "_bpp": float(bonds.mean()) / particles,
            name + "_L_n": float(np.mean(bonds ** (-1 / 3)))}


def strength_unit(study):
    """sigma^[p] / sigma^p: the homogeneous lattice's strength over its bond
    threshold (the same for every row of the study, else an error)."""
    found = {round(d["calibration"]["sigma_hom"] / study.phases["sigma_p"], 6)
             for d in study.kept.values()}
    if len(found) != 1:
        raise ToolError("the rows have several calibrations: %s" % sorted(found))
    return found.pop()


def stopping(study):
    """(-fracture_stop_fraction, -fracture_max_strain_ratio) the rows ran with."""
    found = set()
    for d in study.kept.values():
        options = d["options"]
        found.add(tuple(float(options[options.index(o) + 1])
                        for o in ("-fracture_stop_fraction", "-fracture_max_strain_ratio")))
    if len(found) != 1:
        raise ToolError("the rows ran with several stop rules: %s" % sorted(found))
    return found.pop()


def line_numbers(line):
    """The 516-particle line's numbers, by name."""
    out = {"line_runs": len(line.rows)}
    out.update(resolution_of(line, "line"))
    out["line_stop_fraction"], out["line_strain_cap"] = stopping(line)
    out["line_capped"] = len(strain_cap(line))
    for s in line.samples:
        t = tag(s["rho_m"])
        out["line_E_%s" % t], out["line_beta_%s" % t] = s["E_eff_over_E_unit"], s["beta"]
    intercept, slope = modulus_line(line.samples, start=0.1)
    out["line_E_slope"] = slope
    gaps = [s["E_eff_over_E_unit"] / (intercept + slope * s["rho_m"]) - 1 for s in line.samples]
    out["line_E_gap_max"] = max(abs(g) for s, g in zip(line.samples, gaps) if s["rho_m"] >= 0.1)
    out["line_E_gap_006"] = gaps[0]
    for r in line.rows:
        t = tag(r["rho_m"])
        out["line_nb_%s" % t], out["line_nbw_%s" % t] = r["n_b"], r["n_b_without_bare_contacts"]
        out["line_sigma_%s" % t] = r["sigma_eff_over_sigma_unit"]
        out["line_strength_pm_%s" % t] = r["sigma_eff_over_sigma_pm"]
        out["line_broken_%s" % t], out["line_broken_p_%s" % t] = r["broken"], r["broken_p"]
        out["line_broken_pp_%s" % t] = r["broken_pp"]
    seconds = [r["seconds"] for r in line.rows]
    out.update(line_run_min_min=min(seconds) / 60, line_run_max_h=max(seconds) / 3600)
    rho = [p["rho_m"] for p in line.points]
    strength = [p["sigma_eff_over_sigma_pm"] for p in line.points]
    fit = fit_eq10(rho, strength, errors=True)
    out.update(line_k=fit["k"], line_k_se=fit["k_se"], line_A=fit["A"],
               line_rms=fit["rms_relative_residual"])
    gap, others = low_point_gap(rho, strength)
    out.update(line_low_gap=gap, line_low_line=others["A"] * float(eq10_abscissa(min(rho),
                                                                                 others["k"])))
    without = fit_eq10(rho[1:], strength[1:], errors=True)
    out.update(line_k_without_006=without["k"], line_k_se_without_006=without["k_se"],
               line_A_without_006=without["A"])
    lattice = eq10_in_lattice_units(line.points)
    out.update(line_lattice_A=lattice["A"], line_lattice_k=lattice["k"])
    three = [p for p in line.points if p["rho_m"] in (0.06, 0.13, 0.28)]
    out["k_516_2520_three"] = fit_eq10(*strength_over_adhesion(three))["k"]
    out["line_fixed_k_A"] = fixed_k_a(line.points, 2.5)
    shares = [r["broken_pp"] / r["broken"] for r in line.rows]
    out.update(line_bare_share_min=min(shares), line_bare_share_max=max(shares),
               line_bare_min=min(r["broken_pp"] for r in line.rows),
               line_bare_max=max(r["broken_pp"] for r in line.rows),
               line_hours=sum(r["seconds"] for r in line.rows) / 3600,
               line_strength_unit=strength_unit(line))
    return out


def grid_516_numbers(grid_516, grid, line):
    """The 516-particle grid's numbers, by name, each kept point against
    the 64-particle grid's packings and the line at sigma^pm = sigma^p."""
    out = {"g516_kept": len(grid_516.rows), "g516_strain_cap": stopping(grid_516)[1]}
    low = [r["seconds"] / 60 for r in grid_516.rows if abs(r["rho_m"] - 0.06) < 1e-9]
    out.update(g516_006_minutes_min=min(low), g516_006_minutes_max=max(low))
    # the line at sigma^pm = sigma^p against the grid, which lacks 1.0 (between 0.95 and 1.1)
    out["g516_line_over_64_006"] = (line.point(0.06, 1.0)["sigma_eff_over_sigma_unit"] /
                                    grid.between(0.06, 1.0)["sigma_eff_over_sigma_unit"] - 1)
    for q in grid_516.points:
        t = "%s_%s" % (tag(q["rho_m"]), tag(q["sigma_pm_ratio"]))
        small = grid.between(q["rho_m"], q["sigma_pm_ratio"])
        for column, name in (("sigma_eff_over_sigma_unit", "sigma"), ("n_b", "nb"),
                             ("n_b_without_bare_contacts", "nbw")):
            out["g516_%s_%s" % (name, t)] = q[column]
            if small["std"][column] > 0:  # a point of one packing has no scatter
                out["g516_%s_sd_%s" % (name, t)] = ((q[column] - small[column])
                                                    / small["std"][column])
        out["g516_peak_strain_over_64_%s" % t] = q["strain_at_peak"] / small["strain_at_peak"]
        out["g516_sigma_over_64_%s" % t] = (q["sigma_eff_over_sigma_unit"] /
                                            small["sigma_eff_over_sigma_unit"] - 1)
        out["g516_adhesion_step_%s" % t] = q["sigma_pm_ratio"] - 1.0
        out["g516_gain_%s" % t] = (q["sigma_eff_over_sigma_unit"] /
                                   line.point(q["rho_m"], 1.0)["sigma_eff_over_sigma_unit"] - 1)
    return out


def coating_numbers(coating):
    """The coating study's numbers (full pores, the grid's three packings),
    by name: sigma_eff/sigma^[p] per adhesion, mean and standard deviation."""
    out = {"coating_rho": coating.points[0]["rho_m"]}
    for q in coating.points:
        t = tag(q["sigma_pm_ratio"])
        out["coating_sigma_%s" % t] = q["sigma_eff_over_sigma_unit"]
        out["coating_sigma_sd_%s" % t] = q["std"]["sigma_eff_over_sigma_unit"]
    out["coating_below_140"] = 1 - out["coating_sigma_140"]
    return out


def coating_516_numbers(coating_516, coating):
    """The coating at 516 particles (one run at full pores, 1.4 sigma^p),
    by name, and how far it lies from the 64-particle packings' mean in
    their standard deviations."""
    q = coating_516.point(coating_516.points[0]["rho_m"], 1.4)
    small = coating.point(coating.points[0]["rho_m"], 1.4)
    out = {"coating516_rho": q["rho_m"], "coating516_sigma_140": q["sigma_eff_over_sigma_unit"],
           "coating516_below_140": 1 - q["sigma_eff_over_sigma_unit"],
           "coating516_strain_140": q["strain_at_peak"]}
    (kept,) = coating_516.kept.values()
    out["coating516_rho_v"] = kept["sample"]["rho_v"]  # the void left at full pores
    out["coating516_sd_from_64"] = ((q["sigma_eff_over_sigma_unit"] -
                                     small["sigma_eff_over_sigma_unit"]) /
                                    small["std"]["sigma_eff_over_sigma_unit"])
    return out


def fig3_numbers(fig3, fig3_pp, grid):
    """The fig. 3 studies' numbers, by name: the range of the peak strains
    and strengths at sigma^pm = 0.3 sigma^p (bare contacts), and with
    contacts of 0.3 sigma^p against the grid's bare ones at 0.95 sigma^p."""
    out = {}
    for name, study in (("fig3_030", fig3), ("fig3_pp", fig3_pp)):
        strain = [r["strain_at_peak"] for r in study.rows]
        sigma = [r["sigma_eff_over_sigma_unit"] for r in study.rows]
        out.update({name + "_peak_min": min(strain), name + "_peak_max": max(strain),
                    name + "_sigma_min": min(sigma), name + "_sigma_max": max(sigma)})
    # against the run of the same sample (the grid's first packing) with bare contacts
    bare = {(r["rho_m"], r["sigma_pm_ratio"]): r for r in grid.rows if r["study"] == GRID[0]}
    gains = [r["sigma_eff_over_sigma_unit"] /
             bare[(r["rho_m"], r["sigma_pm_ratio"])]["sigma_eff_over_sigma_unit"] - 1
             for r in fig3_pp.rows]
    out.update(fig3_pp_gain_min=min(gains), fig3_pp_gain_max=max(gains))
    return out


def increment_numbers(study):
    out = {}
    for r in study.rows:
        t = tag(r["rho_m"])
        curve = curve_of(study.kept[r["id"]])
        out["inc_sigma_%s" % t] = r["sigma_eff_over_sigma_unit"]
        out["inc_peak_%s" % t] = r["strain_at_peak"]
        out["inc_end_strain_%s" % t] = float(curve["strain"][-1])
    return out


def resolution_numbers():
    out = {}
    for bpp, fit in k_against_resolution().items():
        out["k_516_%d" % bpp] = fit["k"]
        out["k_516_%d_rms" % bpp] = fit["rms_relative_residual"]
    return out


def numbers(data=DATA):
    """{name: value} of every number the pages quote from the kept rows."""
    grid, line = Study(GRID, data), Study(LINE, data)
    out = grid_numbers(grid)
    out.update(line_numbers(line))
    ours = (out["grid_fixed_k_A"], out["line_fixed_k_A"])
    theirs = (out["paper_A_low"], out["paper_A_high"])
    gaps = [a / b - 1 for a in ours for b in theirs]
    out.update(fixed_k_gap_min=-max(gaps), fixed_k_gap_max=-min(gaps))
    mine = ours + (out["eq10_lattice_A"], out["eq10_095_lattice_A"])
    out.update(paper_A_times_min=min(mine + theirs) / 0.3, paper_A_times_max=max(mine + theirs) / 0.3)
    out["line_bare_spread"] = out["line_bare_max"] / out["line_bare_min"] - 1
    for p in line.points:   # the line against the grid's sigma^pm nearest sigma^p, per rho^m
        near = grid.point(p["rho_m"], 0.95)
        out["line_over_grid_%s" % tag(p["rho_m"])] = (
            p["sigma_eff_over_sigma_unit"] / (near["sigma_eff_over_sigma_unit"] / 0.95))
    out.update(increment_numbers(Study((INCREMENT,), data)))
    out.update(grid_516_numbers(Study(GRID_516, data), grid, line))
    out.update(coating_numbers(Study(COATING, data)))
    out.update(coating_516_numbers(Study(COATING_516, data), Study(COATING, data)))
    out.update(fig3_numbers(Study(FIG3, data), Study(FIG3_PP, data), grid))
    out.update(resolution_numbers())
    out.update(convergence_data.matched_numbers())
    return out


# ---------------------------------------------------------------- the command
def run(args):
    if args.write or args.check:
        stale = []
        for name, (page, content) in blocks(args.data).items():
            with open(page, encoding="utf-8") as f:
                text = f.read()
            new = replace_block(text, name, content)
            if new != text:
                stale.append("%s: %s" % (os.path.relpath(page, ROOT), name))
                if args.write:
                    with open(page, "w", encoding="utf-8") as f:
                        f.write(new)
        if args.check and stale:
            sys.stderr.write("paper_numbers: differs from docs/data: %s\n" % ", ".join(stale))
            return 1
        print("paper_numbers: %s" % ("rewrote " + ", ".join(stale) if args.write and stale
                                     else "the generated tables are those of docs/data"))
        return 0
    for name, value in sorted(numbers(args.data).items()):
        print("%-28s %s" % (name, "–" if value is None else "%.6g" % value))
    return 0


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    group = arg_parser.add_mutually_exclusive_group()
    group.add_argument("--write", action="store_true", help="rewrite the generated tables")
    group.add_argument("--check", action="store_true",
                       help="exit 1 when a generated table differs from the data")
    arg_parser.add_argument("--data", default=DATA, help="the data folders' parent (docs/data)")
    return cli.run(arg_parser, run, argv)
