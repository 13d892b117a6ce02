"""What every figure module shares: matplotlib without a display, phase
colours, the star marks of the paper's values, and saving a figure through
the atomic writer."""
import os

import matplotlib

matplotlib.use("Agg")  # files only: no display on the machines that run studies
import matplotlib.pyplot as plt  # noqa: E402

from .files import atomic_path  # noqa: E402

PHASE_COLORS = {"p": "tab:red", "m": "tab:blue", "pp": "tab:green", "pm": "tab:orange"}
OTHER_PHASE_COLOR = "0.4"


def phase_color(phase):
    return PHASE_COLORS.get(phase, OTHER_PHASE_COLOR)


# The paper's values (paper.paper_values) on every figure: a star edged in black.
PAPER_MARK_STYLE = dict(marker="*", linestyle="none", markeredgecolor="black", markersize=12,
                        zorder=5)


def paper_mark(ax, x, y, label, color="gold"):
    """The paper's values at abscissae `x` and ordinates `y` (sequences) as
    stars, one legend entry `label` for them all; returns their Line2D."""
    return ax.plot(x, y, color=color, label=label, **PAPER_MARK_STYLE)[0]


def save_figure(fig, path, also=(), **savefig_args):
    """Write `fig` to `path` (format from its extension, PNG without one),
    and beside it with each extension of `also` (e.g. ".pdf"), and close it."""
    stem = os.path.splitext(path)[0]
    try:
        for target in [path] + [stem + extension for extension in also]:
            extension = os.path.splitext(target)[1][1:].lower()
            with atomic_path(target) as temporary:
                fig.savefig(temporary, format=extension or "png", **savefig_args)
    finally:
        plt.close(fig)
