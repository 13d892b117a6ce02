#!/usr/bin/python3
"""Plot E_eff/E^[p] and S^pm/S^p against the matrix fraction (paper figs. 5, 11).

Usage: /usr/bin/python3 tools/plot_stiffness.py RESULTS_DIR
Reads RESULTS_DIR/stiffness.csv and fits.csv written by lem_stiffness and
writes RESULTS_DIR/stiffness.png (E_eff with linear fits and the appendix-D
estimates) and RESULTS_DIR/interface.png (S^pm/S^p).
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    if not os.path.isfile(path):
        sys.exit(f"error: {path} does not exist (run lem_stiffness first)")
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    if not rows:
        sys.exit(f"error: {path} has no data rows")
    return rows


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    d = sys.argv[1]
    rows = read_rows(os.path.join(d, "stiffness.csv"))
    fits = {r["quantity"]: r for r in read_rows(os.path.join(d, "fits.csv"))}
    col = lambda name: [float(r[name]) for r in rows]  # noqa: E731
    rho = col("rho_m")
    line = lambda q, x: float(fits[q]["intercept"]) + float(fits[q]["slope"]) * x  # noqa: E731
    xs = [min(rho), max(rho)]

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for key, fit, hs, colour, label in (
        ("E_bare", "E_bare_over_Ep", "HS_bare", "tab:red", "bare contacts ($E^{pp}=0$)"),
        ("E_adhesive", "E_adhesive_over_Ep", "HS_adhesive", "tab:blue",
         "adhesive contacts ($E^{pp}=E^{pm}$)"),
    ):
        ax.plot(rho, col(key), "o", color=colour, label=label)
        ax.plot(xs, [line(fit, x) for x in xs], ":", color=colour)
        ax.plot(rho, col(hs), "-", color=colour, alpha=0.6)
    ax.plot([], [], "k:", label="linear fit")
    ax.plot([], [], "k-", alpha=0.6, label="Hashin-Shtrikman (app. D)")
    ax.set_xlabel(r"matrix volume fraction $\rho^m$")
    ax.set_ylabel(r"$E_{\rm eff} / E^{[p]}$")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=8)
    ax.set_title("Effective Young's modulus (cf. paper fig. 5)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "stiffness.png"), dpi=130)

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ax.plot(rho, col("S_pm"), "ks", label="lattice")
    ax.plot(xs, [line("S_pm_over_S_p", x) for x in xs], "k:", label="linear fit")
    ax.set_xlabel(r"matrix volume fraction $\rho^m$")
    ax.set_ylabel(r"$S^{pm} / S^p$")
    ax.set_ylim(0, 1.05)
    ax.legend(fontsize=8)
    ax.set_title("Particle-matrix interface area (cf. paper fig. 11)", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(d, "interface.png"), dpi=130)
    print(f"wrote {d}/stiffness.png and {d}/interface.png")


if __name__ == "__main__":
    main()
