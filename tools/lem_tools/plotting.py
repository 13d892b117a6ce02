"""What every figure module shares: matplotlib without a display, phase
colours, and saving a figure through the atomic writer."""
import os

import matplotlib

matplotlib.use("Agg")  # files only: no display on the machines that run studies
import matplotlib.pyplot as plt  # noqa: E402

from .files import atomic_path  # noqa: E402

PHASE_COLORS = {"p": "tab:red", "m": "tab:blue", "pp": "tab:green", "pm": "tab:orange"}
OTHER_PHASE_COLOR = "0.4"


def phase_color(phase):
    return PHASE_COLORS.get(phase, OTHER_PHASE_COLOR)


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
