#!/usr/bin/python3
"""Node stresses of a cemented sample under tension (Affes et al. 2012, sect. 4).

Usage: /usr/bin/python3 tools/plot_stress.py RESULTS_DIR
Reads RESULTS_DIR/elastic.h5 (written by lem_fracture at the first
equilibrium: node stresses of eq. 1 with their Voronoi volumes) and writes
  RESULTS_DIR/stress.png   (a) map of sigma_zz^i on the mid-plane y = L/2
                           (fig. 7), (b) pdf of sigma_zz^i / sigma_zz with the
                           fitted exponential tail of eq. 2 (fig. 8)
  RESULTS_DIR/stress.json  beta, the fit range and counts, and the volume
                           average of sigma_zz^i against the applied stress.

The map shows the cut of the 3D Voronoi cells by the plane: each pixel takes
the stress of the node nearest to it in 3D.  Nodes without any bond (void
phase) carry no stress and are left out of the pdf; they are drawn white.

Tail exponent: P(s) ~ exp(-beta s) for s = sigma_zz^i / sigma_zz above
TAIL_START; beta is the maximum-likelihood value 1 / mean(s - TAIL_START) of
the nodes in the tail (a least-squares fit of the log-histogram is printed
beside it as a check).
"""
import json
import os
import sys

import h5py
import matplotlib
import numpy as np
from scipy.spatial import cKDTree

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

TAIL_START = 1.0   # s = sigma_zz^i / sigma_zz where the exponential tail is fitted
MAP_PIXELS = 400   # along the longer side of the mid-plane map
BINS = 80


def fail(message):
    sys.stderr.write("plot_stress.py: %s\n" % message)
    sys.exit(1)


def read_elastic(path):
    """Coordinates, Tensor6 stresses, volumes and the applied stress of elastic.h5."""
    if not os.path.isfile(path):
        fail("%s not found (run lem_fracture with -output_fields true on a sample file)" % path)
    try:
        with h5py.File(path, "r") as f:
            if "stress" not in f["nodes"]:
                fail("%s has no node stresses (the lattice had no Voronoi volumes: "
                     "use a sample file)" % path)
            data = {
                "coords": f["nodes/coordinates"][:],
                "stress": f["nodes/stress"][:],
                "volume": f["nodes/volume"][:],
                "applied": float(f.attrs["applied_stress"]),
                "strain": float(f.attrs["strain"]),
            }
    except (OSError, KeyError) as e:
        fail("cannot read %s: %s" % (path, e))
    if not data["applied"] > 0:
        fail("%s: applied stress %g is not positive" % (path, data["applied"]))
    return data


def tail_exponent(s, start=TAIL_START):
    """beta of P(s) ~ exp(-beta s) above `start`: maximum likelihood and log-histogram fit."""
    tail = s[s > start] - start
    if tail.size < 20:
        return None
    beta_ml = 1.0 / tail.mean()
    hist, edges = np.histogram(tail, bins=30, range=(0, np.quantile(tail, 0.99)), density=True)
    centres = 0.5 * (edges[1:] + edges[:-1])
    ok = hist > 0
    slope = np.polyfit(centres[ok], np.log(hist[ok]), 1)[0] if ok.sum() > 3 else float("nan")
    return {"beta": beta_ml, "beta_histogram_fit": -slope, "tail_nodes": int(tail.size),
            "tail_start": start}


def mid_plane_map(coords, values, box_lo, box_hi):
    """Pixels of the plane y = mid-height-in-y: value of the nearest node in 3D."""
    lx, lz = box_hi[0] - box_lo[0], box_hi[2] - box_lo[2]
    nx = MAP_PIXELS if lx >= lz else max(1, int(MAP_PIXELS * lx / lz))
    nz = MAP_PIXELS if lz >= lx else max(1, int(MAP_PIXELS * lz / lx))
    x = box_lo[0] + (np.arange(nx) + 0.5) * lx / nx
    z = box_lo[2] + (np.arange(nz) + 0.5) * lz / nz
    gx, gz = np.meshgrid(x, z)
    y = 0.5 * (box_lo[1] + box_hi[1])
    pixels = np.column_stack([gx.ravel(), np.full(gx.size, y), gz.ravel()])
    _, nearest = cKDTree(coords).query(pixels)
    return values[nearest].reshape(nz, nx), (box_lo[0], box_hi[0], box_lo[2], box_hi[2])


def main():
    if len(sys.argv) != 2:
        fail("usage: plot_stress.py RESULTS_DIR")
    out = sys.argv[1]
    d = read_elastic(os.path.join(out, "elastic.h5"))
    zz = d["stress"][:, 5]  # Tensor6 order xx, xy, xz, yy, yz, zz
    loaded = np.any(d["stress"] != 0, axis=1)
    s = zz[loaded] / d["applied"]
    lo, hi = d["coords"].min(axis=0), d["coords"].max(axis=0)
    box_volume = np.prod(hi - lo)
    mean_zz = float(np.sum(d["volume"] * zz) / box_volume)
    fit = tail_exponent(s)

    result = {
        "applied_stress": d["applied"], "strain": d["strain"],
        "volume_average_stress_zz": mean_zz,
        "volume_average_relative_gap": abs(mean_zz / d["applied"] - 1),
        "nodes": int(zz.size), "loaded_nodes": int(loaded.sum()),
        "tensile_share": float(np.mean(s > 0)),
        "s_min": float(s.min()), "s_max": float(s.max()),
        "tail": fit,
    }

    fig, (ax_map, ax_pdf) = plt.subplots(1, 2, figsize=(12, 5.2))
    values = np.where(loaded, zz / d["applied"], np.nan)
    image, extent = mid_plane_map(d["coords"], values, lo, hi)
    limit = np.nanquantile(np.abs(s), 0.99)
    cmap = matplotlib.colormaps["RdBu_r"].copy()
    cmap.set_bad("white")
    shown = ax_map.imshow(image, origin="lower", extent=extent, cmap=cmap, vmin=-limit,
                          vmax=limit, interpolation="nearest")
    fig.colorbar(shown, ax=ax_map, label=r"$\sigma_{zz}^i / \sigma_{zz}$ (tension > 0)")
    ax_map.set_xlabel("x")
    ax_map.set_ylabel("z")
    ax_map.set_title("(a) node stresses on the mid-plane y = %.2f (void white)"
                     % (0.5 * (lo[1] + hi[1])))

    hist, edges = np.histogram(s, bins=BINS, density=True)
    centres = 0.5 * (edges[1:] + edges[:-1])
    ok = hist > 0
    ax_pdf.semilogy(centres[ok], hist[ok], "o", ms=4, color="black", label="nodes")
    if fit:
        above = s > TAIL_START
        share = above.mean()
        xs = np.linspace(TAIL_START, s.max(), 50)
        # The tail's own density, scaled by its share of the nodes.
        ax_pdf.semilogy(xs, share * fit["beta"] * np.exp(-fit["beta"] * (xs - TAIL_START)), ":",
                        color="tab:red", lw=2,
                        label=r"$\propto e^{-\beta s}$, $\beta$ = %.2f (ML; log-fit %.2f)"
                        % (fit["beta"], fit["beta_histogram_fit"]))
    ax_pdf.set_xlabel(r"$s = \sigma_{zz}^i / \sigma_{zz}$")
    ax_pdf.set_ylabel("pdf")
    ax_pdf.set_title("(b) pdf of the vertical node stresses (%d loaded nodes)" % loaded.sum())
    ax_pdf.legend()
    fig.suptitle(r"%s: first equilibrium, $\varepsilon_{zz}$ = %.2e; volume average of "
                 r"$\sigma_{zz}^i$ / applied = %.8f" % (os.path.basename(os.path.abspath(out)), d["strain"],
                                                        mean_zz / d["applied"]))
    fig.tight_layout()
    tmp = os.path.join(out, ".stress.png.part")
    fig.savefig(tmp, dpi=110, format="png")
    os.replace(tmp, os.path.join(out, "stress.png"))
    with open(os.path.join(out, ".stress.json.part"), "w") as f:
        json.dump(result, f, indent=2)
    os.replace(os.path.join(out, ".stress.json.part"), os.path.join(out, "stress.json"))
    print("stress: beta = %s, volume average / applied = %.8f -> %s/stress.png"
          % ("%.3f" % fit["beta"] if fit else "n/a", mean_zz / d["applied"], out))


if __name__ == "__main__":
    main()
