"""The convergence figures of a study (paper fig. 6 extended from E_eff to
strength and damage): every quantity against L_n, mean ± standard deviation
of the replicates at each resolution, the fitted line down to L_n = 0 and the
extrapolated value with its standard error there."""
import math
import os

import numpy as np

from .paper import paper_marks, paper_source
from .plotting import paper_mark, plt, save_figure

DPI = 100
MARKERS = ("o", "s", "^", "D", "v", "P")
FIGURES = (("convergence_elastic", "elastic moduli (lem_tension)", "sample"),
           ("convergence_strength", "first-step modulus, strength, peak strain, node stresses",
            ("E_eff_over_E_unit", "sigma_eff_over_sigma_unit", "strain_at_peak", "beta")),
           ("convergence_damage", "damage after failure",
            ("n_b", "n_b_without_bare_contacts", "share_broken_m", "share_broken_pm")))


def point_style(rhos, ratios, rho, ratio):
    color = plt.cm.viridis(np.linspace(0, 0.85, max(1, len(rhos))))[rhos.index(rho)]
    i = 0 if ratio is None else ratios.index(ratio)
    return color, MARKERS[i % len(MARKERS)], ("-", "--", ":", "-.")[i % 4]


def point_label(rho, ratio):
    if ratio is None:
        return r"$\rho^m$ = %.2f" % rho
    return r"$\rho^m$ = %.2f, $\sigma^{pm}/\sigma^p$ = %.2f" % (rho, ratio)


def panel(ax, results, quantity, label, level_l_n, spec):
    keys = sorted(k for k in results if k[0] == quantity)
    rhos = sorted({k[1] for k in keys})
    ratios = sorted({k[2] for k in keys if k[2] is not None})
    # a level whose samples are not described (L_n NaN) sets no limit
    right = max((e["L_n"] for k in keys for e in results[k]["levels"] if math.isfinite(e["L_n"])),
                default=1.0)
    for i, key in enumerate(keys):
        r = results[key]
        color, marker, line = point_style(rhos, ratios, key[1], key[2])
        l_n = np.array([e["L_n"] for e in r["levels"]])
        mean = np.array([e["mean"] for e in r["levels"]])
        std = np.array([e["std"] if e["n"] > 1 else 0.0 for e in r["levels"]])
        ax.errorbar(l_n, mean, yerr=std, fmt=marker, color=color, ms=5, capsize=3,
                    label=point_label(key[1], key[2]))
        fit = r["fit"]
        if fit:
            xs = np.array([0.0, l_n.max()])
            ax.plot(xs, fit["intercept"] + fit["slope"] * xs, line, color=color, lw=1)
            se = r["extrapolated_se"]
            # side by side at L_n = 0, so that the error bars do not hide each other
            shift = (i - (len(keys) - 1) / 2) * 0.012 * right
            ax.errorbar([shift], [fit["intercept"]], yerr=[se if math.isfinite(se) else 0.0],
                        fmt=marker, mfc="white", color=color, ms=6, capsize=3)
    for rho, value in paper_marks(quantity, rhos, spec.get("phases", {})):
        color, _, _ = point_style(rhos, ratios, rho, None)
        paper_mark(ax, [-0.03 * right], [value], r"paper, $\rho^m$ = %.2f (%s)"
                   % (rho, paper_source(quantity)), color)
    ax.set_xlim(-0.06 * right - 0.006 * right * len(keys), 1.06 * right)
    ax.axvline(0, color="0.8", lw=0.8, zorder=0)
    ax.set_xlabel(r"$L_n = M^{-1/3}$")
    ax.set_ylabel(label)
    levels = sorted((v, l) for v, l in level_l_n.items() if v is not None)
    if levels:
        top = ax.secondary_xaxis("top")
        top.set_ticks([l for _, l in levels], labels=["%g" % v for v, _ in levels])
        top.tick_params(labelsize=7)
        per_particle = "lattice_bonds_per_particle" in spec
        top.set_xlabel("bonds per particle" if per_particle else "bonds", fontsize=8)


def samples_text(results, shown):
    """How many samples (packing and lattice seeds) each point of the shown
    quantities is the mean of: "one sample", "3 samples", "1–9 samples"."""
    counts = [e["n"] for k, r in results.items() if k[0] in shown for e in r["levels"]]
    low, high = min(counts), max(counts)
    if high <= 1:
        return "one sample per point"
    return "%s samples per point" % (high if low == high else "%d–%d" % (low, high))


def figure(results, quantities, level_l_n, spec, title, path, particles):
    shown = [(q, label) for q, label, *_ in quantities if any(k[0] == q for k in results)]
    if not shown:
        return None
    columns = 2
    rows = math.ceil(len(shown) / columns)
    fig, axes = plt.subplots(rows, columns, figsize=(12, 4.6 * rows), squeeze=False)
    for ax, (quantity, label) in zip(axes.flat, shown):
        panel(ax, results, quantity, label, level_l_n, spec)
    for ax in list(axes.flat)[len(shown):]:
        ax.set_visible(False)
    # one legend entry per label over all panels (the paper's marks are on some)
    entries = {}
    for ax in axes.flat:
        for handle, label in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(label, handle)
    handles, labels = list(entries.values()), list(entries)
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8, frameon=False)
    fig.suptitle("%s against the mesh density (paper fig. 6 extended), %s particles, %s\n"
                 "mean ± standard deviation of the replicates, linear fit; open symbols: value "
                 "at $L_n \\to 0$ ± standard error; stars: the paper's values"
                 % (title.capitalize(), particles, samples_text(results, [q for q, _ in shown])),
                 fontsize=10)
    fig.tight_layout(rect=(0, 0.06 if rows > 1 else 0.1, 1, 0.97))
    save_figure(fig, path + ".png", also=(".pdf",), dpi=DPI)
    return path + ".png"


def draw_all(results, sample_quantities, run_quantities, level_l_n, spec, particles, folder):
    """figures/convergence_elastic, _strength and _damage (.png and .pdf) of
    the analysed points (convergence_table.analyse) of samples of `particles`
    particles; the figures whose quantities were not measured are not drawn."""
    os.makedirs(folder, exist_ok=True)
    run_labels = {q: label for q, label, _ in run_quantities}
    drawn = []
    for name, title, chosen in FIGURES:
        quantities = sample_quantities if chosen == "sample" else \
            [(q, run_labels[q]) for q in chosen]
        path = figure(results, quantities, level_l_n, spec, title, os.path.join(folder, name),
                      particles)
        if path:
            drawn.append(path)
    return drawn
