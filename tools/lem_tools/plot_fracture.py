"""Pictures of a tensile fracture run written by lem_fracture.

Reads RESULTS_DIR/curve.csv, broken.csv, summary.json (and, if present, the
homogeneous-lattice calibration run RESULTS_DIR/calibration/curve.csv);
writes RESULTS_DIR/fracture.png (and .pdf) with three panels (Affes et al. 2012):
(a) stress-strain curve sigma_zz/sigma_unit against epsilon_zz (fig. 3), with
the stress drops of the rupture steps as vertical segments, the peak
sigma_eff and E_eff, and an inset up to twice the peak strain; (b) 3D map of the broken-bond midpoints coloured by
phase (fig. 4); (c) share n_b of broken bonds inside the particles, both
ways (every broken bond in the denominator, as the paper defines it, and
without the bare contacts), and cumulative broken bonds per phase against
strain (fig. 13).
"""
import os
import textwrap

import numpy as np

from . import cli
from .analysis import share_without_bare_contacts
from .errors import ToolError
from .phases import BREAKABLE, broken_column, phase_name
from .plotting import phase_color, plt, save_figure
from .results import (BROKEN, CURVE, FRACTURE_PLOT, SUMMARY, finite_number, read_broken,
                      read_curve, read_summary, require_finished)

MAX_SCATTER = 60000  # broken bonds drawn in panel (b); the legend counts all of them
STRAIN_SCALE = 1e3   # strain axes are in units of 1e-3


def sawtooth(curve):
    """Strain and stress points (before, then after the ruptures of each step),
    starting at the unloaded state, so that stress drops are vertical."""
    strain = np.concatenate([[0.0], np.repeat(curve["strain"], 2)])
    stress = np.concatenate(
        [[0.0], np.column_stack([curve["stress_before_norm"], curve["stress_norm"]]).ravel()])
    return strain * STRAIN_SCALE, stress


def panel_stress(ax, curve, calibration, summary):
    if calibration is not None:
        # Its own curve is normalised by sigma^p; sigma^[p] is its peak.
        strain, stress = sawtooth(calibration)
        ax.plot(strain, stress / max(stress.max(), 1e-300), color="0.6", lw=1.0, zorder=1,
                label=r"homogeneous lattice (calibration: peak = $\sigma^{[p]}$)")
    e_eff = finite_number(summary, "E_eff_over_E_unit")
    label = "sample"
    if e_eff is not None:
        label += rf", $E_{{\rm eff}}/E_{{\rm unit}}$ = {e_eff:.4g}"
    ax.plot(*sawtooth(curve), color="k", lw=1.2, zorder=2, label=label)
    sigma_eff = finite_number(summary, "sigma_eff_over_sigma_unit")
    strain_peak = finite_number(summary, "strain_at_peak")
    label = r"peak, $\sigma_{\rm eff}/\sigma_{\rm unit}$ = "
    if sigma_eff is None or strain_peak is None:  # not in summary.json: take the curve's
        i = int(np.argmax(curve["stress_before_norm"]))
        sigma_eff, strain_peak = curve["stress_before_norm"][i], curve["strain"][i]
        label = r"curve maximum, $\sigma_{zz}/\sigma_{\rm unit}$ = "
    ax.plot([strain_peak * STRAIN_SCALE], [sigma_eff], "o", color="tab:red", ms=6, zorder=3,
            label=label + f"{sigma_eff:.4g}")
    ax.set_xlim(left=0)
    ax.set_ylim(0, 1.25 * ax.get_ylim()[1])  # a free band on top for the legend
    ax.set_xlabel(r"$\epsilon_{zz}$ ($\times 10^{-3}$)")
    ax.set_ylabel(r"$\sigma_{zz}\,/\,\sigma^{[p]}$")
    ax.set_title("(a) stress-strain", fontsize=10)
    ax.legend(loc="upper left", fontsize=7.5, framealpha=0.9)
    inset_pre_peak(ax, curve, sigma_eff, strain_peak)


def inset_pre_peak(ax, curve, sigma_eff, strain_peak):
    """The rise to the peak and the first fall, which the long post-failure
    tail squeezes against the axis of the main panel."""
    if not strain_peak > 0 or not sigma_eff > 0:
        return
    inset = ax.inset_axes([0.5, 0.28, 0.46, 0.4])
    inset.plot(*sawtooth(curve), color="k", lw=1.0)
    inset.plot([strain_peak * STRAIN_SCALE], [sigma_eff], "o", color="tab:red", ms=4)
    inset.set_xlim(0, 2 * strain_peak * STRAIN_SCALE)
    inset.set_ylim(0, 1.15 * sigma_eff)
    inset.set_title(r"up to 2 $\epsilon_{\rm peak}$", fontsize=7, pad=2)
    inset.tick_params(labelsize=6.5)


def panel_bonds(ax, xyz, phase, bare):
    ax.set_title("(b) broken bonds", fontsize=10)
    ax.set_xlabel("x", labelpad=-6)
    ax.set_ylabel("y", labelpad=-6)
    ax.set_zlabel("z", labelpad=-6)
    ax.tick_params(labelsize=7, pad=0)
    ax.view_init(elev=15, azim=-60)
    try:
        ax.set_box_aspect((1, 1, 1), zoom=1.1)
    except TypeError:  # matplotlib < 3.6
        ax.set_box_aspect((1, 1, 1))
    bare_count = int(bare.sum())
    xyz, phase = xyz[~bare], phase[~bare]
    if bare_count:  # legend entry only
        ax.plot([], [], "o", ms=4, color="white",
                label=f"bare contacts opened (not drawn): {bare_count}")
    n = len(phase)
    if n == 0:
        ax.text2D(0.5, 0.5, "no broken bond", transform=ax.transAxes,
                  ha="center", va="center", fontsize=12)
        if bare_count:
            ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.01), fontsize=7.5,
                      frameon=False)
        return
    # one scatter in random order, so that no phase hides the others wholesale
    order = np.random.default_rng(0).permutation(n)[:MAX_SCATTER]
    if n > MAX_SCATTER:
        ax.set_title(f"(b) broken bonds ({MAX_SCATTER} of {n} drawn)", fontsize=10)
    colors = np.array([phase_color(p) for p in phase[order]], dtype=object)
    pts = xyz[order]
    ax.scatter(pts[:, 0], pts[:, 1], pts[:, 2], s=3 if len(order) <= 10000 else 1,
               marker="o", linewidths=0, c=list(colors), depthshade=False)
    others = sorted(set(phase) - set(BREAKABLE))
    for p in list(BREAKABLE) + others:
        count = int((phase == p).sum())
        if count:  # legend entry only
            ax.plot([], [], "o", ms=4, color=phase_color(p),
                    label=f"{p} ({phase_name(p)}): {count}")
    # equal scales on the three axes, a cube around the broken bonds
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    centre, half = (lo + hi) / 2, max((hi - lo).max() / 2, 1e-12)
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_zlim(centre[2] - half, centre[2] + half)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.01), ncol=2, fontsize=7.5,
              frameon=False, columnspacing=1.0, handletextpad=0.1)


def panel_damage(ax, curve):
    strain = np.concatenate([[0.0], curve["strain"]]) * STRAIN_SCALE
    n_b = np.concatenate([[np.nan], np.where(curve["broken"] > 0, curve["n_b"], np.nan)])
    handles = ax.plot(strain, n_b, color="k", lw=1.8, drawstyle="steps-post",
                      label=r"$n_b$ as the paper counts")
    # n_b both ways: without the bare contacts (sigma^pp = 0 bonds, which open
    # at the first tension) in the denominator, step by step.
    opened = curve["broken"] - curve[broken_column("pp")]
    without = np.concatenate([[np.nan], np.where(opened > 0, curve[broken_column("p")]
                                                 / np.maximum(opened, 1), np.nan)])
    handles += ax.plot(strain, without, color="k", lw=1.2, ls="-.", drawstyle="steps-post",
                       label=r"$n_b$, bare contacts left out")
    # Scaled to its data (n_b is often a few per mille); both axes leave a
    # free band on top for the legend.
    both = np.concatenate([n_b, without])
    top = np.nanmax(both) if np.isfinite(both).any() else 0.0
    ax.set_ylim(0, 1.7 * top if top > 0 else 1.0)
    ax.set_xlim(left=0, right=strain[-1])
    ax.set_xlabel(r"$\epsilon_{zz}$ ($\times 10^{-3}$)")
    ax.set_ylabel(r"$n_b$ (share of broken bonds in particles)")
    ax.set_title("(c) damage", fontsize=10)
    right = ax.twinx()
    for p in BREAKABLE:
        count = np.concatenate([[0.0], curve[broken_column(p)]])
        if count[-1] == 0:
            continue
        handles += right.plot(strain, count, color=phase_color(p), lw=1.0, ls="--",
                              drawstyle="steps-post", label=f"broken {p}")
    total = np.concatenate([[0.0], curve["broken"]])
    handles += right.plot(strain, total, color="0.5", lw=1.0, ls=":",
                          drawstyle="steps-post", label="all broken")
    right.set_ylim(bottom=0, top=max(1.0, total.max()) * 1.3)
    right.set_ylabel("cumulative broken bonds (dashed, dotted)")
    right.ticklabel_format(axis="y", style="sci", scilimits=(-3, 4))
    ax.legend(handles=handles, loc="upper center", ncol=2, fontsize=7, framealpha=0.9,
              columnspacing=0.8, handlelength=1.8, handletextpad=0.4)
    if total[-1] == 0:
        ax.text(0.5, 0.5, "no broken bond", transform=ax.transAxes,
                ha="center", va="center", fontsize=12)


def title(summary, directory):
    def text(value):  # free text from summary.json, no mathtext
        return str(value).replace("$", r"\$")

    parts = [text(os.path.basename(str(summary.get("sample_file", directory))))]
    if "broken" in summary:
        parts.append(f"{summary['broken']} broken bonds")
        if finite_number(summary, "n_b") is not None:
            parts[-1] += f" ($n_b$ = {summary['n_b']:.3f}"
            if all(finite_number(summary, k) is not None for k in ("broken_p", "broken_pp")):
                without = share_without_bare_contacts(summary["broken_p"], summary["broken"],
                                                      summary["broken_pp"])
                parts[-1] += f", {without:.3f} without the bare contacts"
            parts[-1] += ")"
    if "steps" in summary:
        parts.append(f"{summary['steps']} steps, {summary.get('solves', '?')} solves")
    if finite_number(summary, "energy_balance_error") is not None:
        parts.append(f"energy balance error {summary['energy_balance_error']:.2g}")
    if "end_reason" in summary:
        parts.append(f"end: {text(summary['end_reason'])}")
    return ", ".join(parts)


def draw(directory):
    directory = directory.rstrip("/") or "/"
    if not os.path.isdir(directory):
        raise ToolError(f"{directory} is not a directory")
    require_finished(directory)
    summary = read_summary(os.path.join(directory, SUMMARY))
    curve = read_curve(os.path.join(directory, CURVE))
    xyz, phase, threshold = read_broken(os.path.join(directory, BROKEN))
    # Bonds of zero threshold (bare contacts, sigma^pp = 0) open at the first
    # tension: they are no crack and are counted, not drawn.
    bare = threshold <= 0
    calibration_file = os.path.join(directory, "calibration", CURVE)
    calibration = read_curve(calibration_file) if os.path.exists(calibration_file) else None

    fig = plt.figure(figsize=(12, 4.5))
    grid = fig.add_gridspec(1, 3, width_ratios=(1, 1.15, 1), left=0.055, right=0.935,
                            bottom=0.13, top=0.86, wspace=0.38)
    ax_stress = fig.add_subplot(grid[0])
    ax_bonds = fig.add_subplot(grid[1], projection="3d")
    ax_damage = fig.add_subplot(grid[2])
    panel_stress(ax_stress, curve, calibration, summary)
    panel_bonds(ax_bonds, xyz, phase, bare)
    panel_damage(ax_damage, curve)
    # two lines at most: the figure is 12 inches wide, about 150 characters a line
    fig.suptitle(textwrap.fill(title(summary, directory), 150), fontsize=10)
    out = os.path.join(directory, FRACTURE_PLOT)
    save_figure(fig, out, also=(".pdf",), dpi=120)
    print(f"wrote {out} and fracture.pdf")


def main(argv=None):
    return cli.run_on_folder(__doc__, "output folder of lem_fracture (-output_dir)", draw, argv)


if __name__ == "__main__":
    raise SystemExit(main())
