"""Pictures of an elastic tension test written by lem_tension.

Reads RESULTS_DIR/fields.h5 and summary.json; writes RESULTS_DIR/tension.png:
(a) vertical displacement against height (affine stretch + scatter from the
non-affine relaxation), (b) lateral displacement against x (Poisson
contraction), (c) distribution of bond forces normalised by their mean.
"""
import numpy as np

from . import cli
from .plotting import plt, save_figure
from .results import read_hdf5, read_summary

PINNED = 16           # dof_flags bit of a pinned node
MAX_POINTS = 20000    # nodes drawn in the displacement panels


def draw(directory):
    summary = read_summary(f"{directory}/summary.json")
    fields = read_hdf5(f"{directory}/fields.h5", ("nodes/coordinates", "nodes/displacement",
                                                  "nodes/dof_flags", "bonds/force"))
    x, u = fields["nodes/coordinates"], fields["nodes/displacement"]
    force = fields["bonds/force"]
    live = (fields["nodes/dof_flags"].astype(int) & PINNED) == 0
    rng = np.random.default_rng(0)
    pick = rng.choice(np.flatnonzero(live), size=min(MAX_POINTS, live.sum()), replace=False)
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
    save_figure(fig, out, dpi=110)
    print(f"wrote {out}")


def main(argv=None):
    return cli.run_on_folder(__doc__, "output folder of lem_tension", draw, argv)


if __name__ == "__main__":
    raise SystemExit(main())
