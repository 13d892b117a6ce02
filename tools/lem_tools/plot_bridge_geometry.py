"""Draw the matrix bridge of lem's cemented samples in an axial section.

Two particles (radii r_i, r_j) and the frustum joining their centres with
radii lambda*r_i and lambda*r_j; the matrix is the part of the frustum
outside both particles (hatched), for two values of lambda.
"""
import numpy as np
from matplotlib.patches import Circle, Polygon

from . import cli
from .plotting import plt, save_figure

LAMBDAS = (0.45, 0.8)


def draw(out):
    ri, rj, gap = 0.5, 0.6, 0.25
    ci, cj = np.array([0.0, 0.0]), np.array([ri + rj + gap, 0.0])
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
    for ax, lam in zip(axes, LAMBDAS):
        corners = [(ci[0], lam * ri), (cj[0], lam * rj), (cj[0], -lam * rj), (ci[0], -lam * ri)]
        frustum = Polygon(corners, closed=True, facecolor="tab:orange", alpha=0.55, hatch="//",
                          edgecolor="tab:orange",
                          label="matrix bridge (frustum outside the particles)")
        ax.add_patch(frustum)
        for c, r in ((ci, ri), (cj, rj)):
            ax.add_patch(Circle(c, r, facecolor="0.35", edgecolor="k", zorder=3))
        ax.plot([ci[0], cj[0]], [0, 0], "k--", lw=0.7, zorder=4)
        ax.annotate(r"$\lambda r_i$", (ci[0] + 0.02, lam * ri / 2), zorder=5, color="w")
        gap_middle = (ci[0] + ri + cj[0] - rj) / 2
        ax.annotate(r"gap $\delta \leq \delta_{max}$", (gap_middle - 0.12, -0.95))
        ax.set_xlim(-0.7, cj[0] + 0.8)
        ax.set_ylim(-1.0, 1.0)
        ax.set_aspect("equal")
        ax.set_title(rf"$\lambda$ = {lam}")
        ax.axis("off")
    axes[0].legend(loc="upper center", fontsize=8, bbox_to_anchor=(1.1, 1.18))
    save_figure(fig, out, dpi=120, bbox_inches="tight")
    print(f"wrote {out}")


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("out", metavar="OUT.png", help="the picture to write")
    return cli.run(arg_parser, lambda args: draw(args.out), argv)


if __name__ == "__main__":
    raise SystemExit(main())
