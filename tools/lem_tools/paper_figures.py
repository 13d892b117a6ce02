"""The paper's figures redrawn from study data folders (docs/data/<study>/).

Reads the rows kept by `tools/study.py ... --data DATA_DIR` (study_data)
of one or more studies of the same physics (e.g. a grid on one packing and
more packings at some of its points) and writes in OUT_DIR, without running
anything:
  results.csv   one row per run (the study's results.csv columns, with the
                study and lattice it comes from)
  fit.json      eq. 10 fitted to the grid points, beta and S^pm per rho^m
  fig03.png  stress-strain curves at the adhesion nearest sigma^p, one per
             rho^m, each step before its ruptures and the run's end after
             them; the paper's peak strain (~4e-3) marked
  fig05.png  E_eff against rho^m with a linear fit; the paper's 1.6 and
             2.5 E^[m] at rho^m = 0.28 as stars
  fig08.png  (a) the node-stress pdfs at three rho^m with our tails and the
             paper's slopes beta = 0.7 and 2.1; (b) beta against rho^m
  fig09.png  sigma_eff against sigma^pm; sigma_eff = sigma^[p] marked
  fig11.png  S^pm / S^p against rho^m; eq. 6, S^pm = rho^m / 0.28
  fig12.png  eq. 10: (a) against the paper's abscissa (k = 2.5) with its
             A = 0.3 and the slope 0.2 of its rho^m = 0.06 points; (b)
             against ours (the fitted k)
  fig13.png  n_b against strain (the paper's n_b, bare contacts counted;
             n_b without them at the runs' ends as open circles)
  fig14.png  n_b after failure against sigma^pm, (a) as the paper counts
             it, (b) without the bare contacts; the onset of eq. 13 (0.4)
             and the inflection (sigma^pm = sigma^p) marked
  fig15.png  grey maps of n_b both ways with eq. 13 (K_c^r = 0.4) and
             eq. 14 (0.7), the latter with the samples' E_eff and with
             E_eff at L_n -> 0 (paper.CONVERGED_MODULI, the paper's phases)
  fig16.png  n_b both ways (rows) against K_c^r of eq. 14 with the
             samples' E_eff, of eq. 14 with E_eff at L_n -> 0, and of
             eq. 13 (columns); 0.7 and 0.4 marked
A grid point with several runs (other packings or lattice seeds) is drawn
as their mean with +-1 standard deviation as error bars; every figure says
its resolution in its subtitle.  With --beside, the studies of another
resolution (the same phases and stop rule) are drawn beside them on
figs. 9, 12 (a), 14 and 16, open markers and dashed lines at the matrix
fractions the folders share.  Default OUT_DIR: docs/figures/<study name
of the first folder>/ of this repository.
"""
import os

import numpy as np

from . import cli
from .analysis import (K_DAMAGE_LIMIT, K_WEAKEST_LINK, RHO_FILLED, eq10_abscissa, fit_eq10,
                       group_by_rho, replicate_means, sample_means)
from .convergence import fit_line
from .errors import ToolError
from .files import require_folder_path, write_json
from .paper import paper_values
from .plotting import paper_mark, plt, save_figure
from .results import STUDY_COLUMNS
from .study_combine import physics
from .study_data import DataFolder, curve_of, open_data_folder
from .study_plots import (COLUMNS, E_P, N_B_LABELS, N_B_NAMES, RATIO, RHO, beta_panel,
                          damage_curve_picks, damage_curves, damage_map_panel, damage_panel,
                          finish, modulus_panel, point_colors, replicated, scaling_panel,
                          strength_panel, values, with_converged_k)
from .study_table import write_table

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DPI = 100
SEEDS = ("pack_seed", "lattice_seed")
# The paper's statements drawn as lines (sect. 3, 6): the peak strain of
# fig. 3, the A and k of eq. 10 and the slope of its rho^m = 0.06 points.
PAPER_PEAK_STRAIN = 4e-3
PAPER_A, PAPER_K, PAPER_LOW_SLOPE, PAPER_LOW_RHO = 0.3, 2.5, 0.2, 0.06
STRAIN_SCALE = 1e3


def same_physics(spec):
    """What must agree between the folders drawn together: physics() of the
    study without the seeds, which only choose the replicate, and without
    the strain cap, which only bounds how far a run may go (a run that
    stopped at it says so in its end_reason)."""
    out = physics(spec)
    out["sample"] = {k: v for k, v in out["sample"].items() if k not in SEEDS}
    out["fracture"] = {k: v for k, v in out["fracture"].items()
                       if k != "fracture_max_strain_ratio"}
    return out


def comparable(spec):
    """What must agree between the folders drawn and those drawn beside
    them at another resolution: the phases and the stop rule."""
    physics_of = same_physics(spec)
    return {"phases": physics_of["phases"],
            "stop rule": physics_of["fracture"].get("fracture_stop_fraction")}


def read_folders(folders):
    """(spec, rows, kept) of the data folders: the first folder's study,
    rows as results.csv has them with `study` and `lattice` (study name /
    lattice tag: one sample per lattice and rho^m), kept {row id: the run's
    data}."""
    first, rows, kept, seen = None, [], {}, {}
    for folder in folders:
        data, spec = open_data_folder(folder)
        if first is None:
            first, reference = spec, folder
        for part, wanted in same_physics(first).items():
            if same_physics(spec)[part] != wanted:
                raise ToolError("%s and %s differ in their %s: %s against %s"
                                % (reference, folder, part, same_physics(spec)[part], wanted))
        found = data.rows()
        if not found:
            print("paper_figures: %s keeps no row" % folder)
        for d in found:
            sample = d["sample"]
            key = (d["run"]["rho_m"], d["run"]["sigma_pm_ratio"], sample.get("packing_seed"),
                   sample.get("lattice_seed"), sample.get("bonds"))
            if key in seen:
                raise ToolError("the run at rho^m %g, sigma^pm/sigma^p %g, pack seed %s, lattice "
                                "seed %s is in %s and in %s: give each run once"
                                % (key[:4] + (seen[key], folder)))
            seen[key] = folder
            row = {c: np.nan if d["row"].get(c) is None else d["row"][c] for c in STUDY_COLUMNS}
            row["id"] = "%s/%s" % (spec["name"], d["run"]["id"])
            row.update(study=spec["name"], lattice="%s/%s" % (spec["name"], d["run"].get("lattice")))
            rows.append(row)
            kept[row["id"]] = d
    if not rows:
        raise ToolError("no row in %s: run the studies with --data first" % ", ".join(folders))
    return first, rows, kept


def read_beside(folders, spec):
    """{points, resolution} of the studies drawn beside those of `spec` at
    another resolution (None without folders)."""
    if not folders:
        return None
    theirs, rows, kept = read_folders(folders)
    for part, wanted in comparable(spec).items():
        if comparable(theirs)[part] != wanted:
            raise ToolError("--beside %s differs in its %s: %s against %s"
                            % (folders[0], part, comparable(theirs)[part], wanted))
    return {"points": replicate_means(rows, COLUMNS), "resolution": resolution(rows, kept)}


def draw_beside(ax, points, beside, y, x="sigma_pm_ratio", place=None):
    """`beside`'s `y` against `x` (or place(point)) at the matrix fractions
    of `points`, in their colours: open markers on dashed lines."""
    if not beside:
        return
    colors = point_colors(points)
    label = "open, dashed: %s particles" % beside["resolution"]["sample_particles"]
    for rho, ps in group_by_rho(beside["points"]).items():
        near = [r for r in colors if abs(r - rho) < 1e-9]
        ps = [p for p in ps if place or p.get(x) is not None]
        if near and ps:
            values(ax, [place(p) if place else p[x] for p in ps], ps, y, "o--",
                   color=colors[near[0]], mfc="white", alpha=0.7, label=label)
            label = None


def resolution(rows, kept):
    """The figures' subtitle (study_plots.resolution_text) from the samples
    of the rows."""
    samples = {}
    for r in rows:
        samples[(r["lattice"], r["rho_m"])] = kept[r["id"]]["sample"]
    bonds = [s["bonds"] for s in samples.values() if s.get("bonds")]
    particles = {s.get("sample_particles") for s in samples.values()}
    runs = [p["replicates"] for p in replicate_means(rows, ())]
    return {"sample_particles": "/".join(str(p) for p in sorted(particles, key=str)),
            "bonds": float(np.mean(bonds)) if bonds else None,
            "bonds_per_particle": float(np.mean(bonds)) / min(particles) if bonds else None,
            "L_n": float(np.mean(np.power(bonds, -1 / 3))) if bonds else None,
            "bonds_from": "samples", "runs_per_point": [min(runs), max(runs)]}


def sample_points(rows, kept, column):
    """One point per rho^m of the sample quantity `column` (of the rows'
    sample records), the mean and standard deviation over the samples."""
    per_sample = {}
    for r in rows:
        value = kept[r["id"]]["sample"].get(column)
        per_sample[(r["lattice"], r["rho_m"])] = {
            "id": r["lattice"], "rho_m": r["rho_m"], "sigma_pm_ratio": None,
            column: np.nan if value is None else value}
    return replicate_means(list(per_sample.values()), (column,))


def single(title):
    """A figure of one panel titled `title`."""
    fig, ax = plt.subplots(figsize=(7, 5.4))
    ax.set_title(title)
    return fig, ax


def fig03(points, kept, res, phases):
    """Stress against strain at the adhesion nearest sigma^p, one colour per
    rho^m (the particle contacts' strength named where they have one)."""
    ratios = sorted({p["sigma_pm_ratio"] for p in points})
    ratio = min(ratios, key=lambda r: abs(r - 1.0))
    colors = point_colors(points)
    contacts = ""
    if phases.get("sigma_pp"):
        contacts = r", $\sigma^{pp}/\sigma^p$ = %.2f" % (phases["sigma_pp"] / phases["sigma_p"])
    fig, ax = single(r"stress-strain at $\sigma^{pm}/\sigma^p$ = %.2f%s (paper fig. 3)"
                     % (ratio, contacts))
    for p in points:
        if p["sigma_pm_ratio"] != ratio:
            continue
        for i, run_id in enumerate(p["runs"]):
            curve = curve_of(kept[run_id])
            # each step's stress before its ruptures, then where the run
            # ended: after the last step's (a failure in one step shows)
            ax.plot(np.append(curve["strain"], curve["strain"][-1]) * STRAIN_SCALE,
                    np.append(curve["stress_before_norm"], curve["stress_norm"][-1]),
                    color=colors[p["rho_m"]], lw=1.6 if i == 0 else 0.7, alpha=1 if i == 0 else 0.6,
                    label=None if i else r"$\rho^m$ = %.2f" % p["rho_m"])
            peak = int(np.argmax(curve["stress_before_norm"]))
            ax.plot(curve["strain"][peak] * STRAIN_SCALE, curve["stress_before_norm"][peak], "o",
                    color=colors[p["rho_m"]], ms=4)
    ax.axvline(PAPER_PEAK_STRAIN * STRAIN_SCALE, ls="--", color="black",
               label=r"paper: peak at $\varepsilon_{zz} \approx 4\cdot10^{-3}$ (sect. 3)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.set_xlabel(r"strain $\varepsilon_{zz}$ ($10^{-3}$)")
    ax.set_ylabel(r"$\sigma_{zz} / \sigma^{[p]}$ (before each step's ruptures; the end after)")
    ax.legend(fontsize=8, title="dots: peaks" + (", thin: other samples"
                                                   if replicated(points) else ""),
              title_fontsize=8)
    return finish(fig, res)


def fig05(samples, phases, res):
    fig, ax = single("")
    modulus_panel(ax, samples, phases)
    rho = np.array([p["rho_m"] for p in samples])
    e = np.array([p["E_eff_over_E_unit"] for p in samples])
    if len(rho) > 1:
        line = fit_line(rho, e)
        slope, intercept = line["slope"], line["intercept"]
        xs = np.linspace(0, rho.max(), 20)
        ax.plot(xs, intercept + slope * xs, ":", color="tab:blue",
                label=r"linear fit: %.3f + %.3f $\rho^m$" % (intercept, slope))
    (r, value, source, stated), = paper_values("E_adhesive_over_E_unit", phases)
    paper_mark(ax, [r], [value], "paper, %s, adhesive contacts: %s%s" % (
        source, stated, " = %.3f%s" % (value, E_P)), color="tab:red")
    ax.set_title("effective modulus, bare contacts (paper fig. 5)")
    ax.legend(fontsize=8)
    return finish(fig, res)


def pdf_runs(points):
    """The runs whose pdf fig. 8 draws: at the lowest, middle and highest
    rho^m, each its first run at the lowest sigma^pm (the first equilibrium,
    as beta is measured)."""
    rhos = sorted({p["rho_m"] for p in points})
    chosen = sorted({rhos[0], rhos[len(rhos) // 2], rhos[-1]})
    low = min(p["sigma_pm_ratio"] for p in points)
    return [(p["rho_m"], p["runs"][0]) for p in points
            if p["rho_m"] in chosen and p["sigma_pm_ratio"] == low]


def tail(ax, pdf, beta, style, color, label):
    """The exponential tail of eq. 2 with exponent `beta` from the start of
    the tail of `pdf` (its share of the nodes as the density's scale) to its
    largest s."""
    start = pdf["tail_start"]
    edges = np.array(pdf["edges"])
    s = np.linspace(start, edges[-1], 30)
    density = pdf["tail_share"] * beta * np.exp(-beta * (s - start))
    shown = density > 0.3 * min(v for v in pdf["inside"] if v > 0)
    ax.semilogy(s[shown], density[shown], style, color=color, lw=1.5, label=label)


def fig08(points, samples, kept, phases, res):
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5.4))
    colors = point_colors(points)
    drawn = {}
    for rho, run_id in pdf_runs(points):
        pdf = kept[run_id].get("stress_pdf")
        if not pdf:
            continue
        edges = np.array(pdf["edges"])
        centres = 0.5 * (edges[1:] + edges[:-1])
        inside = np.array(pdf["inside"], dtype=float)
        ok = inside > 0
        a.semilogy(centres[ok], inside[ok], "o", ms=3, color=colors[rho],
                   label=r"$\rho^m$ = %.2f" % rho)
        if pdf.get("beta"):
            drawn[rho] = pdf
            tail(a, pdf, pdf["beta"], ":", colors[rho], r"ours, $\beta$ = %.2f" % pdf["beta"])
    # the paper's slopes, each from the tail of the drawn pdf nearest its rho^m
    for rho_paper, beta, *_ in paper_values("beta", phases) if drawn else ():
        rho = min(drawn, key=lambda r: abs(r - rho_paper))
        tail(a, drawn[rho], beta, "--", colors[rho],
             r"paper, $\rho^m$ = %.2f: $\beta$ = %g (sect. 4)" % (rho_paper, beta))
    a.set_xlabel(r"$s = \sigma^i_{zz} / \sigma_{zz}$")
    a.set_ylabel("pdf (nodes off the box faces)")
    a.set_title("(a) node-stress pdf, first equilibrium (paper fig. 8)")
    a.legend(fontsize=8)
    beta_panel(b, samples, phases)
    return finish(fig, res)


def fig09(points, res, beside=None):
    fig, ax = single("")
    strength_panel(ax, points)
    draw_beside(ax, points, beside, "sigma_eff_over_sigma_unit")
    ax.axhline(1.0, ls="--", color="black", lw=1,
               label=r"$\sigma^{[p]}$: the paper's $\sigma_{\rm eff}$ at $\rho^m$ = 0.28, "
                     r"$\sigma^{pm} > \sigma^p$ is slightly above it (sect. 5)")
    ax.set_title("tensile strength (paper fig. 9)")
    ax.legend(fontsize=8)
    return finish(fig, res)


def fig11(rows, kept, res):
    fig, ax = single("particle-matrix interface (paper fig. 11)")
    pts = sample_points(rows, kept, "interface_ratio_Spm_Sp")
    rho = [p["rho_m"] for p in pts]
    values(ax, rho, pts, "interface_ratio_Spm_Sp", "o", color="tab:blue",
           label=r"ours: pm bonds / bonds leaving the particles")
    xs = np.linspace(0, max(rho + [RHO_FILLED]), 20)
    ax.plot(xs, xs / RHO_FILLED, "--", color="black",
            label=r"paper, eq. 6: $S^{pm}/S^p = \rho^m / %.2f$" % RHO_FILLED)
    ax.set_xlabel(RHO)
    ax.set_ylabel(r"$S^{pm} / S^p$")
    ax.legend(fontsize=8)
    return finish(fig, res)


def fig12(points, fit, res, beside=None):
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5.4))
    scaling_panel(a, points, fit, k=PAPER_K)
    draw_beside(a, points, beside, "sigma_eff_over_sigma_pm",
                place=lambda p: float(eq10_abscissa(p["rho_m"], PAPER_K)))
    right = a.get_xlim()[1]
    xs = np.linspace(0, right, 10)
    a.plot(xs, PAPER_A * xs, "-.", color="tab:red",
           label="paper: A = %g, k = %g (units not stated)" % (PAPER_A, PAPER_K))
    a.plot(xs, PAPER_LOW_SLOPE * xs, ":", color="tab:red",
           label=r"paper: slope %g of its $\rho^m$ = %g points" % (PAPER_LOW_SLOPE, PAPER_LOW_RHO))
    a.set_title("(a) eq. 10 at the paper's k = %g (paper fig. 12)" % PAPER_K)
    a.legend(fontsize=8)
    if scaling_panel(b, points, fit):
        b.set_title("(b) eq. 10 at our fitted k")
    return finish(fig, res)


def fig13(points, kept, res):
    fig, ax = single("")
    curves = {run_id: curve_of(kept[run_id]) for p in damage_curve_picks(points)
              for run_id in p["runs"]}
    damage_curves(ax, points, curves, point_colors(points))
    ax.set_title("particle damage against strain (paper fig. 13)")
    return finish(fig, res)


def fig14(points, res, beside=None):
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.4))
    fig.suptitle(r"damage after failure against $\sigma^{pm}$ (paper fig. 14)")
    for ax, quantity, letter in zip(axes, N_B_LABELS, "ab"):
        damage_panel(ax, points, quantity=quantity)
        draw_beside(ax, points, beside, quantity)
        ax.axvline(K_WEAKEST_LINK, ls="--", color="tab:red",
                   label=r"paper: onset at $\sigma^{pm}/\sigma^p \approx$ %.1f (eq. 13)"
                   % K_WEAKEST_LINK)
        ax.axvline(1.0, ls=":", color="0.3",
                   label=r"paper: inflection at $\sigma^{pm} \approx \sigma^p$")
        ax.set_xlabel(RATIO)
        ax.set_title("(%s) %s" % (letter, N_B_NAMES[quantity]))
        ax.legend(fontsize=8)
    return finish(fig, res)


def fig15(points, samples, phases, res):
    fig, axes = plt.subplots(1, 2, figsize=(14, 5.6))
    for ax, quantity, letter in zip(axes, N_B_LABELS, "ab"):
        damage_map_panel(fig, ax, points, samples, phases, quantity)
        ax.set_title(r"(%s) %s over the grid (paper fig. 15)" % (letter, N_B_NAMES[quantity]))
    return finish(fig, res)


def fig16(points, phases, res, beside=None):
    """n_b both ways (rows) against K_c^r of eq. 14 with the samples' E_eff,
    of eq. 14 with E_eff at L_n -> 0 (the paper's phases only) and of eq. 13
    (columns)."""
    points = with_converged_k(points, phases)
    if beside:
        beside = dict(beside, points=with_converged_k(beside["points"], phases))
    converged = any(p["K_c_r_eq14_converged"] is not None for p in points)
    fig, axes = plt.subplots(2, 3, figsize=(17, 10))
    abscissae = (("K_c_r_eq14", r"$K_c^r$ of eq. 14, the samples' $E_{\rm eff}$",
                  K_DAMAGE_LIMIT, ":", "tab:blue", "no damage below"),
                 ("K_c_r_eq14_converged", r"$K_c^r$ of eq. 14, $E_{\rm eff}$ at $L_n \to 0$ "
                  r"(516 p)", K_DAMAGE_LIMIT, ":", "tab:blue", "no damage below"),
                 ("sigma_pm_ratio", r"$K_c^r$ of eq. 13 $= \sigma^{pm}/\sigma^p$",
                  K_WEAKEST_LINK, "--", "tab:red", "first damage at"))
    for row, quantity in zip(axes, N_B_LABELS):
        for ax, (column, label, limit, style, color, says) in zip(row, abscissae):
            letter = "abcdef"[list(axes.flat).index(ax)]
            ax.set_title(r"(%s) %s" % (letter, N_B_NAMES[quantity]), fontsize=10)
            ax.set_xlabel(label)
            if column == "K_c_r_eq14_converged" and not converged:
                ax.text(0.5, 0.5, "no modulus at $L_n \\to 0$\nfor these phases",
                        transform=ax.transAxes, ha="center", va="center")
                continue
            damage_panel(ax, points, column, quantity)
            draw_beside(ax, points, beside, quantity, x=column)
            ax.axvline(limit, ls=style, color=color, label="paper: %s $K_c^r$ = %.1f (eq. %d)"
                       % (says, limit, 14 if limit == K_DAMAGE_LIMIT else 13))
            ax.legend(fontsize=7)
    fig.suptitle("particle damage against the relative toughness (paper fig. 16)")
    return finish(fig, res)


def figures(folders, beside_folders=()):
    """{name: figure} of the data `folders` (with `beside_folders` drawn
    beside them), and what they are drawn from: the rows, the grid points
    and the fit of eq. 10."""
    spec, rows, kept = read_folders(folders)
    phases = spec["phases"]
    beside = read_beside(beside_folders, spec)
    points = replicate_means(rows, COLUMNS)
    samples = sample_means(rows)
    fit = fit_eq10([p["rho_m"] for p in points], [p["sigma_eff_over_sigma_pm"] for p in points])
    res = resolution(rows, kept)
    res_beside = dict(res, beside=beside["resolution"]) if beside else res
    drawn = {"fig03": fig03(points, kept, res, phases), "fig05": fig05(samples, phases, res),
             "fig08": fig08(points, samples, kept, phases, res),
             "fig09": fig09(points, res_beside, beside), "fig11": fig11(rows, kept, res),
             "fig12": fig12(points, fit, res_beside, beside), "fig13": fig13(points, kept, res),
             "fig14": fig14(points, res_beside, beside),
             "fig15": fig15(points, samples, phases, res),
             "fig16": fig16(points, phases, res_beside, beside)}
    record = {"folders": list(folders), "eq10": fit, "runs": len(rows), "points": len(points),
              "beta_by_rho_m": {"%.4f" % p["rho_m"]: p["beta"] for p in samples},
              "interface_ratio_by_rho_m": {
                  "%.4f" % p["rho_m"]: p["interface_ratio_Spm_Sp"]
                  for p in sample_points(rows, kept, "interface_ratio_Spm_Sp")},
              "figures": res}
    if beside:
        record["beside"] = list(beside_folders)
    return drawn, rows, points, record


def draw_folders(folders, out, beside_folders=()):
    """results.csv, fit.json and fig*.png of the data `folders` (and
    `beside_folders` beside them) in `out`; returns the PNG paths."""
    drawn, rows, _, record = figures(folders, beside_folders)
    os.makedirs(out, exist_ok=True)
    write_table(os.path.join(out, "results.csv"), rows, ("study", "lattice") + STUDY_COLUMNS)
    write_json(os.path.join(out, "fit.json"), record)
    paths = []
    for name, fig in drawn.items():
        paths.append(os.path.join(out, name + ".png"))
        save_figure(fig, paths[-1], dpi=DPI)
    return paths


def run(args):
    out = args.out or os.path.join(ROOT, "docs", "figures",
                                   DataFolder(args.folders[0]).spec().get("name", "study"))
    require_folder_path(out, "the figures' folder (--out)")
    paths = draw_folders(args.folders, out, args.beside or ())
    print("paper_figures: %d figures, results.csv and fit.json -> %s" % (len(paths), out))


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("folders", metavar="DATA_DIR", nargs="+",
                            help="data folders of studies (tools/study.py ... --data DATA_DIR)")
    arg_parser.add_argument("--out", metavar="OUT_DIR",
                            help="where the figures go (default: docs/figures/<study name>)")
    arg_parser.add_argument("--beside", metavar="DATA_DIR", nargs="+",
                            help="data folders of studies at another resolution, drawn beside "
                                 "on figs. 9, 12 (a), 14 and 16")
    return cli.run(arg_parser, run, argv)
