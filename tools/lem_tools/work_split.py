"""Where a lem_fracture run spent its solver work: up to the peak and after it.

For each RUN_DIR (a finished or interrupted lem_fracture output folder, with
its calibration/ folder if there is one) prints one row per stage: load
steps evaluated and with ruptures, global solves, CG iterations (per solve
and per step with ruptures), preconditioner builds and wall time. The
counts come from the cumulative columns of curve.csv (curve.csv.part while
a run is going); the peak is the summary's strain_at_peak, or for a
calibration the strain of the largest stress before ruptures. Used for the
relaxation benchmarks of docs/performance.md.
"""
import os

import numpy as np

from . import cli
from .errors import ToolError
from .results import read_csv, read_json

COUNTS = ("solves", "iterations", "pc_builds", "elapsed_s", "broken")
COLUMNS = ("step", "strain", "stress_before_norm", *COUNTS)


def split(curve, strain_at_peak):
    """{stage: counts} for the rows up to the peak strain and after it.

    `curve` maps the columns of COLUMNS to arrays (cumulative counts)."""
    after = curve["strain"] > strain_at_peak * (1 + 1e-9)
    stages = {}
    for name, rows in (("to the peak", ~after), ("after the peak", after)):
        index = np.flatnonzero(rows)
        if not len(index):
            continue
        first, last = index[0], index[-1]
        before = {k: curve[k][first - 1] if first > 0 else 0.0 for k in COUNTS}
        previous_broken = np.concatenate([[0.0], curve["broken"]])[index]
        stage = {k: curve[k][last] - before[k] for k in COUNTS}
        stage["evaluated_steps"] = len(index)
        stage["rupture_steps"] = int(np.count_nonzero(curve["broken"][index] > previous_broken))
        stages[name] = stage
    return stages


def read_run(directory):
    """[(label, stages)] for the calibration (if any) and the sample of a run."""
    found = []
    for label, folder in (("calibration", os.path.join(directory, "calibration")),
                          ("sample", directory)):
        path = next((os.path.join(folder, n) for n in ("curve.csv", "curve.csv.part")
                     if os.path.exists(os.path.join(folder, n))), None)
        if path is None:
            continue
        table = read_csv(path, COLUMNS, need_rows=True)
        curve = {k: table.numbers(k) for k in COLUMNS}
        summary = os.path.join(folder, "summary.json")
        if label == "sample" and os.path.exists(summary):
            peak = float(read_json(summary)["strain_at_peak"])
        else:
            peak = curve["strain"][int(np.argmax(curve["stress_before_norm"]))]
        found.append((label, split(curve, peak)))
    if not found:
        raise ToolError("%s: no curve.csv or curve.csv.part (not a lem_fracture output folder?)"
                        % directory)
    return found


def table(directories):
    """The report as Markdown lines."""
    lines = ["| run | stage | steps (with ruptures) | solves | CG its | its/solve | "
             "its per rupture step | PC builds | wall s |", "|---|---|---|---|---|---|---|---|---|"]
    for d in directories:
        for label, stages in read_run(d):
            for name, s in stages.items():
                lines.append("| %s | %s, %s | %d (%d) | %d | %d | %.1f | %.0f | %d | %.1f |" % (
                    d, label, name, s["evaluated_steps"], s["rupture_steps"], s["solves"],
                    s["iterations"], s["iterations"] / max(1, s["solves"]),
                    s["iterations"] / max(1, s["rupture_steps"]), s["pc_builds"], s["elapsed_s"]))
    return lines


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("run_dirs", metavar="RUN_DIR", nargs="+", help="lem_fracture -output_dir")
    return cli.run(p, lambda a: print("\n".join(table(a.run_dirs))), argv)
