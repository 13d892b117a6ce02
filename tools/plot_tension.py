#!/usr/bin/python3
"""Pictures of an elastic tension test written by lem_tension.

Usage: /usr/bin/python3 tools/plot_tension.py RESULTS_DIR
Reads RESULTS_DIR/fields.h5 and summary.json; writes RESULTS_DIR/tension.png:
(a) vertical displacement against height (affine stretch + scatter from the
non-affine relaxation), (b) lateral displacement against x (Poisson
contraction), (c) distribution of bond forces normalised by their mean.
"""
import json
import sys

import h5py
import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    directory = sys.argv[1]
    try:
        with open(f"{directory}/summary.json") as f:
            summary = json.load(f)
        with h5py.File(f"{directory}/fields.h5", "r") as h5:
            x = h5["nodes/coordinates"][:]
            u = h5["nodes/displacement"][:]
            flags = h5["nodes/dof_flags"][:]
            force = h5["bonds/force"][:]
    except (OSError, KeyError, ValueError) as e:
        sys.exit(f"error: cannot read the results in {directory}: {e}")
    live = (flags.astype(int) & 16) == 0  # not pinned
    rng = np.random.default_rng(0)
    pick = rng.choice(np.flatnonzero(live), size=min(20000, live.sum()), replace=False)
    fig, ax = plt.subplots(1, 3, figsize=(13, 4))
    ax[0].plot(x[pick, 2], u[pick, 2], ".", ms=1, alpha=0.4)
    ax[0].set_xlabel("z")
    ax[0].set_ylabel(r"$u_z$")
    ax[0].set_title("vertical displacement")
    ax[1].plot(x[pick, 0], u[pick, 0], ".", ms=1, alpha=0.4)
    ax[1].set_xlabel("x")
    ax[1].set_ylabel(r"$u_x$")
    ax[1].set_title(rf"lateral contraction, $\nu$ = {summary['nu']:.3f}")
    mean = force.mean()
    ax[2].hist(force / mean, bins=200, density=True, log=True)
    ax[2].set_xlabel(r"bond force / mean")
    ax[2].set_ylabel("pdf")
    ax[2].set_title("bond forces")
    fig.suptitle(f"{summary['bonds']} bonds, L_n = {summary['mesh_density_Ln']:.4f}: "
                 f"E_eff = {summary['E_eff']:.4f} k/a (affine {summary['E_affine']:.4f}), "
                 f"{summary['ksp_iterations']} CG iterations", fontsize=10)
    fig.tight_layout()
    out = f"{directory}/tension.png"
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
