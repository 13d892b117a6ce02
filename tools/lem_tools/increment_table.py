"""How much the load increment matters: the rows of studies that differ only
in -fracture_increment, side by side (docs/model/fracture-increment.md).

Reads the data folders (docs/data/<study>/) of studies whose physics is the
same but for `fracture.fracture_increment`, and compares every run with the
run of the same sample (pack seed, lattice seed, rho^m, sigma^pm) at the
reference increment (the paper's 3e-4 a, or --reference); a point with
no run at the reference increment is left out and named.  Prints a table
per rho^m with, for each increment, the mean and standard deviation over
the samples of sigma_eff, the strain at the peak, n_b after failure (both
ways: as the paper counts it and without the bare contacts) and the broken
bonds per phase, and the mean change from the reference with the
scatter between samples at the reference beside it; writes in OUT_DIR:
  increment.csv    one row per run (increment factor, sample, values)
  increment.json   the table's numbers
  increment.png    each quantity against the increment factor, error bars
                   the standard deviation over the samples
A change is "within the scatter" when its mean over the samples is below
the standard deviation between the samples at the reference increment.
"""
import math
import os

import numpy as np

from . import cli
from .errors import ToolError
from .files import require_folder_path, write_json
from .plotting import plt, save_figure
from .study_combine import physics
from .study_data import open_data_folder
from .study_table import write_table

PAPER_INCREMENT = 3e-4      # -fracture_increment's default, the paper's (in a)
SAMPLE_KEYS = ("packing_seed", "lattice_seed")
QUANTITIES = (  # (row column, label, scale for the table)
    ("sigma_eff_over_sigma_unit", "σ_eff/σ^[p]", 1.0),
    ("strain_at_peak", "ε at peak (10⁻³)", 1e3),
    ("n_b", "n_b after failure", 1.0),
    ("n_b_without_bare_contacts", "n_b without the bare contacts", 1.0),
    ("broken_p", "broken p", 1.0),
    ("broken_m", "broken m", 1.0),
    ("broken_pp", "broken pp", 1.0),
    ("broken_pm", "broken pm", 1.0),
)


def increment_of(spec, folder):
    """The -fracture_increment of a study file (its default when not set)."""
    if "strain_increment" in spec:
        raise ToolError("%s sets strain_increment: compare studies that set "
                        "fracture.fracture_increment" % folder)
    return float(spec.get("fracture", {}).get("fracture_increment", PAPER_INCREMENT))


def without_increment(spec):
    out = physics(spec)
    out["fracture"] = {k: v for k, v in out["fracture"].items() if k != "fracture_increment"}
    return out


def read_rows(folders):
    """One dict per kept run of the folders: increment, rho_m, sigma_pm_ratio,
    the sample's seeds and the QUANTITIES."""
    rows, first, seen = [], None, set()
    for folder in folders:
        data, spec = open_data_folder(folder)
        if first is None:
            first, reference = without_increment(spec), folder
        elif without_increment(spec) != first:
            raise ToolError("%s and %s differ in more than fracture_increment" % (reference, folder))
        increment = increment_of(spec, folder)
        for d in data.rows():
            row = {"increment": increment, "rho_m": d["run"]["rho_m"],
                   "sigma_pm_ratio": d["run"]["sigma_pm_ratio"]}
            row.update({k: d["sample"].get(k) for k in SAMPLE_KEYS})
            key = tuple(row.values())
            if key in seen:
                raise ToolError("the run %s is kept twice (%s)" % (key, folder))
            seen.add(key)
            for column, _, _ in QUANTITIES:
                value = d["row"].get(column)
                row[column] = math.nan if value is None else float(value)
            rows.append(row)
    if not rows:
        raise ToolError("no row in %s: run the studies with --data first" % ", ".join(folders))
    return rows


def compare(rows, reference):
    """{(rho_m, sigma_pm_ratio): {increment: stats}} with, per quantity, the
    mean and standard deviation over the samples and the mean change from
    the same sample's run at the `reference` increment (samples that lack
    it left out of the change).  A point with no run at the reference
    increment yet (a study carried on in parts) is left out."""
    by_point = {}
    for r in rows:
        by_point.setdefault((r["rho_m"], r["sigma_pm_ratio"]), []).append(r)
    out = {}
    for point, runs in sorted(by_point.items()):
        base = {tuple(r[k] for k in SAMPLE_KEYS): r for r in runs if r["increment"] == reference}
        if not base:
            continue
        out[point] = {}
        for increment in sorted({r["increment"] for r in runs}):
            mine = [r for r in runs if r["increment"] == increment]
            stats = {"samples": len(mine)}
            for column, _, _ in QUANTITIES:
                values = np.array([r[column] for r in mine])
                changes = np.array([r[column] - base[s][column] for r in mine
                                    if (s := tuple(r[k] for k in SAMPLE_KEYS)) in base])
                stats[column] = {
                    "mean": float(np.mean(values)),
                    "std": float(np.std(values, ddof=1)) if len(values) > 1 else 0.0,
                    "change": float(np.mean(changes)) if len(changes) else math.nan}
            out[point][increment] = stats
    if not out:
        raise ToolError("no run at the reference increment %g at any point" % reference)
    return out


def without_reference(rows, table):
    """The points of `rows` that `compare` left out, as (rho_m, sigma_pm_ratio)."""
    return sorted({(r["rho_m"], r["sigma_pm_ratio"]) for r in rows} - set(table))


def within_scatter(stats, reference, column):
    """Whether the mean change of `column` is below the scatter between the
    samples at the reference increment (False without a scatter)."""
    scatter = stats[reference][column]["std"]
    return lambda increment: (scatter > 0 and
                              abs(stats[increment][column]["change"]) <= scatter)


def number(value, scale):
    v = value * scale
    if not math.isfinite(v):
        return "–"
    return "%.0f" % v if abs(v) >= 100 else "%.3g" % v


def markdown(table, reference):
    """The table as markdown: a block per point, a row per increment."""
    head = "| × increment | samples | " + " | ".join(label for _, label, _ in QUANTITIES) + " |"
    lines = []
    for (rho, ratio), stats in table.items():
        lines += ["", "ρ^m = %g, σ^pm/σ^p = %g: mean ± sd over the samples; in brackets the "
                  "mean change from the same sample at × 1 (* within the scatter at × 1)"
                  % (rho, ratio), "", head, "|---" * (len(QUANTITIES) + 2) + "|"]
        for increment, s in stats.items():
            cells = []
            for column, _, scale in QUANTITIES:
                c = s[column]
                cell = "%s ± %s" % (number(c["mean"], scale), number(c["std"], scale))
                if increment != reference:
                    star = "*" if within_scatter(stats, reference, column)(increment) else ""
                    cell += " (%+.3g%s)" % (c["change"] * scale, star)
                cells.append(cell)
            lines.append("| %g | %d | %s |" % (increment / reference, s["samples"],
                                                " | ".join(cells)))
    return "\n".join(lines)


def figure(table, reference):
    columns = QUANTITIES[:3] + (("broken", "broken bonds (all phases)", 1.0),)
    fig, axes = plt.subplots(1, len(columns), figsize=(4 * len(columns), 3.8))
    for ax, (column, label, scale) in zip(axes, columns):
        for (rho, ratio), stats in table.items():
            x = [i / reference for i in stats]
            if column == "broken":
                parts = [q for q, _, _ in QUANTITIES if q.startswith("broken_")]
                y = [sum(stats[i][q]["mean"] for q in parts) for i in stats]
                err = None
            else:
                y = [stats[i][column]["mean"] * scale for i in stats]
                err = [stats[i][column]["std"] * scale for i in stats]
            ax.errorbar(x, y, yerr=err, marker="o", capsize=3,
                        label=r"$\rho^m$ = %g, $\sigma^{pm}/\sigma^p$ = %g" % (rho, ratio))
        ax.set_xscale("log", base=2)
        ax.set_xlabel("increment / paper's (3e-4 a)")
        ax.set_title(label)
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    return fig


def run(args):
    require_folder_path(args.out, "the output folder (--out)")
    rows = read_rows(args.folders)
    table = compare(rows, args.reference)
    os.makedirs(args.out, exist_ok=True)
    columns = ("increment", "rho_m", "sigma_pm_ratio") + SAMPLE_KEYS + tuple(
        q for q, _, _ in QUANTITIES)
    write_table(os.path.join(args.out, "increment.csv"), rows, columns)
    write_json(os.path.join(args.out, "increment.json"), {
        "folders": list(args.folders), "reference_increment": args.reference,
        "points": [{"rho_m": p[0], "sigma_pm_ratio": p[1],
                    "by_increment": {"%g" % (i / args.reference): s for i, s in stats.items()}}
                   for p, stats in table.items()]})
    save_figure(figure(table, args.reference), os.path.join(args.out, "increment.png"), dpi=100)
    print(markdown(table, args.reference))
    for point in without_reference(rows, table):
        print("\nleft out: rho^m %g, sigma^pm/sigma^p %g has no run at the reference increment %g"
              % (point + (args.reference,)))
    print("\nincrement_table: %d runs -> %s" % (len(rows), args.out))


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("folders", metavar="DATA_DIR", nargs="+",
                            help="data folders of studies that differ only in fracture_increment")
    arg_parser.add_argument("--reference", type=float, default=PAPER_INCREMENT,
                            help="the increment the others are compared with (default 3e-4)")
    arg_parser.add_argument("--out", metavar="OUT_DIR", default="results/increment",
                            help="where increment.csv, .json and .png go")
    return cli.run(arg_parser, run, argv)
