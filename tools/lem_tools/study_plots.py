"""The figures of a parametric study (paper figs. 5, 8, 9, 12-16), drawn from
the rows of results.csv (study_table.run_row) and the fit of eq. 10."""
import os

import numpy as np

from .analysis import (K_DAMAGE_LIMIT, K_WEAKEST_LINK, RHO_FILLED, eq10_abscissa,
                       eq14_frontier, group_by_rho)
from .plotting import plt, save_figure

DPI = 100


def rho_colors(groups):
    return plt.cm.viridis(np.linspace(0, 0.9, len(groups)))


def strength_figure(rows, fit, path):
    groups = group_by_rho(rows)
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5))
    for c, (rho, rs) in zip(rho_colors(groups), groups.items()):
        x = [r["sigma_pm_ratio"] for r in rs]
        a.plot(x, [r["sigma_eff_over_sigma_unit"] for r in rs], "o-", color=c,
               label=r"$\rho^m$ = %.2f" % rho)
        if fit:
            g = eq10_abscissa(rho, fit["k"])
            b.plot([g] * len(rs), [r["sigma_eff_over_sigma_pm"] for r in rs], "o", color=c)
    a.set_xlabel(r"$\sigma^{pm} / \sigma^p$")
    a.set_ylabel(r"$\sigma_{\rm eff} / \sigma^{[p]}$")
    a.set_title("(a) tensile strength (paper fig. 9)")
    a.legend(fontsize=8)
    if fit:
        gs = np.linspace(0, b.get_xlim()[1], 10)
        b.plot(gs, fit["A"] * gs, "--", color="black",
               label="eq. 10: A = %.3f, k = %.2f (paper 0.3, 2.5)" % (fit["A"], fit["k"]))
        b.legend(fontsize=8)
    b.set_xlabel(r"$\rho^m (2\rho^m_f - \rho^m) / (1 - k \rho^m)$,  $\rho^m_f$ = %.2f" % RHO_FILLED)
    b.set_ylabel(r"$\sigma_{\rm eff} / \sigma^{pm}$")
    b.set_title("(b) scaling of eq. 10 (paper fig. 12)")
    fig.tight_layout()
    save_figure(fig, path, dpi=DPI)


def damage_curve_picks(rows):
    """Runs whose n_b curve panel (a) of the damage figure draws: the lowest
    and highest sigma^pm at the largest rho^m, and the highest sigma^pm at the
    smallest (fig. 13)."""
    rhos = sorted({r["rho_m"] for r in rows})
    ratios = sorted({r["sigma_pm_ratio"] for r in rows})
    picks = {(rhos[-1], ratios[0]), (rhos[-1], ratios[-1]), (rhos[0], ratios[-1])}
    return [r for r in rows if (r["rho_m"], r["sigma_pm_ratio"]) in picks]


def edges(values):
    """Cell edges around sorted centres (one cell each)."""
    v = np.asarray(values, dtype=float)
    if len(v) == 1:
        return np.array([v[0] - 0.05, v[0] + 0.05])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def damage_figure(rows, curves, phases, path):
    """`curves`: {run id: curve (results.read_curve)} of damage_curve_picks(rows)."""
    groups = group_by_rho(rows)
    rhos = list(groups)
    ratios = sorted({r["sigma_pm_ratio"] for r in rows})
    colors = rho_colors(groups)
    fig, axes = plt.subplots(2, 2, figsize=(12, 9.5))
    (a, b), (c, d) = axes
    for r in damage_curve_picks(rows):
        curve = curves[r["id"]]
        a.plot(curve["strain"] * 1e3, curve["n_b"],
               label=r"$\rho^m$ = %.2f, $\sigma^{pm}/\sigma^p$ = %.2f"
               % (r["rho_m"], r["sigma_pm_ratio"]))
    a.set_xlabel(r"$\varepsilon_{zz}$ ($\times 10^{-3}$)")
    a.set_ylabel(r"$n_b$")
    a.set_title("(a) particle damage against strain (paper fig. 13)")
    a.legend(fontsize=8)
    for col, (rho, rs) in zip(colors, groups.items()):
        b.plot([r["sigma_pm_ratio"] for r in rs], [r["n_b"] for r in rs], "o-", color=col,
               label=r"$\rho^m$ = %.2f" % rho)
        d.plot([r["K_c_r_eq14"] for r in rs], [r["n_b"] for r in rs], "o", color=col,
               label=r"$\rho^m$ = %.2f" % rho)
    b.set_xlabel(r"$\sigma^{pm} / \sigma^p$")
    b.set_ylabel(r"$n_b$ after failure")
    b.set_title("(b) paper fig. 14")
    b.legend(fontsize=8)
    # (c) grey map over the grid, with the frontiers of eqs. 13 and 14.
    grid = np.full((len(ratios), len(rhos)), np.nan)
    for r in rows:
        grid[ratios.index(r["sigma_pm_ratio"]), rhos.index(r["rho_m"])] = r["n_b"]
    shown = c.pcolormesh(edges(rhos), edges(ratios), grid, cmap="Greys", shading="flat")
    fig.colorbar(shown, ax=c, label=r"$n_b$")
    c.axhline(K_WEAKEST_LINK, ls="--", color="tab:red", label="eq. 13, $K_c^r$ = %.1f"
              % K_WEAKEST_LINK)
    e_of_rho = [np.mean([r["E_eff_over_E_unit"] for r in groups[rho]]) for rho in rhos]
    c.plot(rhos, [eq14_frontier(e, phases) for e in e_of_rho], ":", color="tab:blue", lw=2,
           label="eq. 14, $K_c^r$ = %.1f" % K_DAMAGE_LIMIT)
    c.set_ylim(edges(ratios)[0], edges(ratios)[-1])
    c.set_xlabel(r"$\rho^m$")
    c.set_ylabel(r"$\sigma^{pm} / \sigma^p$")
    c.set_title("(c) paper fig. 15")
    c.legend(fontsize=8, loc="upper left")
    d.axvline(K_DAMAGE_LIMIT, ls=":", color="tab:blue")
    d.set_xlabel(r"$K_c^r$ (eq. 14)")
    d.set_ylabel(r"$n_b$ after failure")
    d.set_title("(d) paper fig. 16")
    fig.tight_layout()
    save_figure(fig, path, dpi=DPI)


def stiffness_stress_figure(rows, path):
    groups = group_by_rho(rows)
    rhos = list(groups)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    a.plot(rhos, [np.mean([r["E_eff_over_E_unit"] for r in groups[x]]) for x in rhos], "o-")
    a.set_xlabel(r"$\rho^m$")
    a.set_ylabel(r"$E_{\rm eff} / E^{[p]}$")
    a.set_title("(a) effective modulus, bare contacts (paper fig. 5)")
    b.plot(rhos, [groups[x][0]["beta"] for x in rhos], "s-")
    b.set_xlabel(r"$\rho^m$")
    b.set_ylabel(r"tail exponent $\beta$ of eq. 2")
    b.set_title(r"(b) node-stress pdf tail (paper: 0.7 $\to$ 2.1 for 0.06 $\to$ 0.28)")
    fig.tight_layout()
    save_figure(fig, path, dpi=DPI)


def draw_all(rows, fit, curves, phases, folder):
    os.makedirs(folder, exist_ok=True)
    strength_figure(rows, fit, os.path.join(folder, "strength.png"))
    damage_figure(rows, curves, phases, os.path.join(folder, "damage.png"))
    stiffness_stress_figure(rows, os.path.join(folder, "stiffness_stress.png"))
