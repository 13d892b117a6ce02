"""The figures of a parametric study (paper figs. 5, 8, 9, 12-16), drawn from
its grid points (analysis.replicate_means and sample_means of the rows of
results.csv, study_table.run_row) and the fit of eq. 10: a point is a run's
value, or with replicates (several packing and lattice seeds at the size
the figures are drawn at) their mean with ±1 standard deviation as error
bars.  The paper's values are stars (paper.paper_values) and the subtitle
says the resolution (study_table.figures_resolution)."""
import os
import textwrap

import numpy as np

from .analysis import (K_DAMAGE_LIMIT, K_WEAKEST_LINK, RHO_FILLED, converged_modulus,
                       eq10_abscissa, eq14_frontier, group_by_rho, k_c_r_eq14)
from .paper import CONVERGED_MODULI, paper_values
from .plotting import paper_mark, plt, save_figure

DPI = 100
# The columns of results.csv the figures show, averaged over the replicates.
COLUMNS = ("E_eff_over_E_unit", "sigma_eff_over_sigma_unit", "sigma_eff_over_sigma_pm", "n_b",
           "n_b_without_bare_contacts", "K_c_r_eq14")
RHO = r"matrix fraction $\rho^m$"
RATIO = r"interface strength $\sigma^{pm} / \sigma^p$"
E_P = r" $E^{[p]}$"
# n_b both ways: the paper's definition (the share of the particles in every
# broken bond, the bare contacts that open at the first step included) and
# without the bare contacts (sigma^pp = 0) in the denominator.
N_B_NAMES = {"n_b": r"$n_b$, bare contacts counted (the paper's definition)",
             "n_b_without_bare_contacts": r"$n_b$ without the bare contacts"}
N_B = r"$n_b$ after failure, bare contacts counted (the paper's definition)"
N_B_WITHOUT = r"$n_b$ after failure without the bare contacts"
N_B_LABELS = {"n_b": N_B, "n_b_without_bare_contacts": N_B_WITHOUT}
# The paper's phases (sect. 2.3): the moduli at L_n -> 0 (paper.CONVERGED_MODULI)
# were measured with them, and are used only for samples of the same phases.
PAPER_PHASES = {"E_p": 3.0, "E_m": 1.0, "E_pm": 1.0}


def rho_colors(groups):
    return plt.cm.viridis(np.linspace(0, 0.9, len(groups)))


def replicated(points):
    return any(p["replicates"] > 1 for p in points)


def values(ax, x, points, column, fmt, xcolumn=None, **style):
    """`column` of `points` against `x`: with replicates the means and ±1
    standard deviation as error bars (horizontal ones of `xcolumn` too),
    else the single runs' values; returns the ErrorbarContainer."""
    bars = replicated(points)
    return ax.errorbar(x, [p[column] for p in points],
                       yerr=[p["std"][column] for p in points] if bars else None,
                       xerr=[p["std"][xcolumn] for p in points] if bars and xcolumn else None,
                       fmt=fmt, capsize=3, ms=6, **style)


def paper_stars(ax, quantity, phases, unit=""):
    """The paper's values of `quantity` as stars with their legend entry
    (what the paper states, and in `unit` what that is here); None if the
    paper gives none."""
    found = paper_values(quantity, phases)
    if not found:
        return None
    label = "paper, %s: " % found[0][2] + ", ".join(
        r"%s%s at $\rho^m$ = %.2f" % (stated, " = %.3f%s" % (value, unit) if unit else "", rho)
        for rho, value, _, stated in found)
    return paper_mark(ax, [f[0] for f in found], [f[1] for f in found], label)


def thousands(value):
    """An integer with its thousands set apart by a space: 1 250."""
    return "{:,}".format(int(round(value))).replace(",", " ")


def resolution_text(resolution):
    """The figures' subtitle: sample particles, bonds per particle and L_n,
    and how many samples each point is drawn from."""
    parts = ["%s particles" % resolution["sample_particles"]]
    per_particle = resolution.get("bonds_per_particle")
    if per_particle:
        parts.append("%s bonds per particle%s ($L_n$ = %.3f)" % (
            thousands(float("%.3g" % per_particle)),
            "" if resolution["bonds_from"] == "samples" else " asked", resolution["L_n"]))
    low, high = resolution["runs_per_point"]
    if high <= 1:
        parts.append(r"one sample per $\rho^m$")
    else:
        parts.append(r"%s samples per $\rho^m$ (seeds): mean ± standard deviation"
                     % (high if low == high else "%d–%d" % (low, high)))
    if resolution.get("beside"):
        return "%s; open markers, dashed: %s" % (", ".join(parts),
                                                 resolution_text(resolution["beside"]))
    return ", ".join(parts)


def finish(fig, resolution):
    """The subtitle, and the panels laid out below it."""
    # wrapped to the figure's width (about 13 characters an inch at this size)
    fig.suptitle(textwrap.fill(resolution_text(resolution), int(13 * fig.get_figwidth())),
                 fontsize=11)
    fig.tight_layout()  # leaves room for the subtitle
    return fig


def strength_panel(ax, points):
    """sigma_eff against sigma^pm, a line per rho^m (fig. 9)."""
    groups = group_by_rho(points)
    for color, (rho, ps) in zip(rho_colors(groups), groups.items()):
        values(ax, [p["sigma_pm_ratio"] for p in ps], ps, "sigma_eff_over_sigma_unit", "o-",
               color=color, label=r"$\rho^m$ = %.2f" % rho)
    ax.set_xlabel(RATIO)
    ax.set_ylabel(r"tensile strength $\sigma_{\rm eff} / \sigma^{[p]}$")
    ax.set_title("(a) tensile strength (paper fig. 9)")
    ax.legend(fontsize=8)


def scaling_panel(ax, points, fit, k=None):
    """sigma_eff / sigma^pm against the abscissa of eq. 10 with exponent k
    (default: the fitted one), and the fitted eq. 10 (fig. 12); returns the
    abscissa's k, None when nothing is drawn (no fit and no k)."""
    groups = group_by_rho(points)
    ratios = sorted({p["sigma_pm_ratio"] for p in points})
    k = k if k is not None else fit["k"] if fit else None
    title = "(b) scaling of eq. 10 (paper fig. 12)"
    if k is None:
        ax.set_title(title + ": not fitted, needs two matrix fractions")
        return None
    right = float(max(eq10_abscissa(list(groups), k)))
    # the sigma^pm of a rho^m share its abscissa: with error bars, side by
    # side over 3 % of the axis, so that the bars do not hide each other
    step = 0.03 * right / max(1, len(ratios) - 1) if replicated(points) else 0.0
    for color, (rho, ps) in zip(rho_colors(groups), groups.items()):
        x = float(eq10_abscissa(rho, k))
        values(ax, [x + (ratios.index(p["sigma_pm_ratio"]) - (len(ratios) - 1) / 2) * step
                    for p in ps], ps, "sigma_eff_over_sigma_pm", "o", color=color,
               label=r"$\rho^m$ = %.2f" % rho)
    if fit:
        label = "eq. 10 fitted: A = %.3f, k = %.2f (paper: 0.3, 2.5)" % (fit["A"], fit["k"])
        if abs(k - fit["k"]) < 1e-12:
            gs = np.linspace(0, 1.05 * right, 10)
            ax.plot(gs, fit["A"] * gs, "--", color="black", label=label)
        else:  # the fitted law is a curve against another k's abscissa
            rho = np.linspace(0, max(groups), 50)
            ax.plot(eq10_abscissa(rho, k), fit["A"] * eq10_abscissa(rho, fit["k"]), "--",
                    color="black", label=label)
    ax.set_xlabel(r"$\rho^m (2\rho^m_f - \rho^m) / (1 - k \rho^m)$,  $\rho^m_f$ = %.2f, k = %.2f"
                  % (RHO_FILLED, k))
    ax.set_ylabel(r"$\sigma_{\rm eff} / \sigma^{pm}$")
    ax.set_title(title + (r", $\sigma^{pm}$ rising to the right" if step else ""))
    ax.legend(fontsize=8)
    return k


def strength_figure(points, fit, resolution):
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5.4))
    strength_panel(a, points)
    scaling_panel(b, points, fit)
    return finish(fig, resolution)


def damage_curve_picks(points):
    """Points whose n_b curves panel (a) of the damage figure draws: the
    lowest and highest sigma^pm at the largest rho^m, and the highest
    sigma^pm at the smallest (fig. 13)."""
    rhos = sorted({p["rho_m"] for p in points})
    ratios = sorted({p["sigma_pm_ratio"] for p in points})
    picks = {(rhos[-1], ratios[0]), (rhos[-1], ratios[-1]), (rhos[0], ratios[-1])}
    return [p for p in points if (p["rho_m"], p["sigma_pm_ratio"]) in picks]


def edges(values):
    """Cell edges around sorted centres (one cell each)."""
    v = np.asarray(values, dtype=float)
    if len(v) == 1:
        return np.array([v[0] - 0.05, v[0] + 0.05])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def damage_curves(ax, points, curves, colors):
    """Panel (a): n_b against the strain of damage_curve_picks, one colour
    per rho^m, dashed with markers and on top at the lowest sigma^pm (its
    n_b stays near 0, where the others start); with replicates the first
    seeds' run thick and the others thin.  The curves count the bare
    contacts (the paper's n_b); n_b without them, known at the end of each
    point's runs, is an open circle on the right axis at the end of the
    first run's curve."""
    low = min(p["sigma_pm_ratio"] for p in points)
    ends = []
    for p in damage_curve_picks(points):
        style = dict(ls="--", marker="v", markevery=0.1, zorder=3) \
            if p["sigma_pm_ratio"] == low else dict(ls="-")
        for i, run_id in enumerate(p["runs"]):
            curve = curves[run_id]
            ax.plot(curve["strain"] * 1e3, curve["n_b"], color=colors[p["rho_m"]],
                    lw=2 if i == 0 else 0.8, alpha=1 if i == 0 else 0.6, **style,
                    label=None if i else r"$\rho^m$ = %.2f, $\sigma^{pm}/\sigma^p$ = %.2f"
                    % (p["rho_m"], p["sigma_pm_ratio"]))
        without = p.get("n_b_without_bare_contacts")
        if without is not None and np.isfinite(without):
            ends.append((curves[p["runs"][0]]["strain"][-1] * 1e3, without, colors[p["rho_m"]]))
    ax.set_xlabel(r"strain $\varepsilon_{zz}$ ($10^{-3}$)")
    ax.set_ylabel(r"$n_b$, bare contacts counted (the paper's definition)")
    ax.set_title("(a) particle damage against strain (paper fig. 13)")
    ax.legend(fontsize=8, title="thick: first seeds, thin: the other samples"
              if replicated(points) else None, title_fontsize=8, loc="upper left")
    if ends:
        right = ax.twinx()
        for x, y, color in ends:
            right.plot([x], [y], "o", mfc="white", mec=color, mew=1.5, ms=8)
        right.set_ylim(bottom=0, top=1.1 * max(1e-3, max(y for _, y, _ in ends)))
        right.set_ylabel(r"open circles: $n_b$ without the bare contacts, end of the runs")


def point_colors(points):
    """{rho^m: colour} of the matrix fractions of `points`."""
    groups = group_by_rho(points)
    return dict(zip(groups, rho_colors(groups)))


def damage_panel(ax, points, column="sigma_pm_ratio", quantity="n_b"):
    """`quantity` (n_b, or n_b_without_bare_contacts) after failure against
    sigma^pm (fig. 14) or, with `column` K_c_r_eq14, against K_c^r of eq. 14
    (fig. 16), a series per rho^m; a `column` of None values for a point
    leaves it out."""
    colors = point_colors(points)
    against_ratio = column == "sigma_pm_ratio"
    for rho, ps in group_by_rho(points).items():
        ps = [p for p in ps if p.get(column) is not None]
        if not ps:
            continue
        has_std = column in ps[0]["std"]
        values(ax, [p[column] for p in ps], ps, quantity, "o-" if against_ratio else "o",
               xcolumn=None if against_ratio or not has_std else column, color=colors[rho],
               label=r"$\rho^m$ = %.2f" % rho)
    ax.set_ylabel(N_B_LABELS[quantity])
    ax.legend(fontsize=8)


def converged_moduli(phases):
    """paper.CONVERGED_MODULI for samples of the paper's phases, else None."""
    if all(abs(phases.get(k, float("nan")) - v) < 1e-12 for k, v in PAPER_PHASES.items()):
        return CONVERGED_MODULI
    return None


def with_converged_k(points, phases):
    """The points with K_c_r_eq14_converged: K_c^r of eq. 14 with E_eff at
    L_n -> 0 (None where no converged modulus is known at that rho^m)."""
    moduli = converged_moduli(phases) or {}
    out = []
    for p in points:
        e = converged_modulus(p["rho_m"], moduli)
        out.append(dict(p, K_c_r_eq14_converged=None if e is None else
                        k_c_r_eq14(e, p["sigma_pm_ratio"], phases)))
    return out


def damage_map_panel(fig, c, points, samples, phases, quantity="n_b"):
    """Grey map of `quantity` over (rho^m, sigma^pm) with the frontiers of
    eqs. 13 and 14 (fig. 15), eq. 14's with the samples' E_eff and, for the
    paper's phases, with E_eff at L_n -> 0; `samples` as
    analysis.sample_means gives them."""
    rhos = sorted({p["rho_m"] for p in points})
    ratios = sorted({p["sigma_pm_ratio"] for p in points})
    grid = np.full((len(ratios), len(rhos)), np.nan)
    for p in points:
        grid[ratios.index(p["sigma_pm_ratio"]), rhos.index(p["rho_m"])] = p[quantity]
    greys = plt.get_cmap("Greys").copy()
    greys.set_bad("mistyrose")  # a point without a run, unlike n_b = 0 (white)
    shown = c.pcolormesh(edges(rhos), edges(ratios), grid, cmap=greys, shading="flat", vmin=0)
    fig.colorbar(shown, ax=c, label=N_B_LABELS[quantity])
    c.axhline(K_WEAKEST_LINK, ls="--", color="tab:red", label="eq. 13, $K_c^r$ = %.1f"
              % K_WEAKEST_LINK)
    e_of_rho = {p["rho_m"]: p["E_eff_over_E_unit"] for p in samples}
    c.plot(rhos, [eq14_frontier(e_of_rho[rho], phases) for rho in rhos], ":", color="tab:blue",
           lw=2, label="eq. 14, $K_c^r$ = %.1f, the samples' $E_{\\rm eff}$" % K_DAMAGE_LIMIT)
    moduli = converged_moduli(phases)
    known = [(rho, converged_modulus(rho, moduli or {})) for rho in rhos]
    known = [(rho, e) for rho, e in known if e is not None]
    if known:
        c.plot([rho for rho, _ in known], [eq14_frontier(e, phases) for _, e in known], "-.",
               color="tab:cyan", lw=2, label="eq. 14, $K_c^r$ = %.1f, $E_{\\rm eff}$ at "
               "$L_n \\to 0$ (516 p)" % K_DAMAGE_LIMIT)
    c.set_ylim(edges(ratios)[0], edges(ratios)[-1])
    c.set_xlabel(RHO)
    c.set_ylabel(RATIO)
    c.set_title(r"(c) $n_b$ over the grid (paper fig. 15)")
    c.legend(fontsize=8, loc="best", framealpha=0.9)


def damage_figure(points, samples, curves, phases, resolution):
    """`curves`: {run id: curve (results.read_curve)} of the runs of
    damage_curve_picks(points); `samples`: analysis.sample_means (the
    moduli of eq. 14's frontier).  n_b both ways: (b), (e) as the paper
    defines it, (c), (f) without the bare contacts."""
    fig, axes = plt.subplots(2, 3, figsize=(18, 10))
    (a, b, c), (d, e, f) = axes
    damage_curves(a, points, curves, point_colors(points))
    for ax, quantity, letter in ((b, "n_b", "b"), (c, "n_b_without_bare_contacts", "c")):
        damage_panel(ax, points, quantity=quantity)
        ax.set_xlabel(RATIO)
        ax.set_title(r"(%s) damage against $\sigma^{pm}$ (paper fig. 14)" % letter)
    damage_map_panel(fig, d, points, samples, phases)
    d.set_title(r"(d) $n_b$ over the grid (paper fig. 15)")
    for ax, quantity, letter in ((e, "n_b", "e"), (f, "n_b_without_bare_contacts", "f")):
        damage_panel(ax, points, "K_c_r_eq14", quantity)
        ax.axvline(K_DAMAGE_LIMIT, ls=":", color="tab:blue", label="eq. 14, $K_c^r$ = %.1f"
                   % K_DAMAGE_LIMIT)
        ax.set_xlabel(r"$K_c^r$ of eq. 14 (the samples' $E_{\rm eff}$)")
        ax.set_title(r"(%s) damage against $K_c^r$ (paper fig. 16)" % letter)
        ax.legend(fontsize=8)
    return finish(fig, resolution)


def modulus_panel(ax, samples, phases):
    """E_eff against rho^m (fig. 5), the paper's value as a star."""
    values(ax, [p["rho_m"] for p in samples], samples, "E_eff_over_E_unit", "o-",
           color="tab:blue", label="first step of lem_fracture (bare contacts open)")
    paper_stars(ax, "E_eff_over_E_unit", phases, E_P)
    ax.set_xlabel(RHO)
    ax.set_ylabel(r"effective modulus $E_{\rm eff} / E^{[p]}$")
    ax.set_title("(a) effective modulus, bare contacts (paper fig. 5)")
    ax.legend(fontsize=8)


def beta_panel(ax, samples, phases):
    """The tail exponent beta against rho^m (fig. 8), the paper's as stars."""
    values(ax, [p["rho_m"] for p in samples], samples, "beta", "s-", color="tab:blue",
           label=r"$P(s) \propto e^{-\beta s}$ above $s$ = 1, $s = \sigma^i_{zz}/\sigma_{zz}$, "
                 "nodes off the box faces")
    paper_stars(ax, "beta", phases)
    ax.set_xlabel(RHO)
    ax.set_ylabel(r"tail exponent $\beta$ of eq. 2")
    ax.set_title("(b) node-stress pdf tail (paper fig. 8)")
    ax.legend(fontsize=8)


def stiffness_stress_figure(samples, phases, resolution):
    """`samples`: analysis.sample_means (one point per rho^m)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5.4))
    modulus_panel(a, samples, phases)
    beta_panel(b, samples, phases)
    return finish(fig, resolution)


def draw_all(points, samples, fit, curves, phases, resolution, folder):
    """figures/strength, damage and stiffness_stress (.png and .pdf) of the
    grid points `points` (analysis.replicate_means of COLUMNS) and
    `samples` (analysis.sample_means); returns the PNG paths."""
    os.makedirs(folder, exist_ok=True)
    figures = {"strength": strength_figure(points, fit, resolution),
               "damage": damage_figure(points, samples, curves, phases, resolution),
               "stiffness_stress": stiffness_stress_figure(samples, phases, resolution)}
    paths = []
    for name, fig in figures.items():
        paths.append(os.path.join(folder, name + ".png"))
        save_figure(fig, paths[-1], also=(".pdf",), dpi=DPI)
    return paths
