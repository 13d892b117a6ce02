"""The study's figures (study_plots): the paper's values as stars at their
converted values, replicate means and standard deviations as what is
plotted, the resolution in the subtitle, and the gather step drawing them
and fitting eq. 10 to what it draws."""
import json
import os
import shutil

import numpy as np
import pytest

from conftest import write_curve, write_manifest, write_study_file
from lem_tools import analysis, paper, study, study_plots
from lem_tools.plotting import plt
from lem_tools.study import Study

PHASES = {"E_p": 2.5, "E_m": 1.0, "E_pp": 1.0, "E_pm": 1.0, "sigma_p": 0.01}
RHOS, RATIOS = (0.06, 0.28), (0.5, 1.0)
# the replicates' share: pack seed 1 below the point's value, 3 above it
SPREAD = {1: -0.02, 2: 0.0, 3: 0.02}
RESOLUTION = {"sample_particles": 64, "bonds": 80000.0, "bonds_per_particle": 1250.0,
              "L_n": 80000 ** (-1 / 3), "bonds_from": "samples", "runs_per_point": [1, 1]}


def value(rho, ratio, d=0.0):
    """A run's value: known per grid point, shifted by its replicate's d."""
    return rho + 0.1 * ratio + d


def synthetic_rows(seeds=(1,)):
    """Rows of results.csv (what the figures read): one run per grid point
    and pack seed."""
    rows = []
    for seed in seeds:
        for rho in RHOS:
            for ratio in RATIOS:
                v = value(rho, ratio, SPREAD[seed])
                rows.append({"id": "p%d_%g_%g" % (seed, rho, ratio), "lattice": "p%d" % seed,
                             "rho_m": rho, "sigma_pm_ratio": ratio, "E_eff_over_E_unit": v,
                             "sigma_eff_over_sigma_unit": 2 * v, "sigma_eff_over_sigma_pm": 3 * v,
                             "n_b": 0.1 * v, "n_b_without_bare_contacts": 0.5 * v,
                             "K_c_r_eq14": 4 * v, "beta": 1 + v})
    return rows


def curves_of(points):
    strain = np.array([0.0, 1e-3, 2e-3])
    return {run: {"strain": strain, "n_b": np.array([0.0, 0.01, 0.02])}
            for p in study_plots.damage_curve_picks(points) for run in p["runs"]}


def figures(rows, resolution=RESOLUTION):
    """The three figures of `rows`, as draw_all draws them."""
    points = analysis.replicate_means(rows, study_plots.COLUMNS)
    samples = analysis.sample_means(rows)
    fit = analysis.fit_eq10([p["rho_m"] for p in points],
                            [p["sigma_eff_over_sigma_pm"] for p in points])
    return (study_plots.strength_figure(points, fit, resolution),
            study_plots.damage_figure(points, samples, curves_of(points), PHASES, resolution),
            study_plots.stiffness_stress_figure(samples, PHASES, resolution))


@pytest.fixture
def close_figures():
    yield
    plt.close("all")


def drawn(ax):
    """[(x, y, x half-bars, y half-bars)] of the error-bar containers of `ax`
    (None where a container has no bars)."""
    out = []
    for c in ax.containers:
        line, _, columns = c.lines
        half = [[(s[1][axis] - s[0][axis]) / 2 for s in lc.get_segments()]
                for axis, lc in zip([0] * c.has_xerr + [1] * c.has_yerr, columns)]
        xerr = half.pop(0) if c.has_xerr else None
        out.append((list(line.get_xdata()), list(line.get_ydata()), xerr,
                    half.pop(0) if c.has_yerr else None))
    return out


def stars(ax):
    return [line for line in ax.get_lines() if line.get_marker() == "*"]


# --- the paper's values -------------------------------------------------------

def test_paper_values_in_the_units_of_the_figures():
    # moduli through E_m/E_p: 1.6 E^[m] = 1.6 / 2.5 E^[p]; beta is a pure number
    assert paper.paper_values("E_eff_over_E_unit", PHASES) == [
        (0.28, pytest.approx(1.6 / 2.5), "sect. 3", "1.6 $E^{[m]}$")]
    assert [(r, v) for r, v, *_ in paper.paper_values("beta", PHASES)] == [(0.06, 0.7),
                                                                            (0.28, 2.1)]
    assert paper.paper_source("beta") == "sect. 4, fig. 8"
    assert paper.paper_values("n_b", PHASES) == [] and paper.paper_source("n_b") is None
    # the convergence figures mark them only at their own matrix fractions
    assert paper.paper_marks("beta", [0.06, 0.13], PHASES) == [(0.06, 0.7)]


def test_stiffness_figure_stars_the_paper_at_its_converted_values(close_figures):
    *_, stiffness = figures(synthetic_rows())
    a, b = stiffness.axes
    (modulus,) = stars(a)
    assert list(modulus.get_xdata()) == [0.28]
    assert list(modulus.get_ydata()) == [pytest.approx(1.6 * 1.0 / 2.5)]
    assert modulus.get_label().startswith("paper, sect. 3")
    (beta,) = stars(b)
    assert list(beta.get_xdata()) == [0.06, 0.28]
    assert list(beta.get_ydata()) == [0.7, 2.1]
    # each has its legend entry
    for ax, star in ((a, modulus), (b, beta)):
        assert star.get_label() in [t.get_text() for t in ax.get_legend().get_texts()]
    # the other figures have no value of the paper to mark
    strength, damage, _ = figures(synthetic_rows())
    assert not any(stars(ax) for ax in strength.axes + damage.axes)


def test_convergence_figures_share_the_paper_marks(close_figures):
    from lem_tools import convergence_plots

    level = {"L_n": 0.02, "mean": 1.0, "std": 0.1, "n": 3}
    results = {("beta", rho, 1.0): {"levels": [level], "fit": None, "extrapolated_se": 0.0}
               for rho in (0.06, 0.13)}
    fig, ax = plt.subplots()
    convergence_plots.panel(ax, results, "beta", "beta", {}, {"phases": PHASES})
    (star,) = stars(ax)
    assert list(star.get_ydata()) == [0.7]
    assert star.get_label() == r"paper, $\rho^m$ = 0.06 (sect. 4, fig. 8)"


# --- replicates -------------------------------------------------------------------

def test_replicates_are_plotted_as_their_mean_and_standard_deviation(close_figures):
    rows = synthetic_rows(seeds=(1, 2, 3))
    std = np.std([SPREAD[s] for s in (1, 2, 3)], ddof=1)        # 0.02
    strength, damage, stiffness = figures(rows, dict(RESOLUTION, runs_per_point=[3, 3]))
    # strength (a): one series per rho^m against sigma^pm, means and their bars
    series = drawn(strength.axes[0])
    assert len(series) == len(RHOS)
    for rho, (x, y, xerr, yerr) in zip(RHOS, series):
        assert x == list(RATIOS) and xerr is None
        assert y == pytest.approx([2 * value(rho, ratio) for ratio in RATIOS])
        assert yerr == pytest.approx([2 * std] * len(RATIOS))
    # strength (b): sigma_eff / sigma^pm, the values eq. 10 is fitted to
    for rho, (_, y, _, yerr) in zip(RHOS, drawn(strength.axes[1])):
        assert y == pytest.approx([3 * value(rho, ratio) for ratio in RATIOS])
        assert yerr == pytest.approx([3 * std] * len(RATIOS))
    # damage (b) n_b against sigma^pm, (c) without the bare contacts; (e)
    # against K_c^r, with bars both ways
    for rho, (_, y, _, yerr) in zip(RHOS, drawn(damage.axes[1])):
        assert y == pytest.approx([0.1 * value(rho, ratio) for ratio in RATIOS])
        assert yerr == pytest.approx([0.1 * std] * len(RATIOS))
    for rho, (_, y, _, yerr) in zip(RHOS, drawn(damage.axes[2])):
        assert y == pytest.approx([0.5 * value(rho, ratio) for ratio in RATIOS])
        assert yerr == pytest.approx([0.5 * std] * len(RATIOS))
    for rho, (x, _, xerr, _) in zip(RHOS, drawn(damage.axes[4])):
        assert x == pytest.approx([4 * value(rho, ratio) for ratio in RATIOS])
        assert xerr == pytest.approx([4 * std] * len(RATIOS))
    # stiffness: per sample the mean modulus over its runs, then over the samples
    ((x, y, _, yerr),) = drawn(stiffness.axes[0])
    assert x == list(RHOS)
    assert y == pytest.approx([np.mean([value(rho, r) for r in RATIOS]) for rho in RHOS])
    assert yerr == pytest.approx([std, std])
    # beta: each sample's run at the lowest sigma^pm
    ((_, y, _, yerr),) = drawn(stiffness.axes[1])
    assert y == pytest.approx([1 + value(rho, RATIOS[0]) for rho in RHOS])
    assert yerr == pytest.approx([std, std])


def test_single_runs_are_plotted_as_they_are(close_figures):
    rows = synthetic_rows(seeds=(3,))
    strength, _, stiffness = figures(rows)
    for rho, (_, y, xerr, yerr) in zip(RHOS, drawn(strength.axes[0])):
        assert y == pytest.approx([2 * value(rho, ratio, SPREAD[3]) for ratio in RATIOS])
        assert xerr is None and yerr is None
    assert all(yerr is None for *_, yerr in drawn(stiffness.axes[1]))


def test_replicate_means_keep_the_runs_of_each_point():
    rows = synthetic_rows(seeds=(1, 2, 3))
    points = analysis.replicate_means(rows, ["n_b"])
    assert [(p["rho_m"], p["sigma_pm_ratio"]) for p in points] == [
        (rho, ratio) for rho in RHOS for ratio in RATIOS]
    assert points[0]["replicates"] == 3
    assert points[0]["runs"] == ["p1_0.06_0.5", "p2_0.06_0.5", "p3_0.06_0.5"]
    single = analysis.replicate_means(synthetic_rows(), ["n_b"])
    assert single[0]["std"] == {"n_b": 0.0} and single[0]["replicates"] == 1


# --- the resolution ---------------------------------------------------------------

def test_every_figure_says_its_resolution(close_figures):
    for fig in figures(synthetic_rows()):
        assert fig._suptitle.get_text() == (
            r"64 particles, 1 250 bonds per particle ($L_n$ = 0.023), one sample per $\rho^m$")
    text = study_plots.resolution_text(dict(RESOLUTION, runs_per_point=[2, 3]))
    assert text.endswith(r"2–3 samples per $\rho^m$ (seeds): mean ± standard deviation")
    asked = study_plots.resolution_text(dict(RESOLUTION, bonds_from="study file"))
    assert "1 250 bonds per particle asked" in asked
    unknown = dict(RESOLUTION, bonds=None, bonds_per_particle=None, L_n=None)
    assert study_plots.resolution_text(unknown) == r"64 particles, one sample per $\rho^m$"


# --- the gather step ------------------------------------------------------------------

REPLICATED = """name: r
ranks: 1
sample: {sample_particles: 64}
lattice_bonds_per_particle: [600, 1250]
pack_seeds: [1, 2, 3]
replicates_up_to: 1250
matrix_fractions: [0.06, 0.28]
sigma_pm_ratios: [0.5, 1.0]
"""
BONDS = {1: 79000, 2: 80000, 3: 81000}   # what lem_sample counts for 80 000 asked


def write_json(path, data):
    with open(path, "w") as f:
        json.dump(data, f)


def replicated_study(tmp_path):
    """Samples and runs of REPLICATED written here: three packings at each
    size, the run values value(rho, ratio) + SPREAD at 1250 bonds per
    particle, something else at 600."""
    s = Study(write_study_file(tmp_path, REPLICATED, "r.yaml"), str(tmp_path / "out"))
    s.plan()
    os.makedirs(os.path.join(s.out, "samples"))
    for sample in s.samples():
        write_json(os.path.join(s.out, "samples", sample["stem"] + "_summary.json"),
                   {"bonds": BONDS[sample["lattice"]["pack_seed"]] * sample["lattice"]["level"]
                    // 1250, "rho_m": sample["rho_m"]})
    for run in s.runs():
        lattice = s.lattice_of(run)
        v = value(run["rho_m"], run["sigma_pm_ratio"], SPREAD[lattice["pack_seed"]])
        if lattice["level"] != 1250:
            v = 10.0                            # not the figures' size: never drawn
        d = s.run_dir(run)
        os.makedirs(d)
        write_json(os.path.join(d, "run.json"), s.run_record(run))
        write_json(os.path.join(d, "summary.json"), {
            "E_eff_over_E_unit": v, "sigma_eff_over_sigma_unit": 2 * v,
            "sigma_eff": 3 * v * run["sigma_pm_ratio"] * 0.01, "strain_at_peak": 4e-3,
            "n_b": 0.1 * v, "broken": 20, "broken_p": 2, "broken_m": 4, "broken_pp": 10,
            "broken_pm": 4, "end_reason": "stress below the stop fraction of the peak",
            "solves": 7, "seconds": 1.0})
        write_curve(os.path.join(d, "curve.csv"), [(1e-4, 0.1, 0.1, 0, 0, 10, 0),
                                                   (2e-4, 0.2, 0.1, 2, 4, 10, 4)])
        write_json(os.path.join(d, "stress.json"), {"tail": {"beta": 1 + v}})
        write_manifest(d, ("summary.json", "curve.csv"))
    return s


@pytest.mark.long  # draws every figure of a study: 5-8 s
def test_gather_draws_and_fits_the_replicate_means(tmp_path, monkeypatch, close_figures):
    s = replicated_study(tmp_path)
    saved = {}
    real_save = study_plots.save_figure

    def keep(fig, path, **args):
        saved[os.path.basename(path)] = fig
        real_save(fig, path, **args)
    monkeypatch.setattr(study_plots, "save_figure", keep)   # a closed figure keeps its artists
    assert study.gather(s) == 0
    with open(os.path.join(s.out, "fit.json")) as f:
        fit = json.load(f)
    tags = ["bpp1250_p1", "bpp1250_p2", "bpp1250_p3"]
    assert fit["figures_lattice"] == "bpp1250_p1" and fit["figures_lattices"] == tags
    assert fit["figures"] == {
        "sample_particles": 64, "bonds": 80000.0, "bonds_per_particle": 1250.0,
        "L_n": pytest.approx(np.mean([b ** (-1 / 3) for b in BONDS.values()])),
        "bonds_from": "samples", "runs_per_point": [3, 3]}
    # eq. 10 is fitted to the plotted means, not to one lattice's runs
    means = [3 * value(rho, ratio) for rho in RHOS for ratio in RATIOS]
    rhos = [rho for rho in RHOS for _ in RATIOS]
    expected = analysis.fit_eq10(rhos, means)
    assert fit["eq10"]["A"] == pytest.approx(expected["A"], rel=1e-6)
    assert fit["eq10"]["k"] == pytest.approx(expected["k"], rel=1e-6)
    first = analysis.fit_eq10(rhos, [m + 3 * SPREAD[1] for m in means])
    assert fit["eq10"]["A"] != pytest.approx(first["A"], rel=1e-3)
    assert "mean over its replicates" in fit["eq10_fitted_to"]
    assert fit["beta_by_rho_m"] == {"%.4f" % rho: pytest.approx(1 + value(rho, RATIOS[0]))
                                    for rho in RHOS}
    assert fit["beta_std_by_rho_m"] == {"%.4f" % rho: pytest.approx(0.02) for rho in RHOS}
    # what was drawn: the means with their standard deviations, and the resolution
    strength = saved["strength.png"]
    for rho, (_, y, _, yerr) in zip(RHOS, drawn(strength.axes[0])):
        assert y == pytest.approx([2 * value(rho, ratio) for ratio in RATIOS])
        assert yerr == pytest.approx([0.04, 0.04])
    for name in ("strength", "damage", "stiffness_stress"):
        assert saved[name + ".png"]._suptitle.get_text() == (
            r"64 particles, 1 250 bonds per particle ($L_n$ = 0.023), "
            r"3 samples per $\rho^m$ (seeds): mean ± standard deviation")
        assert os.path.getsize(os.path.join(s.out, "figures", name + ".pdf")) > 0
    # damage (a): the picked points' curves of every replicate
    assert len(saved["damage.png"].axes[0].get_lines()) == 3 * 3


@pytest.mark.long  # draws every figure of a study: 5-8 s
def test_gather_before_the_finest_runs_draws_the_finest_complete_size(tmp_path):
    """A gather while the finest size's runs are still to come (a study cut
    short, or still running) draws the paper's figures at the finest size
    that has complete runs, not nothing."""
    s = replicated_study(tmp_path)
    for run in s.runs():
        if s.lattice_of(run)["level"] == 1250:
            shutil.rmtree(s.run_dir(run))
    assert study.gather(s) == 1                     # the 1250 runs are missing
    with open(os.path.join(s.out, "fit.json")) as f:
        fit = json.load(f)
    assert fit["figures_lattices"] == ["bpp600_p1", "bpp600_p2", "bpp600_p3"]
    assert fit["figures"]["bonds_per_particle"] == pytest.approx(
        np.mean([b * 600 // 1250 for b in BONDS.values()]) / 64)
    assert fit["eq10"] is not None
    assert os.path.getsize(os.path.join(s.out, "figures", "strength.png")) > 0


@pytest.mark.long  # draws every figure of a study: 5-8 s
def test_gather_draws_the_finest_size_whose_grid_is_whole(tmp_path):
    """One run missing at the finest size: the figures come from the size
    below, whose every grid point is there, not from part of a grid."""
    s = replicated_study(tmp_path)
    finest = [run for run in s.runs() if s.lattice_of(run)["level"] == 1250]
    shutil.rmtree(s.run_dir(finest[0]))
    assert study.gather(s) == 1
    with open(os.path.join(s.out, "fit.json")) as f:
        fit = json.load(f)
    assert fit["figures_lattices"] == ["bpp600_p1", "bpp600_p2", "bpp600_p3"]
