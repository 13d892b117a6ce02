#!/usr/bin/python3
"""Where a lem_fracture run's solves, CG iterations and time went, by part of
its stress-strain curve (the table of docs/notes/paper-grid-data.md for the
516 line's rho^m = 0.06 row): to the peak, the gradual decrease down to
STRESS_1, the avalanche down to STRESS_2, and the tail to the end.  Stresses
in units of the run's sigma^[p] (the curve's stress_norm).

Usage: /usr/bin/python3 docs/notes/scripts/run_parts.py CURVE_CSV STRESS_1 STRESS_2
(CURVE_CSV: a result's curve.csv, or the curve.csv.part of a run in flight)
"""
import csv
import sys


def parts(rows, first_level, second_level):
    peak = max(range(len(rows)), key=lambda i: rows[i]["stress_before_norm"])
    ends = [peak]
    for level in (first_level, second_level):
        after = [i for i in range(ends[-1] + 1, len(rows)) if rows[i]["stress_norm"] <= level]
        ends.append(after[0] if after else len(rows) - 1)
    ends.append(len(rows) - 1)
    names = ["to the peak", f"decrease to {first_level}", f"avalanche to {second_level}", "tail"]
    start = {"step": 0, "solves": 0, "iterations": 0, "elapsed_s": 0.0, "broken": 0}
    out = []
    for name, end in zip(names, ends):
        row = rows[end]
        d = {k: row[k] - start[k] for k in start}
        out.append((name, row, d))
        start = {k: row[k] for k in start}
    return out


def main():
    path, first_level, second_level = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
    with open(path) as f:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]
    print("| part | ends at (stress, strain) | load steps | solves | CG its (a solve) "
          "| run time | bonds broken | at the end |")
    print("|---|---|---|---|---|---|---|---|")
    for name, row, d in parts(rows, first_level, second_level):
        per = d["iterations"] / d["solves"] if d["solves"] else 0
        print(f"| {name} | {row['stress_norm']:.3f}, {row['strain']:.3e} | {d['step']:.0f} "
              f"| {d['solves']:.0f} | {d['iterations']:.0f} ({per:.0f}) "
              f"| {d['elapsed_s'] / 60:.1f} min | {d['broken']:.0f} | {row['broken']:.0f} |")


if __name__ == "__main__":
    main()
