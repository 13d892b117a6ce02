"""The L_n -> 0 extrapolations of docs/convergence.md, docs/model/theory.md
(fig. 6) and docs/paper-void-rule.md, recomputed from the measurements kept
as plain tables in docs/data/convergence-*.csv, their figures, and the
resolution of our 516-particle sample that matches each of the paper's
three measures of its own.

    tools/convergence_data.py                 every line: the per-size values and the fit
    tools/convergence_data.py --figures DIR   draw a figure per table into DIR

Each line is lem_tools.convergence.fit_line in L_n = M^(-1/3) (M the
lattice's bonds): ordinary least squares for single samples, weighted by
the standard error of each size's mean where the table keeps mean, sd and
n (the scatter study).  tests/python/test_convergence_data.py finds each
number on the pages at the digits they quote.
"""
import csv
import math
import os

from . import cli
from .convergence import fit_line

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DATA = os.path.join(ROOT, "docs", "data")
TABLES = ("elastic-516", "strength-516", "scatter-64-elastic", "scatter-fracture", "fig6",
          "void-rule")
PARTICLES = 516

# The paper's own measures of its resolution (appendix A and sect. 3).
PAPER_BONDS = 1.3e6             # M, elements
PAPER_NODES = 3e5               # N, nodes
PAPER_P_BONDS_PER_PARTICLE = 1550
PAPER_ROUGHNESS = 0.2           # 2a/d, d the mean particle diameter
# Our sample at the paper's M (docs/model/cemented-samples.md): the bonds
# with both ends in one particle, per particle, and the mean diameter.
OUR_P_BONDS_PER_PARTICLE = 1205
MEAN_DIAMETER_OVER_DMIN = 1.125


# Lines the pages do not extrapolate (not linear in L_n, or a stop-point
# measure): drawn as points joined by dashes, without a line to L_n = 0.
NOT_EXTRAPOLATED = {("strength-516", "strain_at_peak_1e-3"), ("strength-516", "n_b_at_stop"),
                    ("strength-516", "particle_share_of_non_bare_broken"),
                    ("scatter-fracture", "strain_at_peak_1e-3")}


def path(name, data=DATA):
    return os.path.join(data, "convergence-%s.csv" % name)


def half_unit(text):
    """Half a unit of the last digit of a number as written."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return 0.5 * 10 ** -decimals


def read(name, data=DATA):
    """The rows of docs/data/convergence-<name>.csv, numbers as floats
    (an empty cell None), the comment lines skipped; "_half" maps each
    column to half a unit of its last digit as kept."""
    with open(path(name, data), encoding="utf-8") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    out = []
    for row in rows:
        parsed = {"_half": {k: half_unit(t) for k, t in row.items()}}
        for key, text in row.items():
            try:
                parsed[key] = float(text) if text != "" else None
            except ValueError:
                parsed[key] = text
        out.append(parsed)
    return out


def l_n(bonds):
    return bonds ** (-1.0 / 3.0)


def line(points, weighted=False, halves=None, halves_sd=None):
    """{"points": [(label, L_n, value, sd, n)] coarse to fine, "fit":
    fit_line's result, "rounding": how far each of the fit's numbers can
    move within the rounding of the kept values (half a unit of each
    value's last digit, `halves`, in the order of `points`)} of one quantity."""
    order = sorted(range(len(points)), key=lambda i: -points[i][1])
    points = [points[i] for i in order]
    halves = [halves[i] for i in order] if halves else [0.0] * len(points)
    halves_sd = [halves_sd[i] for i in order] if halves_sd else [0.0] * len(points)
    sigma = [p[3] / math.sqrt(p[4]) for p in points] if weighted else None
    x = [p[1] for p in points]
    y = [p[2] for p in points]
    fit = fit_line(x, y, sigma)
    rounding = dict.fromkeys(("intercept", "slope", "intercept_se"), 0.0)
    moves = [(x, [v + (h if j == i else 0.0) for j, v in enumerate(y)], sigma)
             for i, h in enumerate(halves)]
    if weighted:        # the weights move with the rounding of each sd
        moves += [(x, y, [(p[3] + (h if j == i else 0.0)) / math.sqrt(p[4])
                          for j, p in enumerate(points)])
                  for i, h in enumerate(halves_sd)]
    for args in moves:
        moved = fit_line(*args)
        for key in rounding:
            if math.isfinite(moved[key]):
                rounding[key] += abs(moved[key] - fit[key])
    return {"points": points, "fit": fit, "rounding": rounding}


def group(rows, keys):
    out = {}
    for row in rows:
        out.setdefault(tuple(row[k] for k in keys), []).append(row)
    return out


def lines(data=DATA):
    """{table: {key: line}} for every table; a key names the quantity and
    its point: (quantity, rho_m[, sigma^pm/sigma^p])."""
    out = {}
    rows = read("elastic-516", data)
    out["elastic-516"] = {
        (q, rho): line([(r["bonds_per_particle"], l_n(r["bonds_per_particle"] * PARTICLES),
                         r["value"], None, 1) for r in g], halves=[r["_half"]["value"] for r in g])
        for (q, rho), g in group(rows, ("quantity", "rho_m")).items()}
    rows = read("strength-516", data)
    out["strength-516"] = {
        key: line([(r["bonds_per_particle"], l_n(r["bonds_per_particle"] * PARTICLES),
                    r["value"], None, 1) for r in g], halves=[r["_half"]["value"] for r in g])
        for key, g in group(rows, ("quantity", "rho_m", "sigma_pm_ratio")).items()}
    rows = read("scatter-64-elastic", data)
    out["scatter-64-elastic"] = {
        key: line([(r["bonds_per_particle"], l_n(r["bonds_per_particle"] * 64), r["mean"],
                    r["sd"], r["n"]) for r in g], weighted=True,
                   halves=[r["_half"]["mean"] for r in g], halves_sd=[r["_half"]["sd"] for r in g])
        for key, g in group(rows, ("quantity", "rho_m")).items()}
    rows = [r for r in read("scatter-fracture", data) if r["particles"] == 64]
    out["scatter-fracture"] = {
        key: line([(r["bonds_per_particle"], l_n(r["bonds_per_particle"] * 64), r["mean"],
                    r["sd"], r["n"]) for r in g], weighted=True,
                   halves=[r["_half"]["mean"] for r in g], halves_sd=[r["_half"]["sd"] for r in g])
        for key, g in group(rows, ("quantity", "rho_m")).items()}
    rows = read("fig6", data)
    out["fig6"] = {
        (q,): line([(r["bonds"], r["L_n"], r[q], None, 1) for r in rows],
                   halves=[r["_half"][q] for r in rows])
        for q in ("E_stiff_over_Em", "E_pores_any_end_over_Em", "E_pores_both_ends_over_Em")}
    rows = read("void-rule", data)
    out["void-rule"] = {
        (q, rho): line([(r["bonds_per_particle"], l_n(r["bonds"]), r[q], None, 1) for r in g],
                       halves=[r["_half"][q] for r in g])
        for (rho,), g in group(rows, ("rho_m",)).items()
        for q in ("E_bare_any_end_over_Ep", "E_bare_both_ends_over_Ep",
                  "E_adhesive_any_end_over_Ep", "E_adhesive_both_ends_over_Ep")}
    return out


def mean_sd(values):
    mean = sum(values) / len(values)
    return mean, math.sqrt(sum((x - mean) ** 2 for x in values) / (len(values) - 1))


def replicates_516(data=DATA):
    """{(quantity, rho_m): {mean, sd, values, and how far the mean and sd can
    move within the rounding of the kept values}} of the three
    516-particle packings."""
    rows = [r for r in read("scatter-fracture", data) if r["particles"] == PARTICLES]
    out = {}
    for key, g in group(rows, ("quantity", "rho_m")).items():
        v = [r["mean"] for r in sorted(g, key=lambda r: r["pack_seed"])]
        h = g[0]["_half"]["mean"]
        mean, sd = mean_sd(v)
        sd_rounding = sum(abs(mean_sd([x + (h if j == i else 0.0) for j, x in enumerate(v)])[1]
                              - sd) for i in range(len(v)))
        out[key] = {"mean": mean, "sd": sd, "values": v, "mean_rounding": h,
                    "sd_rounding": sd_rounding}
    return out


# ---------------------------------------------------------------- the paper's resolution
def matched_resolutions(data=DATA):
    """Bonds per particle of our 516-particle sample that match each of the
    paper's measures of its resolution:

    - "elements": M = 1.3e6 bonds, as it is;
    - "nodes": N = 3e5 nodes, with our nodes proportional to the bonds
      (the two kept node counts give the ratio; they differ by "node_ratio_spread");
    - "particle bonds": 1 550 bonds inside each particle, our 1 205 at the
      paper's M scaled in proportion to M;
    - "roughness": 2a/d = 0.2, with a proportional to L_n = M^(-1/3)."""
    rows = read("resolution-516", data)
    ratios = [r["nodes"] / r["bonds"] for r in rows]
    ratio = ratios[0]           # the paper-size sample
    paper_size = rows[0]
    per_particle = paper_size["bonds"] / PARTICLES
    roughness = 2 * paper_size["a_over_dmin"] / MEAN_DIAMETER_OVER_DMIN
    return {
        "elements": PAPER_BONDS / PARTICLES,
        "nodes": PAPER_NODES / ratio / PARTICLES,
        "particle bonds": per_particle * PAPER_P_BONDS_PER_PARTICLE / OUR_P_BONDS_PER_PARTICLE,
        "roughness": per_particle * (roughness / PAPER_ROUGHNESS) ** 3,
        "our_roughness": roughness,
        "nodes_per_bond": ratio,
        "node_ratio_spread": max(ratios) / min(ratios) - 1,
    }


def interpolate(fitted, bonds_per_particle, particles=PARTICLES):
    """The value of a line's kept sizes at `bonds_per_particle`, linear in
    L_n between the two sizes that bracket it (None outside them)."""
    x = l_n(bonds_per_particle * particles)
    points = fitted["points"]
    for (_, x0, y0, _, _), (_, x1, y1, _, _) in zip(points, points[1:]):
        if x1 <= x <= x0:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return None


# The verdicts of docs/paper.md's comparison table that rest on our value at
# the paper's resolution: (name, table, key).
AT_RESOLUTION = (
    ("beta_006", "strength-516", ("beta_off_faces", 0.06, None)),
    ("beta_028", "strength-516", ("beta_off_faces", 0.28, None)),
    ("strain_013", "strength-516", ("strain_at_peak_1e-3", 0.13, 1.0)),
    ("strain_028", "strength-516", ("strain_at_peak_1e-3", 0.28, 1.0)),
    ("E_bare_028", "elastic-516", ("E_bare_over_Ep", 0.28)),
    ("E_adhesive_028", "elastic-516", ("E_adhesive_over_Ep", 0.28)),
)


def at_matched_resolutions(data=DATA):
    """{(name, measure): value} of each AT_RESOLUTION quantity at each
    matched resolution within the kept sizes (None beyond them)."""
    fits = lines(data)
    matched = matched_resolutions(data)
    return {(name, measure): interpolate(fits[table][key], matched[measure])
            for name, table, key in AT_RESOLUTION
            for measure in ("elements", "nodes", "particle bonds", "roughness")}


MEASURES = (("elements", "elements M", "1.3·10⁶"), ("nodes", "nodes N", "3·10⁵"),
            ("particle bonds", "bonds inside a particle", "1 550"),
            ("roughness", "roughness 2a/d̄", "0.2"))
# (name, what, the paper's value, scale to the unit shown, digits)
SHOWN = {"beta_006": ("β at ρ^m = 0.06", "≈ 0.7", 1.0, 3),
         "beta_028": ("β at ρ^m = 0.28", "≈ 2.1", 1.0, 3),
         "strain_013": ("ε_zz at the peak (10⁻³), ρ^m = 0.13", "≈ 4", 1.0, 2),
         "strain_028": ("ε_zz at the peak (10⁻³), ρ^m = 0.28", "≈ 4", 1.0, 2),
         "E_bare_028": ("E_eff/E^[m], bare contacts, ρ^m = 0.28", "1.6", 3.0, 2),
         "E_adhesive_028": ("E_eff/E^[m], adhesive contacts, ρ^m = 0.28", "2.5", 3.0, 2)}


def group_digits(n):
    return "{:,}".format(int(round(n))).replace(",", " ")


def resolution_table(data=DATA):
    """The generated block of docs/paper-analysis.md: the size of our
    516-particle sample that matches each of the paper's measures, and the
    quantities of the verdicts made at the paper's resolution there."""
    matched = matched_resolutions(data)
    paper_size = read("resolution-516", data)[0]
    ours = {"elements": group_digits(paper_size["bonds"]),
            "nodes": group_digits(paper_size["nodes"]),
            "particle bonds": group_digits(OUR_P_BONDS_PER_PARTICLE),
            "roughness": "%.3f" % matched["our_roughness"]}
    out = ["| the paper's measure | the paper | ours at 2 521 bonds per particle "
           "| matched at (bonds per particle) |", "|---|---|---|---|"]
    for measure, label, paper_value in MEASURES:
        out.append("| %s | %s | %s | %s |" % (label, paper_value, ours[measure],
                                              group_digits(matched[measure])))
    out += ["", "| quantity | the paper | 2 500 b/p (kept) | matched by M | by N "
            "| by bonds inside a particle | by roughness | at L_n → 0 |",
            "|---|---|---|---|---|---|---|---|"]
    fits = lines(data)
    values = at_matched_resolutions(data)
    for name, table, key in AT_RESOLUTION:
        what, paper_value, scale, digits = SHOWN[name]
        fitted = fits[table][key]
        kept = [p[2] for p in fitted["points"] if p[0] == 2500][0]
        cells = ["%.*f" % (digits, kept * scale)]
        for measure, _, _ in MEASURES:
            v = values[(name, measure)]
            cells.append("–" if v is None else "%.*f" % (digits, v * scale))
        if key[0].startswith("strain"):
            cells.append("not extrapolated")
        else:
            fit = fitted["fit"]
            cells.append("%.*f ± %.*f" % (digits, fit["intercept"] * scale, digits,
                                          fit["intercept_se"] * scale))
        out.append("| %s | %s | %s |" % (what, paper_value, " | ".join(cells)))
    return "\n".join(out)


def matched_numbers(data=DATA):
    """{name: value} of the matched resolutions and the quantities there,
    as docs/paper-analysis.md quotes them (tools/paper_numbers.py)."""
    matched = matched_resolutions(data)
    out = {"res_%s" % m.replace(" ", "_"): matched[m] for m, _, _ in MEASURES}
    out.update(res_our_roughness=matched["our_roughness"],
               res_nodes_per_bond=matched["nodes_per_bond"],
               res_node_spread=matched["node_ratio_spread"],
               res_nodes_bonds=matched["nodes"] * PARTICLES,
               res_roughness_bonds=matched["roughness"] * PARTICLES)
    for (name, measure), value in at_matched_resolutions(data).items():
        if value is not None:
            out["res_%s_%s" % (name, measure.replace(" ", "_"))] = value * SHOWN[name][2]
    return out


# ---------------------------------------------------------------- figures
def draw(out_dir, data=DATA):
    """A figure per table: each quantity against L_n, its points, the
    fitted line and the extrapolated point at L_n = 0.  Returns the paths."""
    from .plotting import plt, save_figure

    os.makedirs(out_dir, exist_ok=True)
    fits = lines(data)
    paths = []
    for table in TABLES:
        groups = {}
        for key, fitted in fits[table].items():
            groups.setdefault(key[0], []).append((key, fitted))
        names = sorted(groups)
        columns = min(4, len(names))
        rows = math.ceil(len(names) / columns)
        fig, axes = plt.subplots(rows, columns, figsize=(3.6 * columns, 3.0 * rows),
                                 squeeze=False)
        for ax, name in zip(axes.flat, names):
            for key, fitted in sorted(groups[name], key=lambda e: str(e[0])):
                xs = [p[1] for p in fitted["points"]]
                ys = [p[2] for p in fitted["points"]]
                label = ", ".join("%g" % k for k in key[1:] if k is not None) or name
                errors = [p[3] for p in fitted["points"]]
                if all(e is not None for e in errors):
                    shown = ax.errorbar(xs, ys, yerr=errors, fmt="o", ms=4, capsize=2,
                                        label=label)
                    colour = shown[0].get_color()
                else:
                    colour = ax.plot(xs, ys, "o", ms=4, label=label)[0].get_color()
                fit = fitted["fit"]
                if (table, name) in NOT_EXTRAPOLATED:
                    ax.plot(xs, ys, "--", color=colour, lw=0.8)
                elif fit:
                    ends = [0.0, max(xs)]
                    ax.plot(ends, [fit["intercept"] + fit["slope"] * x for x in ends], "-",
                            color=colour, lw=0.8)
                    ax.errorbar([0.0], [fit["intercept"]],
                                yerr=[fit["intercept_se"]] if math.isfinite(
                                    fit["intercept_se"]) else None,
                                fmt="*", ms=9, color=colour, capsize=2)
            ax.set_title(name, fontsize=9)
            ax.set_xlabel("L_n")
            ax.set_xlim(left=-0.0003)
            ax.legend(fontsize=7, title="ρ^m, σ^pm/σ^p" if table != "fig6" else None,
                      title_fontsize=7)
        for ax in list(axes.flat)[len(names):]:
            ax.axis("off")
        fig.suptitle("docs/data/convergence-%s.csv: lines in L_n (stars: L_n → 0; dashed: "
                     "not extrapolated on the pages)" % table, fontsize=10)
        fig.tight_layout()
        target = os.path.join(out_dir, "convergence-data-%s.png" % table)
        save_figure(fig, target, dpi=100)
        paths.append(target)
    return paths


# ---------------------------------------------------------------- the command
def report(data=DATA):
    lines_out = []
    for table, fitted_lines in lines(data).items():
        lines_out.append("== convergence-%s.csv" % table)
        for key, fitted in sorted(fitted_lines.items(), key=lambda e: str(e[0])):
            fit = fitted["fit"]
            values = " ".join("%g" % p[2] for p in fitted["points"])
            lines_out.append("%-60s %s -> %.4f +- %.4f (slope %.2f)" % (
                key, values, fit["intercept"], fit["intercept_se"], fit["slope"]))
    matched = matched_resolutions(data)
    lines_out.append("== the paper's resolution in bonds per particle of our 516-particle sample")
    for measure in ("elements", "nodes", "particle bonds", "roughness"):
        lines_out.append("%-16s %.0f" % (measure, matched[measure]))
    for (name, measure), value in sorted(at_matched_resolutions(data).items()):
        lines_out.append("%-16s %-16s %s" % (name, measure,
                                             "-" if value is None else "%.4f" % value))
    return "\n".join(lines_out)


def run(args):
    if args.figures:
        for target in draw(args.figures):
            print(target)
    else:
        print(report())
    return 0


def main(argv=None):
    parser = cli.parser(__doc__)
    parser.add_argument("--figures", metavar="DIR",
                        help="draw a figure per table into DIR (docs/figures for the pages)")
    return cli.run(parser, run, argv)
