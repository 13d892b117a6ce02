#!/usr/bin/python3
"""Plot E_eff/E^[m] against the mesh density L_n (paper fig. 6).

Usage: /usr/bin/python3 tools/plot_convergence.py RESULTS_DIR [RESULTS_DIR_2 LABEL_2]
Reads RESULTS_DIR/convergence.csv and fit.csv written by lem_convergence and
writes RESULTS_DIR/convergence.png.  An optional second run (for example with
-inclusion_void_bonds both) is drawn with open symbols.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_table(path):
    with open(path) as f:
        rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
    if not rows:
        sys.exit(f"error: {path} has no data rows")
    return rows


def hashin_shtrikman(fraction, ratio, nu=0.25):
    """Two-phase HS estimate with the matrix as reference (lower bound for
    stiffer inclusions, upper bound for pores); E normalised by E_matrix."""
    E1 = 1.0
    k1, m1 = E1 / (3 * (1 - 2 * nu)), E1 / (2 * (1 + nu))
    k2, m2 = ratio * k1, ratio * m1
    f1, f2 = 1 - fraction, fraction
    inv = lambda x: float("inf") if x == 0 else 1.0 / x  # noqa: E731
    k = k1 + f2 / (inv(k2 - k1) + 3 * f1 / (3 * k1 + 4 * m1))
    m = m1 + f2 / (inv(m2 - m1) + 6 * f1 * (k1 + 2 * m1) / (5 * m1 * (3 * k1 + 4 * m1)))
    return 9 * k * m / (3 * k + m)


def main():
    if len(sys.argv) not in (2, 4):
        sys.exit(__doc__)
    runs = [(sys.argv[1], "any-end void rule")]
    if len(sys.argv) == 4:
        runs.append((sys.argv[2], sys.argv[3]))
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for k, (directory, label) in enumerate(runs):
        rows = read_table(f"{directory}/convergence.csv")
        fits = {r["case"]: r for r in read_table(f"{directory}/fit.csv")}
        ln = [float(r["Ln"]) for r in rows]
        xs = [0.0] + ln
        for case, column, colour in (("stiff", "E_stiff_over_matrix", "tab:blue"),
                                     ("pore", "E_pore_over_matrix", "tab:red")):
            y = [float(r[column]) for r in rows]
            face = colour if k == 0 else "none"
            name = "stiff inclusions (x10)" if case == "stiff" else "pores"
            ax.plot(ln, y, "o" if k == 0 else "s", color=colour, mfc=face,
                    label=f"{name}, {label}" if len(runs) > 1 else name)
            if case in fits:
                e0, alpha = float(fits[case]["extrapolated_E_over_Em"]), float(fits[case]["alpha_E"])
                ax.plot(xs, [e0 + alpha * x for x in xs], ":", color=colour)
    for ratio, colour in ((10.0, "tab:blue"), (0.0, "tab:red")):
        ax.axhline(hashin_shtrikman(0.2, ratio), color=colour, lw=0.8, alpha=0.5)
    ax.set_xlabel(r"mesh density $L_n = M^{-1/3}$")
    ax.set_ylabel(r"$E_{\rm eff} / E^{[m]}$")
    ax.set_xlim(left=0)
    ax.set_title("Mesh-density convergence, 20% inclusions (lines: HS estimates)", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    out = f"{runs[0][0]}/convergence.png"
    fig.savefig(out, dpi=130)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
