"""Where a lem_fracture run spent its solver work: up to the peak and after it.

For each RUN_DIR (a finished or interrupted lem_fracture output folder, with
its calibration/ folder if there is one) prints one row per stage: load
steps evaluated and with ruptures, global solves, CG iterations (per solve
and per step with ruptures), preconditioner builds and wall time. The
counts come from the cumulative columns of curve.csv (curve.csv.part while
a run is going); the peak is the summary's strain_at_peak, or for a
calibration the strain of the largest stress before ruptures. Used for the
relaxation benchmarks of docs/performance.md.

With --margins M1,M2,... it also reads broken.csv and prints, after the
peak, the share of the ruptures whose force was within a margin m of their
threshold (force <= (1 + m) threshold) and the share of the batches (the
ruptures of one relaxation cycle) that hold such a rupture: the batches
that a local relaxation certified by a margin m must leave to a global
solve (docs/fracture.md, "Relaxation schemes").
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


def near_threshold(broken, strain_at_peak, margins):
    """Ruptures after the peak and how close to their thresholds they were.

    `broken` maps step, cycle, strain, force, threshold to arrays (the
    columns of broken.csv).  Returns (ruptures, batches, {margin: (share of
    the ruptures within it, share of the batches holding one)}); bonds of
    zero threshold (bare contacts) are never within a margin."""
    after = broken["strain"] > strain_at_peak * (1 + 1e-9)
    threshold = broken["threshold"][after]
    ratio = np.full(threshold.shape, np.inf)
    positive = threshold > 0
    ratio[positive] = broken["force"][after][positive] / threshold[positive]
    batch_of = np.unique(np.stack([broken["step"][after], broken["cycle"][after]], axis=1),
                         axis=0, return_inverse=True)[1].ravel()
    batches = int(batch_of.max()) + 1 if batch_of.size else 0
    closest = np.full(batches, np.inf)
    np.minimum.at(closest, batch_of, ratio)
    shares = {}
    for m in margins:
        shares[m] = (float(np.mean(ratio <= 1 + m)) if ratio.size else 0.0,
                     float(np.mean(closest <= 1 + m)) if batches else 0.0)
    return int(ratio.size), batches, shares


def _output_file(folder, name):
    """folder/name, or folder/name.part while the run is going; None if neither."""
    return next((os.path.join(folder, n) for n in (name, name + ".part")
                 if os.path.exists(os.path.join(folder, n))), None)


def read_run(directory, margins=()):
    """[(label, stages, near)] for the calibration (if any) and the sample of
    a run; `near` is near_threshold's answer, or None without margins."""
    found = []
    for label, folder in (("calibration", os.path.join(directory, "calibration")),
                          ("sample", directory)):
        path = _output_file(folder, "curve.csv")
        if path is None:
            continue
        table = read_csv(path, COLUMNS, need_rows=True)
        curve = {k: table.numbers(k) for k in COLUMNS}
        summary = os.path.join(folder, "summary.json")
        if label == "sample" and os.path.exists(summary):
            peak = float(read_json(summary)["strain_at_peak"])
        else:
            peak = curve["strain"][int(np.argmax(curve["stress_before_norm"]))]
        near = None
        if margins:
            broken_path = _output_file(folder, "broken.csv")
            if broken_path is None:
                raise ToolError("%s: no broken.csv or broken.csv.part" % folder)
            columns = ("step", "cycle", "strain", "force", "threshold")
            rows = read_csv(broken_path, columns)
            near = near_threshold({k: rows.numbers(k) for k in columns}, peak, margins)
        found.append((label, split(curve, peak), near))
    if not found:
        raise ToolError("%s: no curve.csv or curve.csv.part (not a lem_fracture output folder?)"
                        % directory)
    return found


def table(directories, margins=()):
    """The report as Markdown lines."""
    runs = [(d, read_run(d, margins)) for d in directories]
    lines = ["| run | stage | steps (with ruptures) | solves | CG its | its/solve | "
             "its per rupture step | PC builds | wall s |", "|---|---|---|---|---|---|---|---|---|"]
    for d, found in runs:
        for label, stages, _ in found:
            for name, s in stages.items():
                lines.append("| %s | %s, %s | %d (%d) | %d | %d | %.1f | %.0f | %d | %.1f |" % (
                    d, label, name, s["evaluated_steps"], s["rupture_steps"], s["solves"],
                    s["iterations"], s["iterations"] / max(1, s["solves"]),
                    s["iterations"] / max(1, s["rupture_steps"]), s["pc_builds"], s["elapsed_s"]))
    if margins:
        lines += ["", "| run | stage | ruptures after the peak | batches | " + " | ".join(
            "within %g: ruptures / batches" % m for m in margins) + " |",
            "|---|---|---|---|" + "---|" * len(margins)]
        for d, found in runs:
            for label, _, (ruptures, batches, shares) in found:
                lines.append("| %s | %s | %d | %d | %s |" % (d, label, ruptures, batches, " | ".join(
                    "%.0f %% / %.0f %%" % (100 * shares[m][0], 100 * shares[m][1])
                    for m in margins)))
    return lines


def margin_list(text):
    """0.01,0.03 -> (0.01, 0.03); each margin >= 0."""
    try:
        margins = tuple(float(x) for x in text.split(","))
    except ValueError:
        raise ToolError("--margins %r: give numbers separated by commas, e.g. 0.01,0.05" % text)
    if any(not m >= 0 for m in margins):
        raise ToolError("--margins %r: margins are fractions of a threshold, >= 0" % text)
    return margins


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("run_dirs", metavar="RUN_DIR", nargs="+", help="lem_fracture -output_dir")
    p.add_argument("--margins", default="",
                   help="comma-separated margins m (fractions of a threshold): also report the "
                        "post-peak ruptures and batches within m of a threshold")
    return cli.run(p, lambda a: print("\n".join(
        table(a.run_dirs, margin_list(a.margins) if a.margins else ()))), argv)
