"""Where a lem_fracture run spent its solver work: up to the peak and after it.

For each RUN_DIR (a finished or interrupted lem_fracture output folder, with
its calibration/ folder if there is one) prints one row per stage: load
steps evaluated and with ruptures, global solves, CG iterations (per solve
and per step with ruptures), preconditioner builds and wall time. The
counts come from the cumulative columns of curve.csv (curve.csv.part while
a run is going); the peak is the summary's strain_at_peak, or for a
calibration the strain of the largest stress before ruptures. Used for the
relaxation measurements of docs/notes/performance-relaxation-schemes.md.

With --margins M1,M2,... it also reads broken.csv and prints, after the
peak, the share of the ruptures whose force was within a margin m of their
threshold (force <= (1 + m) threshold) and the share of the batches (the
ruptures of one relaxation cycle) that hold such a rupture: the batches
that a local relaxation certified by a margin m must leave to a global
solve (docs/model/fracture-solver.md, "Relaxation schemes").

With --floor it also prints, stage by stage, the least work that the rules
of the protocol allow: every load step with ruptures ends on a global solve
to -ksp_rtol, so it costs at least one such solve. Its size is taken from
the stage's steps that broke one batch and needed one solve (the median of
their iterations), its time from the stage's seconds per CG iteration
(docs/notes/performance-complete-failure-tail.md).
"""
import os

import numpy as np

from . import cli
from .errors import ToolError
from .results import BROKEN, CURVE, SUMMARY, read_csv, read_json

COUNTS = ("solves", "iterations", "pc_builds", "elapsed_s", "broken")
COLUMNS = ("step", "strain", "stress_before_norm", "stress_norm", "cycles", *COUNTS)


def stage_rows(curve, strain_at_peak, tail_fraction=0.0):
    """[(stage, boolean mask of its rows)]: up to the peak strain and after it.

    `curve` maps the columns of COLUMNS to arrays (cumulative counts).  With
    tail_fraction f > 0 the rows after the peak are split again at the first
    equilibrium whose stress is below f times the peak stress (the tail)."""
    after = curve["strain"] > strain_at_peak * (1 + 1e-9)
    groups = [("to the peak", ~after), ("after the peak", after)]
    if tail_fraction > 0:
        peak_stress = curve["stress_norm"][~after].max() if (~after).any() else 0.0
        low = after & (curve["stress_norm"] < tail_fraction * peak_stress)
        tail = after & (np.cumsum(low) > 0)
        groups = [groups[0], ("peak to %g of it" % tail_fraction, after & ~tail),
                  ("below %g of the peak" % tail_fraction, tail)]
    return [(name, rows) for name, rows in groups if rows.any()]


def _deltas(curve, rows):
    """Per-row increments of the cumulative counts over the rows of `rows`."""
    index = np.flatnonzero(rows)
    return {k: curve[k][index] - np.concatenate([[0.0], curve[k]])[index] for k in COUNTS}


def counts(curve, rows):
    """The counts of the rows `rows`: COUNTS, evaluated and rupture steps."""
    delta = _deltas(curve, rows)
    stage = {k: float(delta[k].sum()) for k in COUNTS}
    stage["evaluated_steps"] = int(rows.sum())
    stage["rupture_steps"] = int(np.count_nonzero(delta["broken"] > 0))
    return stage


def split(curve, strain_at_peak, tail_fraction=0.0):
    """{stage: counts} for the stages of stage_rows."""
    return {name: counts(curve, rows)
            for name, rows in stage_rows(curve, strain_at_peak, tail_fraction)}


def floor(curve, rows):
    """The least work of the rows `rows` under the protocol's rules, or None.

    Every load step with ruptures ends on a global solve to -ksp_rtol; a
    step that broke one batch with one solve is that solve alone, so the
    median of their iterations is the cost of the closing solve.  Returns
    {rupture_steps, one_solve_steps, closing_iterations, seconds_per_iteration,
    iterations, seconds, floor_iterations, floor_seconds}: the actual counts
    beside the floor; None without a one-solve step."""
    delta = _deltas(curve, rows)
    ruptured = delta["broken"] > 0
    one_solve = ruptured & (curve["cycles"][rows] == 1) & (delta["solves"] == 1)
    iterations = float(delta["iterations"].sum())
    if not one_solve.any() or iterations <= 0:
        return None
    closing = float(np.median(delta["iterations"][one_solve]))
    per_iteration = float(delta["elapsed_s"].sum()) / iterations
    steps = int(ruptured.sum())
    return {"rupture_steps": steps, "one_solve_steps": int(one_solve.sum()),
            "closing_iterations": closing, "seconds_per_iteration": per_iteration,
            "iterations": iterations, "seconds": float(delta["elapsed_s"].sum()),
            "floor_iterations": steps * closing, "floor_seconds": steps * closing * per_iteration}


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


def read_run(directory, margins=(), tail_fraction=0.0):
    """[(label, stages, near, least)] for the calibration (if any) and the
    sample of a run; `near` is near_threshold's answer, or None without
    margins; `least` maps each stage to floor's answer."""
    found = []
    for label, folder in (("calibration", os.path.join(directory, "calibration")),
                          ("sample", directory)):
        path = _output_file(folder, CURVE)
        if path is None:
            continue
        table = read_csv(path, COLUMNS, need_rows=True)
        curve = {k: table.numbers(k) for k in COLUMNS}
        summary = os.path.join(folder, SUMMARY)
        if label == "sample" and os.path.exists(summary):
            peak = float(read_json(summary)["strain_at_peak"])
        else:
            peak = curve["strain"][int(np.argmax(curve["stress_before_norm"]))]
        near = None
        if margins:
            broken_path = _output_file(folder, BROKEN)
            if broken_path is None:
                raise ToolError("%s: no broken.csv or broken.csv.part" % folder)
            columns = ("step", "cycle", "strain", "force", "threshold")
            rows = read_csv(broken_path, columns)
            near = near_threshold({k: rows.numbers(k) for k in columns}, peak, margins)
        stages = stage_rows(curve, peak, tail_fraction)
        found.append((label, {name: counts(curve, rows) for name, rows in stages}, near,
                      {name: floor(curve, rows) for name, rows in stages}))
    if not found:
        raise ToolError("%s: no curve.csv or curve.csv.part (not a lem_fracture output folder?)"
                        % directory)
    return found


def table(directories, margins=(), with_floor=False, tail_fraction=0.0):
    """The report as Markdown lines."""
    runs = [(d, read_run(d, margins, tail_fraction)) for d in directories]
    lines = ["| run | stage | steps (with ruptures) | solves | CG its | its/solve | "
             "its per rupture step | PC builds | wall s |", "|---|---|---|---|---|---|---|---|---|"]
    for d, found in runs:
        for label, stages, _, _ in found:
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
            for label, _, (ruptures, batches, shares), _ in found:
                cells = " | ".join("%.0f %% / %.0f %%" % (100 * shares[m][0], 100 * shares[m][1])
                                   for m in margins)
                lines.append("| %s | %s | %d | %d | %s |" % (d, label, ruptures, batches, cells))
    if with_floor:
        lines += ["", "| run | stage | steps with ruptures | closing solve its (median of "
                  "one-solve steps) | s per CG it | CG its: actual / floor | wall s: actual / "
                  "floor |", "|---|---|---|---|---|---|---|"]
        for d, found in runs:
            for label, _, _, floors in found:
                for name, f in floors.items():
                    if f is None:
                        lines.append("| %s | %s, %s | no step of one batch and one solve "
                                     "| | | | |" % (d, label, name))
                        continue
                    lines.append("| %s | %s, %s | %d | %.0f (%d steps) | %.4f | %d / %d | "
                                 "%.0f / %.0f |" % (
                                     d, label, name, f["rupture_steps"], f["closing_iterations"],
                                     f["one_solve_steps"], f["seconds_per_iteration"],
                                     f["iterations"], f["floor_iterations"], f["seconds"],
                                     f["floor_seconds"]))
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


def tail_fraction(f):
    """--tail F: a fraction of the peak stress in [0, 1) (0: no tail stage)."""
    if not 0 <= f < 1:
        raise ToolError("--tail %g: give a fraction of the peak stress in [0, 1), e.g. 0.1" % f)
    return f


def main(argv=None):
    p = cli.parser(__doc__)
    p.add_argument("run_dirs", metavar="RUN_DIR", nargs="+", help="lem_fracture -output_dir")
    p.add_argument("--margins", default="",
                   help="comma-separated margins m (fractions of a threshold): also report the "
                        "post-peak ruptures and batches within m of a threshold")
    p.add_argument("--floor", action="store_true",
                   help="also report the least work per stage that the protocol's rules allow: "
                        "one solve to -ksp_rtol per load step with ruptures")
    p.add_argument("--tail", type=float, default=0.0, metavar="F",
                   help="split the stage after the peak at the first equilibrium below F times "
                        "the peak stress (e.g. 0.1)")
    return cli.run(p, lambda a: print("\n".join(
        table(a.run_dirs, margin_list(a.margins) if a.margins else (), a.floor,
              tail_fraction(a.tail)))), argv)
