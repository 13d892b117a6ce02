"""Plot E_eff/E^[p] and S^pm/S^p against the matrix fraction (paper figs. 5, 11).

Reads RESULTS_DIR/stiffness.csv and fits.csv written by lem_stiffness and
writes RESULTS_DIR/stiffness.png (E_eff with linear fits, the appendix-D
estimates, the Voigt bound of the phases and the paper's values at rho^m =
0.28) and RESULTS_DIR/interface.png (S^pm/S^p), each also as PDF.
"""
import os

from . import cli
from .plotting import plt, save_figure
from .results import ResultsError, read_csv

# Sect. 5 of the paper: E_eff at rho^m = 0.28 is about 1.6 E^[m] (bare) and
# 2.5 E^[m] (adhesive), with E^[m] = E^[p]/3 (E^m = E^p/3 on one lattice).
PAPER_RHO_M = 0.28
PAPER_E_OVER_EP = {"E_bare": 1.6 / 3, "E_adhesive": 2.5 / 3}
MATRIX_OVER_PARTICLE = 1 / 3

CONTACTS = (("E_bare", "E_bare_over_Ep", "HS_bare", "tab:red", "bare contacts ($E^{pp}=0$)"),
            ("E_adhesive", "E_adhesive_over_Ep", "HS_adhesive", "tab:blue",
             "adhesive contacts ($E^{pp}=E^{pm}$)"))


def read_table(path):
    if not os.path.isfile(path):
        raise ResultsError(f"{path} does not exist (run lem_stiffness first)")
    return read_csv(path, need_rows=True)


def draw(d):
    table = read_table(os.path.join(d, "stiffness.csv"))
    fits = read_table(os.path.join(d, "fits.csv")).records_by("quantity")

    def column(name):
        return list(table.numbers(name))

    def line(quantity, x):
        if quantity not in fits:
            raise ResultsError(f"{d}/fits.csv has no row {quantity}")
        return float(fits[quantity]["intercept"]) + float(fits[quantity]["slope"]) * x

    rho = column("rho_m")
    xs = [min(rho), max(rho)]

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    for key, fit, hs, colour, label in CONTACTS:
        ax.plot(rho, column(key), "o", color=colour, label=label)
        ax.plot(xs, [line(fit, x) for x in xs], ":", color=colour)
        ax.plot(rho, column(hs), "-", color=colour, alpha=0.6)
        ax.plot([PAPER_RHO_M], [PAPER_E_OVER_EP[key]], "D", mfc="none", color=colour, ms=7)
    # Voigt bound of the phases: particles E^[p], every other solid node at
    # most E^[m] (E^pm = E^pp = E^m), pores nothing.
    voigt = [p + (1 - p - v) * MATRIX_OVER_PARTICLE
             for p, v in zip(column("rho_p"), column("rho_v"))]
    ax.plot(rho, voigt, "--", color="0.4", lw=1, label="Voigt bound of the phases")
    ax.plot([], [], "D", mfc="none", color="k", label=r"paper, sect. 5 ($\rho^m$ = 0.28)")
    ax.plot([], [], "k:", label="linear fit")
    ax.plot([], [], "k-", alpha=0.6, label="Hashin-Shtrikman (app. D)")
    ax.set_xlabel(r"matrix volume fraction $\rho^m$")
    ax.set_ylabel(r"$E_{\rm eff} / E^{[p]}$")
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=8)
    ax.set_title("Effective Young's modulus (cf. paper fig. 5)", fontsize=10)
    fig.tight_layout()
    save_figure(fig, os.path.join(d, "stiffness.png"), also=(".pdf",), dpi=130)

    fig, ax = plt.subplots(figsize=(5.5, 4.2))
    ax.plot(rho, column("S_pm"), "ks", label="lattice")
    ax.plot(xs, [line("S_pm_over_S_p", x) for x in xs], "k:", label="linear fit")
    ax.set_xlabel(r"matrix volume fraction $\rho^m$")
    ax.set_ylabel(r"$S^{pm} / S^p$")
    ax.set_ylim(0, 1.05)
    ax.legend(fontsize=8)
    ax.set_title("Particle-matrix interface area (cf. paper fig. 11)", fontsize=10)
    fig.tight_layout()
    save_figure(fig, os.path.join(d, "interface.png"), also=(".pdf",), dpi=130)
    print(f"wrote {d}/stiffness.png and {d}/interface.png")


def main(argv=None):
    return cli.run_on_folder(__doc__, "output folder of lem_stiffness", draw, argv)


if __name__ == "__main__":
    raise SystemExit(main())
