"""Plot E_eff/E^[m] against the mesh density L_n (paper fig. 6).

Reads RESULTS_DIR/convergence.csv and fit.csv written by lem_convergence and
writes RESULTS_DIR/convergence.png.  An optional second run (for example with
-inclusion_void_bonds both_ends) is drawn with open symbols.
"""
from . import cli
from .analysis import hashin_shtrikman
from .plotting import plt, save_figure
from .results import read_csv

CASES = (("stiff", "E_stiff_over_matrix", "tab:blue", "stiff inclusions (x10)", 10.0),
         ("pore", "E_pore_over_matrix", "tab:red", "pores", 0.0))
INCLUSION_FRACTION = 0.2  # of lem_convergence's samples


def draw(runs):
    fig, ax = plt.subplots(figsize=(6, 4.5))
    for k, (directory, label) in enumerate(runs):
        table = read_csv(f"{directory}/convergence.csv", ("Ln",), need_rows=True)
        fits = read_csv(f"{directory}/fit.csv", ("case",), need_rows=True).records_by("case")
        ln = list(table.numbers("Ln"))
        xs = [0.0] + ln
        for case, column, colour, name, _ in CASES:
            face = colour if k == 0 else "none"
            ax.plot(ln, list(table.numbers(column)), "o" if k == 0 else "s", color=colour,
                    mfc=face, label=f"{name}, {label}" if len(runs) > 1 else name)
            if case in fits:
                e0 = float(fits[case]["extrapolated_E_over_Em"])
                alpha = float(fits[case]["alpha_E"])
                ax.plot(xs, [e0 + alpha * x for x in xs], ":", color=colour)
    for _, _, colour, _, ratio in CASES:
        ax.axhline(hashin_shtrikman(INCLUSION_FRACTION, ratio), color=colour, lw=0.8, alpha=0.5)
    ax.set_xlabel(r"mesh density $L_n = M^{-1/3}$")
    ax.set_ylabel(r"$E_{\rm eff} / E^{[m]}$")
    ax.set_xlim(left=0)
    ax.set_title("Mesh-density convergence, 20% inclusions (lines: HS estimates)", fontsize=10)
    ax.legend(fontsize=8)
    fig.tight_layout()
    out = f"{runs[0][0]}/convergence.png"
    save_figure(fig, out, dpi=130)
    print(f"wrote {out}")


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("results_dir", metavar="RESULTS_DIR",
                            help="output folder of lem_convergence; the figure goes there")
    arg_parser.add_argument("second_dir", nargs="?", metavar="RESULTS_DIR_2",
                            help="a second run, drawn with open symbols")
    arg_parser.add_argument("second_label", nargs="?", metavar="LABEL_2",
                            help="the second run's legend label")

    def work(args):
        if (args.second_dir is None) != (args.second_label is None):
            arg_parser.error("a second run needs both RESULTS_DIR_2 and LABEL_2")
        runs = [(args.results_dir, "any-end void rule")]
        if args.second_dir is not None:
            runs.append((args.second_dir, args.second_label))
        draw(runs)
    return cli.run(arg_parser, work, argv)


if __name__ == "__main__":
    raise SystemExit(main())
