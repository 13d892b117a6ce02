"""Node stresses of a cemented sample under tension (Affes et al. 2012, sect. 4).

Reads RESULTS_DIR/elastic.h5 (written by lem_fracture at the first
equilibrium: node stresses of eq. 1 with their Voronoi volumes) and writes
  RESULTS_DIR/stress.png   (a) map of sigma_zz^i on the mid-plane y = L/2
                           (fig. 7), (b) pdf of sigma_zz^i / sigma_zz with the
                           fitted exponential tail of eq. 2 (fig. 8), the
                           nodes on the box faces apart
  RESULTS_DIR/stress.json  beta, the fit range and counts, and the volume
                           average of sigma_zz^i against the applied stress.

The map shows the cut of the 3D Voronoi cells by the plane: each pixel takes
the stress of the node nearest to it in 3D.  Nodes without any bond (void
phase) carry no stress and are left out of the pdf; they are drawn grey.

Tail exponent: P(s) ~ exp(-beta s) for s = sigma_zz^i / sigma_zz above 1;
beta is the maximum-likelihood value 1 / mean(s - 1) of the nodes in the
tail (a least-squares fit of the log-histogram is printed beside it as a
check).  The nodes on the box faces are left out of the fit: the box halves
their Voronoi cells but the random lattice keeps the bonds in the faces
whole, which inflates their stress (lem_tools.analysis.on_box_faces); their
share falls as the sample grows, so with them beta would depend on the
sample size.

With --maps OUT.png RESULTS_DIR..., the maps (a) of several runs are drawn
side by side on one colour scale instead (fig. 7 at several rho^m), each
titled with its sample's rho^m; nothing else is written.
"""
import os

import matplotlib
import numpy as np

from . import cli
from .analysis import TAIL_START, ZZ, mid_plane_map, node_stress_statistics, stress_pdf
from .files import write_json
from .plotting import plt, save_figure
from .results import (ELASTIC, STRESS_FIT, STRESS_PLOT, SUMMARY, read_elastic, read_hdf5,
                      read_summary, sample_path)


def stress_map(ax, d, loaded, limit):
    """The mid-plane map of sigma_zz^i / sigma_zz on `ax`, in [-limit, limit]."""
    lo, hi = d["coords"].min(axis=0), d["coords"].max(axis=0)
    values = np.where(loaded, d["stress"][:, ZZ] / d["applied"], np.nan)
    image, extent = mid_plane_map(d["coords"], values, lo, hi)
    cmap = matplotlib.colormaps["RdBu_r"].copy()
    cmap.set_bad("0.55")  # void: grey, so that it is not read as zero stress (white)
    ax.set_xlabel("x")
    ax.set_ylabel("z")
    return ax.imshow(image, origin="lower", extent=extent, cmap=cmap, vmin=-limit, vmax=limit,
                     interpolation="nearest"), 0.5 * (lo[1] + hi[1])


def draw(out):
    d = read_elastic(os.path.join(out, ELASTIC))
    result, s, loaded, on_face = node_stress_statistics(d)
    fit = result["tail"]
    relative_mean = result["volume_average_stress_zz"] / d["applied"]

    fig, (ax_map, ax_pdf) = plt.subplots(1, 2, figsize=(12, 5.2))
    shown, y = stress_map(ax_map, d, loaded, np.nanquantile(np.abs(s), 0.99))
    fig.colorbar(shown, ax=ax_map, label=r"$\sigma_{zz}^i / \sigma_{zz}$ (tension > 0)")
    ax_map.set_title("(a) node stresses on the mid-plane y = %.2f (void grey)" % y)

    # Both pdfs per loaded node, so that they add up to the pdf of all nodes.
    edges, inside, faces = stress_pdf(s, on_face)
    centres = 0.5 * (edges[1:] + edges[:-1])
    floor = np.inf
    for hist, chosen, style, label in (
            (inside, ~on_face, "o", "nodes inside the box"),
            (faces, on_face, "x", "nodes on the box faces (left out of the fit)")):
        ok = hist > 0
        if ok.any():
            ax_pdf.semilogy(centres[ok], hist[ok], style, ms=4,
                            color="black" if style == "o" else "0.55",
                            label="%s (%d)" % (label, chosen.sum()))
            floor = min(floor, hist[ok].min())
    if fit:
        inside = s[~on_face]
        share = (inside > TAIL_START).sum() / s.size
        # Over the nodes it describes: the tail up to its 99 % quantile (a
        # single node per bin beyond that is the histogram's floor).
        xs = np.linspace(TAIL_START, np.quantile(inside[inside > TAIL_START], 0.99), 50)
        # The tail's own density, scaled by its share of the nodes.
        ax_pdf.semilogy(xs, share * fit["beta"] * np.exp(-fit["beta"] * (xs - TAIL_START)), ":",
                        color="tab:red", lw=2,
                        label=r"$\propto e^{-\beta s}$, $\beta$ = %.2f (ML; log-fit %.2f)"
                        % (fit["beta"], fit["beta_histogram_fit"]))
    ax_pdf.set_ylim(bottom=0.3 * floor)
    ax_pdf.set_xlabel(r"$s = \sigma_{zz}^i / \sigma_{zz}$")
    ax_pdf.set_ylabel("pdf")
    ax_pdf.set_title("(b) pdf of the vertical node stresses (%d loaded nodes)" % loaded.sum())
    ax_pdf.legend(loc="upper right", fontsize=8)
    fig.suptitle(r"%s: first equilibrium, $\varepsilon_{zz}$ = %.2e; volume average of "
                 r"$\sigma_{zz}^i$ / applied = %.8f"
                 % (os.path.basename(os.path.abspath(out)), d["strain"], relative_mean))
    fig.tight_layout()
    save_figure(fig, os.path.join(out, STRESS_PLOT), also=(".pdf",), dpi=110)
    write_json(os.path.join(out, STRESS_FIT), result)
    every = result["tail_all_nodes"]
    print("stress: beta = %s off the box faces (%s with the %d face nodes), volume average / "
          "applied = %.8f -> %s/stress.png"
          % ("%.3f" % fit["beta"] if fit else "n/a", "%.3f" % every["beta"] if every else "n/a",
             result["face_nodes"], relative_mean, out))


def matrix_fraction(directory):
    """rho^m of the run's sample (its attribute rho_m), or None."""
    summary = os.path.join(directory, SUMMARY)
    path = sample_path(read_summary(summary), directory) if os.path.exists(summary) else None
    return float(read_hdf5(path, (), ("rho_m",))["rho_m"]) if path else None


def draw_maps(out, directories):
    """The mid-plane maps of several runs side by side, one colour scale."""
    runs = [read_elastic(os.path.join(d, ELASTIC)) for d in directories]
    stats = [node_stress_statistics(d) for d in runs]
    limit = max(np.nanquantile(np.abs(s), 0.99) for _, s, _, _ in stats)
    fig, axes = plt.subplots(1, len(runs), figsize=(4.2 * len(runs) + 1.2, 4.6), squeeze=False)
    for ax, d, (_, _, loaded, _), directory in zip(axes[0], runs, stats, directories):
        shown, y = stress_map(ax, d, loaded, limit)
        rho = matrix_fraction(directory)
        ax.set_title((r"$\rho^m$ = %.3f" % rho) if rho is not None
                     else os.path.basename(os.path.abspath(directory)), fontsize=10)
    fig.colorbar(shown, ax=list(axes[0]), label=r"$\sigma_{zz}^i / \sigma_{zz}$ (tension > 0)",
                 shrink=0.9)
    fig.suptitle("node stresses on the mid-plane y = %.2f at the first equilibrium (void grey)"
                 % y, fontsize=10)
    save_figure(fig, out, dpi=110)
    print("wrote %s (%d maps)" % (out, len(runs)))


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("results_dirs", metavar="RESULTS_DIR", nargs="+",
                            help="output folder of lem_fracture (-output_dir); several with "
                                 "--maps")
    arg_parser.add_argument("--maps", metavar="OUT.png",
                            help="draw the maps of every RESULTS_DIR side by side into OUT.png")

    def work(args):
        if args.maps:
            return draw_maps(args.maps, args.results_dirs)
        if len(args.results_dirs) != 1:
            arg_parser.error("one RESULTS_DIR, or several with --maps")
        return draw(args.results_dirs[0])

    return cli.run(arg_parser, work, argv)


if __name__ == "__main__":
    raise SystemExit(main())
