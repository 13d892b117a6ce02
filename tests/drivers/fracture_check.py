#!/usr/bin/python3
"""Value checks of lem_fracture results: one checker for the fracture tests.

  fracture_check.py fcc  --run "CMD" --dir D --cells N --increment d --break-strain e [--k k]
      runs CMD (an mpiexec line ending in lem_fracture) on an FCC lattice and
      compares every result with its closed form (docs/developer/testing.md).
  fracture_check.py gold --run "CMD" --dir D --gold G [--tolerances T] [-- args]
      runs CMD with args and compares the results with G/summary.json and
      G/curve.csv within the tolerances of T (default G/tolerances.json,
      each justified there).
  fracture_check.py write-gold --dir D --gold G
      stores the results of run D as the gold (after a deliberate change).
  fracture_check.py curves A B TOL
      rows of A's curve found in B: same broken counts, stresses within TOL
      of B's peak (used by check_fracture.sh).
  fracture_check.py ruptures A B TOL [--pre-peak TOL2] [--parts P...]
      runs A and B break the same bonds in the same order (step, cycle, bond
      id of broken.csv), naming the first rupture that differs, and their
      curves agree within TOL of the peak as functions of the strain (their
      evaluated steps may differ), within TOL2 up to the peak; with --parts,
      the subfolders P of A and B in turn (calibration .).
  fracture_check.py spec --run "CMD" --dir D [--energy-bound B] -- args
      runs CMD with args (a sample file's run with its calibration) and checks
      its outputs against the sample file and docs/model/fracture.md: one a
      for thresholds and the load increment (the mean length of every row of
      /bonds), bond ids that are rows of /bonds (broken.csv, fields.h5,
      elastic.h5), the energy balance W = E + G + R, and the calibration's
      stop (no step ends with a bond over its threshold; the last is the
      first whose stress is below 0.9 of the peak).

LEM_TEST_EXTRA_ARGS (environment) is appended to the command line of fcc and
gold runs: it exists to show that a test fails on a changed protocol, e.g.
LEM_TEST_EXTRA_ARGS="-fracture_increment 2.9e-4" ctest -R gold.
"""
import argparse
import csv
import json
import math
import os
import shlex
import shutil
import subprocess
import sys

import numpy as np

# Columns of curve.csv kept in the gold (the rest are solver counters and times).
CURVE_COLUMNS = ("step", "strain", "stress_before_norm", "stress_norm", "broken")


class Checker:
    """Collects comparisons, prints one line each, and fails at the end."""

    def __init__(self):
        self.failed = []

    # Each comparison is written so that it holds only for a finite number
    # (summary.json writes a NaN or an infinity as null): a missing value, a
    # null or a NaN fails it.
    def close(self, name, value, expected, rtol=0.0, atol=0.0):
        if self._number(name, value):
            ok = abs(value - expected) <= atol + rtol * abs(expected)
            self._line(ok, name, f"{value:.10g}", f"{expected:.10g}",
                       f"rtol {rtol:g} atol {atol:g}")

    def equal(self, name, value, expected):
        self._line(value == expected, name, str(value), str(expected), "exact")

    def at_most(self, name, value, bound):
        if self._number(name, value):
            self._line(value <= bound, name, f"{value:.3g}", f"<= {bound:g}", "bound")

    def at_least(self, name, value, bound):
        if self._number(name, value):
            self._line(value >= bound, name, f"{value:.3g}", f">= {bound:g}", "bound")

    def _number(self, name, value):
        ok = finite_number(value)
        if not ok:
            self._line(False, name, repr(value), "a finite number", "present")
        return ok

    def _line(self, ok, name, got, want, how):
        print(f"{'ok  ' if ok else 'FAIL'} {name:32s} {got:>20s}  expected {want:>20s}  ({how})")
        if not ok:
            self.failed.append(name)

    def finish(self):
        if self.failed:
            sys.exit(f"FAIL: {len(self.failed)} check(s): {', '.join(self.failed)}")
        print("all checks passed")


def finite_number(value):
    return (isinstance(value, (int, float, np.number)) and not isinstance(value, bool)
            and math.isfinite(value))


def read_curve(directory):
    lines = (line for line in open(os.path.join(directory, "curve.csv")) if not line.startswith("#"))
    rows = list(csv.DictReader(lines))
    return {k: np.array([float(r[k]) for r in rows]) for k in CURVE_COLUMNS}


def read_summary(directory):
    with open(os.path.join(directory, "summary.json")) as f:
        return json.load(f)


def read_broken(directory):
    with open(os.path.join(directory, "broken.csv")) as f:
        return list(csv.DictReader(f))


def run(command, directory, args):
    """Run the driver; a failed run fails the test with its last lines."""
    extra = shlex.split(os.environ.get("LEM_TEST_EXTRA_ARGS", ""))
    if extra:
        print(f"note: LEM_TEST_EXTRA_ARGS adds {' '.join(extra)}")
    shutil.rmtree(directory, ignore_errors=True)
    os.makedirs(directory)
    cmd = shlex.split(command) + args + ["-output_dir", directory] + extra
    with open(os.path.join(directory, "log"), "w") as log:
        status = subprocess.call(cmd, stdout=log, stderr=subprocess.STDOUT)
    if status != 0:
        tail = open(os.path.join(directory, "log")).read().splitlines()[-5:]
        sys.exit(f"FAIL: exit status {status}: {' '.join(cmd)}\n" + "\n".join(tail))


# ---------------------------------------------------------------- FCC
def fcc(a):
    """Uniaxial tension of the FCC block of make_fcc_lattice (bond length 1,
    face bonds k/2, edge bonds k/4), free lateral faces: the affine field
    eps_xx = eps_yy = -eps/3 is exact, so a bond along n stretches by
    n.eps.n: -eps/3 for the two <110> directions in the xy plane, +eps/3 for
    the four with a z component."""
    n = a.cells
    side = n * math.sqrt(2.0)          # cube side c = a sqrt 2, a = 1
    volume = side ** 3
    young = 2.0 * math.sqrt(2.0) / 3.0  # k/a units (docs/model/theory.md)
    strain = lambda step: step * a.increment / side
    # A bond of the four inclined directions breaks when eps/3 > break strain.
    critical = 3.0 * a.break_strain * side / a.increment
    margin = abs(critical - round(critical))
    if margin < 1e-3:
        sys.exit(f"bad test parameters: the critical step {critical} is within {margin} of an "
                 "integer, so solver noise would decide the rupture step")
    first = math.floor(critical) + 1
    sites = ((2 * n + 1) ** 3 + 1) // 2          # grid points with an even coordinate sum
    per_direction = 2 * n * n * (2 * n + 1)        # bonds along one <110> direction
    inclined = 4 * per_direction

    run(a.run, a.dir, ["-lattice_type", "fcc", "-fcc_cells", str(n), "-lattice_k", str(a.k),
                       "-fracture_increment", repr(a.increment),
                       "-lattice_break_strain", repr(a.break_strain)])
    s, c, broken = read_summary(a.dir), read_curve(a.dir), read_broken(a.dir)
    check = Checker()
    print(f"FCC {n}^3 cells: {sites} nodes, {6 * per_direction} bonds; first rupture at step "
          f"{first} (critical {critical:.4f}); E = {young:.9f} k/a")
    check.equal("nodes", s["nodes"], sites)
    check.equal("active_bonds", s["active_bonds"], 6 * per_direction)
    # The solve is converged to rtol 1e-8: moduli and stresses to 1e-6.
    check.close("E_eff [k/a]", s["E_eff"], young, rtol=1e-6)
    # Before the first rupture the curve is the straight line E eps.
    step1 = int(np.argmax(c["step"] == 1))
    check.equal("first curve row is step 1", int(c["step"][0]), 1)
    check.close("stress at step 1", c["stress_norm"][step1], young * strain(1), rtol=1e-6)
    last_idle = np.flatnonzero(c["step"] == first - 1)
    check.equal("curve has step first-1", len(last_idle), 1)
    if len(last_idle):
        check.close("stress at step first-1", c["stress_norm"][last_idle[0]],
                    young * strain(first - 1), rtol=1e-6)
    # The step of the ruptures: all inclined bonds go at once, in one cycle.
    check.equal("rupture steps", s["rupture_steps"], 1)
    check.equal("relaxation cycles", s["relaxation_cycles"], 1)
    check.equal("last step", s["steps"], first)
    check.equal("broken bonds", s["broken"], inclined)
    check.equal("broken_p (every bond is p)", s["broken_p"], inclined)
    check.equal("rows of broken.csv", len(broken), inclined)
    check.equal("their steps", sorted({int(r["step"]) for r in broken}), [first])
    check.equal("their cycle", sorted({int(r["cycle"]) for r in broken}), [0])
    # Every broken bond is an inclined one: its midpoint lies half-way between
    # two z layers of sites (z / (h/2) odd, h = c/2 the layer spacing), while
    # the in-plane bonds lie in a layer.
    h = side / (2 * n)
    odd = sum(1 for r in broken if round(float(r["z"]) / (h / 2)) % 2 == 1)
    check.equal("broken bonds between z layers", odd, inclined)
    # Force / threshold the same for face, edge and bulk bonds: no boundary
    # effect.  A single bond force carries the solver error times the
    # condition number (spread measured 1.5e-6 at rtol 1e-8); a boundary
    # effect would be of order one on the edge bonds.
    ratio = np.array([float(r["force"]) / float(r["threshold"]) for r in broken])
    expected_ratio = strain(first) / 3.0 / a.break_strain
    check.close("largest force/threshold", ratio.max(), expected_ratio, rtol=1e-5)
    check.close("smallest force/threshold", ratio.min(), expected_ratio, rtol=1e-5)
    last = np.flatnonzero(c["step"] == first)
    check.equal("curve has step first", len(last), 1)
    if len(last):
        i = last[0]
        check.close("stress before the ruptures", c["stress_before_norm"][i],
                    young * strain(first), rtol=1e-6)
        check.close("stress after the ruptures", c["stress_norm"][i], 0.0, atol=1e-12)
    # The peak is the last state without an over-critical bond (step first-1).
    check.close("sigma_eff [k/a]", s["sigma_eff"], young * strain(first - 1), rtol=1e-6)
    check.close("strain_at_peak", s["strain_at_peak"], strain(first - 1), rtol=1e-9)
    check.equal("end_reason", s["end_reason"], "no piece joins the bottom to the top face")
    # Energies in k a^2: the work up to the step of the ruptures is all released.
    energy = 0.5 * young * a.k * strain(first) ** 2 * volume
    check.close("work [k a^2]", s["work"], energy, rtol=1e-6)
    check.close("released_energy [k a^2]", s["released_energy"], energy, rtol=1e-6)
    check.close("stored_energy", s["stored_energy"], 0.0, atol=1e-12 * energy)
    check.at_most("energy_balance_error", s["energy_balance_error"], 1e-6)
    check.equal("warnings", s.get("warnings"), [])
    check.finish()


# ---------------------------------------------------------------- gold
KEPT = ("E_eff", "sigma_eff", "sigma_hom", "E_hom", "strain_at_peak", "final_strain", "work",
        "energy_balance_error", "ground_energy", "mean_bond_length", "n_b", "broken", "broken_p", "broken_m", "broken_pp",
        "broken_pm", "steps", "end_reason", "active_bonds", "nodes", "increment_over_a",
        "break_rule")


def stress_at(curve, strains):
    """Stress (after the ruptures of a step) of the piecewise-linear curve at
    given strains: between two evaluated rows the lattice is linear, and a
    row's jump belongs to its strain."""
    x = np.concatenate([[0.0], np.repeat(curve["strain"], 2)])
    y = np.concatenate([[0.0], np.column_stack([curve["stress_before_norm"],
                                                curve["stress_norm"]]).ravel()])
    # np.interp takes the last of equal abscissae: the stress after the jump.
    return np.interp(strains, x, y, right=np.nan)


def curve_differences(run_curve, gold_curve):
    """Largest difference up to the peak and mean difference over the whole
    gold curve, both relative to the gold peak."""
    peak = gold_curve["stress_norm"].max()
    ipeak = int(np.argmax(gold_curve["stress_norm"]))
    grid = gold_curve["strain"]
    diff = np.abs(stress_at(run_curve, grid) - gold_curve["stress_norm"]) / peak
    diff = np.where(np.isnan(diff), 1.0, diff)  # the run ended early: fully off
    return diff[: ipeak + 1].max(), diff.mean()


def gold(a):
    tol = json.load(open(a.tolerances or os.path.join(a.gold, "tolerances.json")))
    run(a.run, a.dir, a.args)
    s, want = read_summary(a.dir), json.load(open(os.path.join(a.gold, "summary.json")))
    check = Checker()
    for k in ("end_reason", "active_bonds", "nodes", "increment_over_a", "break_rule"):
        check.equal(k, s[k], want[k])
    for k, t in tol["relative"].items():
        check.close(k, s.get(k), want[k], rtol=t)
    for k, least in tol.get("at_least", {}).items():  # the scheme under test did its work
        check.at_least(k, s.get(k), least)
    for k, t in tol.get("absolute", {}).items():
        check.close(k, s.get(k), want[k], atol=t)
    for k, t in tol["counts"].items():
        check.close(k, s.get(k), want[k], atol=max(t["at_least"], t["fraction"] * want[k]))
    if "peak_increments" in tol:  # the strain at the peak, in load steps
        gold_curve = read_curve(a.gold)
        per_step = gold_curve["strain"][0] / gold_curve["step"][0]
        got = s.get("strain_at_peak")
        off = (round(abs(got - want["strain_at_peak"]) / per_step, 6)
               if finite_number(got) else got)
        check.at_most("strain at the peak, steps off", off, tol["peak_increments"])
    check.at_most("energy_balance_error", s.get("energy_balance_error"),
                  tol["energy_balance_error"])
    # A sound run at the paper's increment warns of nothing (docs/model/fracture.md, "Warnings").
    check.equal("warnings", s.get("warnings"), [])
    pre_peak, mean = curve_differences(read_curve(a.dir), read_curve(a.gold))
    check.at_most("curve up to the peak, max", pre_peak, tol["curve_pre_peak_max"])
    check.at_most("whole curve, mean", mean, tol["curve_mean"])
    check.finish()


def write_gold(a):
    os.makedirs(a.gold, exist_ok=True)
    s = read_summary(a.dir)
    with open(os.path.join(a.gold, "summary.json"), "w") as f:
        json.dump({k: s[k] for k in KEPT}, f, indent=1)
        f.write("\n")
    c = read_curve(a.dir)
    with open(os.path.join(a.gold, "curve.csv"), "w") as f:
        f.write(",".join(CURVE_COLUMNS) + "\n")
        for i in range(len(c["step"])):
            f.write(f"{int(c['step'][i])},{c['strain'][i]:.12e},{c['stress_before_norm'][i]:.12e},"
                    f"{c['stress_norm'][i]:.12e},{int(c['broken'][i])}\n")
    print(f"gold written to {a.gold} from {a.dir}")


# ---------------------------------------------------------------- curves
def curves(a):
    """Rows of A's curve present in B agree (same step numbers).  A step of A
    without ruptures may be missing in B: a run whose load steps end on
    decided fields predicts the next step from the forces at the top of their
    error, and so evaluates a few steps more where nothing breaks."""
    def rows(path):
        lines = (line for line in open(path) if not line.startswith("#"))
        return {int(r["step"]): r for r in csv.DictReader(lines)}
    first, second = rows(os.path.join(a.a, "curve.csv")), rows(os.path.join(a.b, "curve.csv"))
    peak = max(abs(float(r["stress_norm"])) for r in second.values())
    if not (math.isfinite(peak) and peak > 0):
        sys.exit(f"FAIL: the peak stress of {a.b} is {peak}")
    worst, skipped = 0.0, 0
    for step, r in first.items():
        if step not in second and r["cycles"] == "0":
            skipped += 1
            continue
        if step not in second:
            sys.exit(f"FAIL: step {step} (with ruptures) missing in {a.b}")
        for k in ("stress_before_norm", "stress_norm"):
            # np.max, unlike max(), keeps a NaN, which then fails below.
            worst = np.max([worst, abs(float(r[k]) - float(second[step][k])) / peak])
        if r["broken"] != second[step]["broken"]:
            sys.exit(f"FAIL: broken count differs at step {step}")
    print(f"curves: {len(first) - skipped} rows compared ({skipped} steps without ruptures only "
          f"in A), largest stress difference {worst:.2e} of the peak")
    if not worst <= a.tol:
        sys.exit(f"FAIL: stress differs by {worst:.2e} of the peak (tolerance {a.tol})")


# ---------------------------------------------------------------- ruptures
def ruptures(a):
    """The whole rupture sequence of A equals B's; then the curves."""
    def text(r):
        return (f"step {r['step']} cycle {r['cycle']} bond {r['bond_id']} ({r['phase']}, "
                f"force {float(r['force']):.6e}, threshold {float(r['threshold']):.6e})")

    def key(r):
        return int(r["step"]), int(r["cycle"]), int(r["bond_id"])
    first, second = read_broken(a.a), read_broken(a.b)
    for i in range(max(len(first), len(second))):
        x = first[i] if i < len(first) else None
        y = second[i] if i < len(second) else None
        if x and y and key(x) == key(y):
            continue
        sys.exit(f"FAIL: rupture {i + 1} of {len(first)} / {len(second)} differs\n"
                 f"  {a.a}: {text(x) if x else 'none (the run ends)'}\n"
                 f"  {a.b}: {text(y) if y else 'none (the run ends)'}")
    ca, cb = read_curve(a.a), read_curve(a.b)
    for name, c in ((a.a, ca), (a.b, cb)):
        for k in ("strain", "stress_before_norm", "stress_norm"):
            if not np.isfinite(c[k]).all():
                sys.exit(f"FAIL: {name}/curve.csv: {k} is not finite at step "
                         f"{int(c['step'][~np.isfinite(c[k])][0])}")
    peak = cb["stress_norm"].max()
    strain_at_peak = cb["strain"][np.argmax(cb["stress_norm"])]

    def off(x, y):  # |x - y| at y's rows, split at the peak strain
        d = np.abs(stress_at(x, y["strain"]) - y["stress_norm"]) / peak
        return np.nanmax(d), np.nanmax(d[y["strain"] <= strain_at_peak])
    (whole, rise), (whole2, rise2) = off(ca, cb), off(cb, ca)
    whole, rise = max(whole, whole2), max(rise, rise2)
    print(f"ruptures: the same {len(first)} in the same order; curves ({len(ca['step'])} and "
          f"{len(cb['step'])} rows) within {rise:.2e} of the peak up to it, {whole:.2e} in all")
    if not (rise <= a.pre_peak and whole <= a.tol):
        sys.exit(f"FAIL: stresses differ by more than {a.pre_peak:g} of the peak up to it "
                 f"or {a.tol:g} in all")


def ruptures_of_parts(a):
    """ruptures() on each of the --parts of A and B (a run and its calibration)."""
    top_a, top_b = a.a, a.b
    for part in a.parts:
        a.a, a.b = os.path.join(top_a, part), os.path.join(top_b, part)
        ruptures(a)


# ---------------------------------------------------------------- spec
def option_values(args):
    """-name value pairs of a command line."""
    return {args[i]: args[i + 1] for i in range(len(args) - 1) if args[i].startswith("-")}


def spec(a):
    """A sample file's run against the sample file and the documented rules."""
    import h5py  # here: the other checks run without it
    run(a.run, a.dir, a.args)
    options = option_values(a.args)
    with h5py.File(options["-sample_file"], "r") as f:
        ends = f["bonds/connectivity"][:]
        phase = f["bonds/phase"][:]
        xyz = f["nodes/coordinates"][:]
        height = f.attrs["box_hi"][2] - f.attrs["box_lo"][2]
    length = np.linalg.norm(xyz[ends[:, 1]] - xyz[ends[:, 0]], axis=1)
    mean_length = length.mean()  # the paper's a: every element, void bonds included
    check = Checker()
    s = read_summary(a.dir)

    # 1. One a: the summary's, the load increment's and the thresholds'.
    check.close("a = mean length of /bonds", s.get("mean_bond_length", math.nan), mean_length,
                rtol=1e-9)
    curve = read_curve(a.dir)
    check.close("strain per load step / (3e-4 a / H)", curve["strain"][0] / curve["step"][0],
                s["increment_over_a"] * mean_length / height, rtol=1e-9)
    sigma = {"p": 0.01, "m": 0.01, "pp": 0.0, "pm": 0.006}  # the defaults (docs/model)
    for name in sigma:
        sigma[name] = float(options.get(f"-phase_sigma_{name}", sigma[name]))
    broken = read_broken(a.dir)
    worst = max(abs(float(r["threshold"]) - sigma[r["phase"]] * mean_length ** 2) /
                (sigma["p"] * mean_length ** 2) for r in broken)
    check.at_most("thresholds f - sigma a^2, of f^p", worst, 1e-12)

    # 2. Bond ids are rows of the sample's /bonds: the same phase and ends.
    names = ("p", "m", "v", "pp", "pm")  # tools/lem_tools/phases.py
    rows = np.array([int(r["bond_id"]) for r in broken])
    inside = (rows >= 0) & (rows < len(ends))
    check.equal("broken.csv bond ids in /bonds", int(inside.sum()), len(rows))
    rows = rows[inside]
    middle = 0.5 * (xyz[ends[rows, 0]] + xyz[ends[rows, 1]])
    given = np.array([[float(r[k]) for k in "xyz"] for r, ok in zip(broken, inside) if ok])
    joined = np.all(np.abs(middle - given) <= 1e-7 * height, axis=1)
    joined &= np.array([names[phase[i]] == r["phase"] for i, r in zip(rows, broken)])
    check.equal("ruptures joined to /bonds (midpoint, phase)", int(joined.sum()), len(broken))
    for stem in ("fields", "elastic"):
        with h5py.File(os.path.join(a.dir, stem + ".h5"), "r") as f:
            ids = f["bonds/id"][:]
            node_ids = f["nodes/id"][:][f["bonds/connectivity"][:]]
        same = np.sort(node_ids, axis=1) == np.sort(ends[ids], axis=1)
        check.equal(f"{stem}.h5 bonds whose ends are their /bonds row's",
                    int(np.all(same, axis=1).sum()), len(ids))

    # 3. The energy balance: W = E + G + R, G the ground springs'.
    ground = s.get("ground_energy", math.nan)
    check.at_least("ground_energy / work", ground / s["work"], 1e-12)
    balance = abs(s["work"] - s["stored_energy"] - ground - s["released_energy"]) / s["work"]
    check.close("|W - E - G - R| / W as the summary's", balance, s["energy_balance_error"],
                atol=1e-9)  # the summary's 10 digits
    check.at_most("energy_balance_error", s["energy_balance_error"], a.energy_bound)

    # 4. The calibration stops where docs/model/fracture-calibration.md says: in the
    # first load step whose stress falls below 0.9 of the peak, and every
    # step before it ends with no bond over its threshold.  A bond broken in
    # the first cycle of step n had, at step n - 1 (the same damage, the
    # field scaled by (n - 1)/n), the force force (n - 1)/n.
    cal = os.path.join(a.dir, "calibration")
    c = read_curve(cal)
    level, top = 0.9 * c["stress_norm"].max(), int(np.argmax(c["stress_norm"]))
    check.equal("calibration steps after the peak below 0.9 of it",
                [int(n) for n in c["step"][top:][c["stress_norm"][top:] < level]],
                [int(c["step"][-1])])
    late = [r for r in read_broken(cal) if r["cycle"] == "0" and int(r["step"]) > 1 and
            float(r["force"]) * (int(r["step"]) - 1) / int(r["step"]) >
            float(r["threshold"]) * (1 + 1e-4)]
    for r in late[:3]:
        print(f"     over its threshold at step {int(r['step']) - 1}: bond {r['bond_id']}, "
              f"force {float(r['force']) * (int(r['step']) - 1) / int(r['step']):.6e}, "
              f"threshold {float(r['threshold']):.6e}")
    check.equal("calibration bonds left over threshold", len(late), 0)
    check.finish()


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="what", required=True)
    q = sub.add_parser("fcc")
    q.add_argument("--run", required=True)
    q.add_argument("--dir", required=True)
    q.add_argument("--cells", type=int, required=True)
    q.add_argument("--increment", type=float, required=True)
    q.add_argument("--break-strain", type=float, required=True)
    q.add_argument("--k", type=float, default=1.0)
    q.set_defaults(func=fcc)
    q = sub.add_parser("gold")
    q.add_argument("--run", required=True)
    q.add_argument("--dir", required=True)
    q.add_argument("--gold", required=True)
    q.add_argument("--tolerances")
    q.add_argument("args", nargs="*")
    q.set_defaults(func=gold)
    q = sub.add_parser("write-gold")
    q.add_argument("--dir", required=True)
    q.add_argument("--gold", required=True)
    q.set_defaults(func=write_gold)
    q = sub.add_parser("curves")
    q.add_argument("a")
    q.add_argument("b")
    q.add_argument("tol", type=float)
    q.set_defaults(func=curves)
    q = sub.add_parser("ruptures")
    q.add_argument("a")
    q.add_argument("b")
    q.add_argument("tol", type=float)
    q.add_argument("--pre-peak", type=float, default=math.inf)
    q.add_argument("--parts", nargs="+", default=["."],
                   help="subfolders of A and B compared in turn (calibration .)")
    q.set_defaults(func=ruptures_of_parts)
    q = sub.add_parser("spec")
    q.add_argument("--run", required=True)
    q.add_argument("--dir", required=True)
    q.add_argument("--energy-bound", type=float, default=1e-6)
    q.add_argument("args", nargs="*")
    q.set_defaults(func=spec)
    a = p.parse_args()
    a.func(a)


if __name__ == "__main__":
    main()
