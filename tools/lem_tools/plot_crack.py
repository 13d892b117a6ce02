"""Crack map of a tensile fracture run written by lem_fracture (the paper's fig. 4).

Reads RESULTS_DIR/broken.csv and summary.json, and the particles of the
sample the run read (summary.json's sample_file, or --sample FILE); writes
RESULTS_DIR/crack.png (and .pdf) with three panels (Affes et al. 2012):
(a) 3D view of the broken-bond midpoints coloured by phase; (b) a slice
through the crack: the vertical plane y = L/2, with the particles it cuts
(grey discs) and the broken bonds within half a mean particle diameter of
it, so that one sees the crack go around the particles (pm) or through them
(p); (c) the broken bonds per unit height against z by phase, whose maximum
places the crack (the dashed line of (b)).  Bare contacts (zero threshold,
sigma^pp = 0) open at the first tension; they are no crack and are counted,
not drawn.  Without the sample file the slice is drawn without particles
and says so.
"""
import os

import numpy as np

from . import cli
from .errors import ToolError
from .phases import BREAKABLE, phase_name
from .plotting import phase_color, plt, save_figure
from .results import (BROKEN, SUMMARY, read_broken, read_hdf5, read_summary, require_finished,
                      sample_path)

CRACK_PLOT = "crack.png"
PROFILE_BINS = 40  # height bins of panel (c)


def read_particles(path):
    """Centres (n x 3), radii and the box (lo, hi) of a lem_sample file."""
    data = read_hdf5(path, ("particles/centres", "particles/radii"), ("box_lo", "box_hi"))
    return (data["particles/centres"], data["particles/radii"],
            np.asarray(data["box_lo"], dtype=float), np.asarray(data["box_hi"], dtype=float))


def crack_height(z, lo, hi, bins=PROFILE_BINS):
    """Edges of the height bins and the middle of the fullest one: where the
    broken bonds (not the bare contacts) are densest."""
    edges = np.linspace(lo, hi, bins + 1)
    counts, _ = np.histogram(z, bins=edges)
    k = int(np.argmax(counts)) if len(z) else bins // 2
    return edges, 0.5 * (edges[k] + edges[k + 1])


def slice_discs(centres, radii, y):
    """(x, z, r) of the circles the plane at height y cuts from the particles."""
    dy = centres[:, 1] - y
    cut = np.abs(dy) < radii
    return centres[cut, 0], centres[cut, 2], np.sqrt(radii[cut] ** 2 - dy[cut] ** 2)


def scatter_by_phase(ax, points, phase, size, project=lambda p: (p[:, 0], p[:, 2])):
    """Points coloured by phase in a fixed random order, so that no phase
    hides the others wholesale; returns the phases drawn."""
    order = np.random.default_rng(0).permutation(len(phase))
    colors = [phase_color(p) for p in phase[order]]
    ax.scatter(*project(points[order]), s=size, c=colors, linewidths=0)
    return sorted(set(phase))


def marker_size(count, scale):
    """Larger dots when there are few of them."""
    return float(np.clip(scale / max(count, 1), 1.0, 10.0))


def panel_3d(ax, xyz, phase, lo, hi):
    if len(phase):
        scatter_by_phase(ax, xyz, phase, marker_size(len(phase), 3000), project=lambda p: (p[:, 0], p[:, 1], p[:, 2]))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_title("(a) broken bonds", fontsize=10)


def panel_slice(ax, xyz, phase, particles, lo, hi, z_crack, half_width):
    y = 0.5 * (lo[1] + hi[1])
    if particles is not None:
        for x, z, r in zip(*slice_discs(particles[0], particles[1], y)):
            ax.add_patch(plt.Circle((x, z), r, color="0.85", lw=0))
    else:
        ax.text(0.5, 0.02, "sample file not found: particles not drawn", fontsize=7,
                ha="center", transform=ax.transAxes)
    near = np.abs(xyz[:, 1] - y) <= half_width
    if near.any():
        scatter_by_phase(ax, xyz[near], phase[near], marker_size(int(near.sum()), 1500))
    ax.axhline(z_crack, color="k", ls="--", lw=0.8)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[2], hi[2])
    ax.set_aspect("equal")
    ax.set_xlabel("x")
    ax.set_ylabel("z")
    ax.set_title(f"(b) slice y = {y:.3g} ± {half_width:.2g}: {int(near.sum())} bonds",
                 fontsize=10)


def panel_profile(ax, xyz, phase, edges, z_crack):
    height = edges[1] - edges[0]
    middles = 0.5 * (edges[:-1] + edges[1:])
    for p in BREAKABLE:
        counts, _ = np.histogram(xyz[phase == p, 2], bins=edges)
        if counts.any():
            ax.plot(counts / height, middles, color=phase_color(p), lw=1.2,
                    drawstyle="steps-mid", label=f"{p} ({phase_name(p)}): {int(counts.sum())}")
    ax.axhline(z_crack, color="k", ls="--", lw=0.8, label=f"crack at z = {z_crack:.3g}")
    ax.set_ylim(edges[0], edges[-1])
    ax.set_xlim(left=0)
    ax.set_xlabel("broken bonds per unit height")
    ax.set_ylabel("z")
    ax.legend(fontsize=7, loc="lower right", framealpha=0.9)
    ax.set_title("(c) where the bonds broke", fontsize=10)


def draw(directory, sample=None):
    directory = directory.rstrip("/") or "/"
    if not os.path.isdir(directory):
        raise ToolError(f"{directory} is not a directory")
    require_finished(directory)
    summary = read_summary(os.path.join(directory, SUMMARY))
    xyz, phase, threshold = read_broken(os.path.join(directory, BROKEN))
    bare = threshold <= 0
    path = sample_path(summary, directory, sample)
    particles = read_particles(path) if path else None
    if particles is not None:
        lo, hi = particles[2], particles[3]
    elif len(xyz):
        lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    else:
        lo, hi = np.zeros(3), np.ones(3)
    crack, crack_phase = xyz[~bare], phase[~bare]
    edges, z_crack = crack_height(crack[:, 2], lo[2], hi[2])
    # half a mean particle diameter: a slice about one particle thick
    half_width = float(np.mean(particles[1])) if particles is not None else (hi[1] - lo[1]) / 10

    fig = plt.figure(figsize=(13, 4.6))
    grid = fig.add_gridspec(1, 3, width_ratios=(1.1, 1, 0.9), left=0.03, right=0.98,
                            bottom=0.12, top=0.86, wspace=0.28)
    panel_3d(fig.add_subplot(grid[0], projection="3d"), crack, crack_phase, lo, hi)
    panel_slice(fig.add_subplot(grid[1]), crack, crack_phase, particles, lo, hi, z_crack,
                half_width)
    panel_profile(fig.add_subplot(grid[2]), crack, crack_phase, edges, z_crack)
    name = os.path.basename(str(summary.get("sample_file", directory)))
    fig.suptitle(f"{name}: {len(crack)} broken bonds drawn, {int(bare.sum())} bare contacts "
                 "opened at zero threshold (not drawn)", fontsize=10)
    out = os.path.join(directory, CRACK_PLOT)
    save_figure(fig, out, also=(".pdf",), dpi=120)
    print(f"wrote {out} and crack.pdf (crack at z = {z_crack:.4g})")


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("results_dir", metavar="RESULTS_DIR",
                            help="output folder of lem_fracture (-output_dir)")
    arg_parser.add_argument("--sample", metavar="FILE",
                            help="the sample file (default: summary.json's sample_file)")
    return cli.run(arg_parser, lambda args: draw(args.results_dir, args.sample), argv)


if __name__ == "__main__":
    raise SystemExit(main())
