"""Convergence in L_n and replicates: the fit and its uncertainty, the
replicate statistics, the resolution and replicate axes of a study file and
the convergence part of the gather step, on cases whose answer is known."""
import csv
import json
import math
import os

import numpy as np
import pytest

from conftest import write_curve, write_manifest, write_study_file
from lem_tools import convergence, convergence_plots, study, study_combine, study_plots
from lem_tools.study import Study, StudyError, load_study

# --- the numbers ------------------------------------------------------------


def test_replicate_stats():
    s = convergence.replicate_stats([1.0, 2.0, 4.0, float("nan"), None])
    assert s["n"] == 3
    assert s["mean"] == pytest.approx(7 / 3)
    assert s["std"] == pytest.approx(np.std([1, 2, 4], ddof=1))
    assert s["sem"] == pytest.approx(s["std"] / math.sqrt(3))
    assert (s["min"], s["max"]) == (1.0, 4.0)
    one = convergence.replicate_stats([5.0])
    assert one["n"] == 1 and one["mean"] == 5.0 and math.isnan(one["std"])
    assert convergence.replicate_stats([])["n"] == 0


def test_pooled_std_weights_each_level_by_its_degrees_of_freedom():
    stats = [convergence.replicate_stats(v) for v in ([1, 3], [0, 0, 6], [9])]
    # (1 * 2 + 2 * 12) / (1 + 2): variances 2 and 12, one single run left out
    assert convergence.pooled_std(stats) == pytest.approx(math.sqrt(26 / 3))
    assert math.isnan(convergence.pooled_std([convergence.replicate_stats([1.0])]))


def test_weighted_fit_of_an_exact_line_gives_the_analytic_standard_errors():
    x = np.array([0.04, 0.03, 0.02, 0.01])
    y = 2.0 - 5.0 * x
    sigma = np.array([0.1, 0.2, 0.1, 0.3])
    fit = convergence.fit_line(x, y, sigma)
    assert fit["intercept"] == pytest.approx(2.0)
    assert fit["slope"] == pytest.approx(-5.0)
    assert fit["chi2"] == pytest.approx(0.0, abs=1e-20) and fit["dof"] == 2
    # chi^2 = 0 < dof: the standard errors are those of the weights alone
    w = 1 / sigma ** 2
    det = w.sum() * (w * x * x).sum() - (w * x).sum() ** 2
    assert fit["intercept_se"] == pytest.approx(math.sqrt((w * x * x).sum() / det))
    assert fit["slope_se"] == pytest.approx(math.sqrt(w.sum() / det))


def test_unweighted_fit_matches_scipy():
    from scipy.stats import linregress

    x = np.array([0.05, 0.04, 0.03, 0.02, 0.012])
    y = np.array([1.18, 1.185, 1.24, 1.264, 1.327])
    fit = convergence.fit_line(x, y)
    ref = linregress(x, y)
    assert fit["intercept"] == pytest.approx(ref.intercept)
    assert fit["slope"] == pytest.approx(ref.slope)
    assert fit["intercept_se"] == pytest.approx(ref.intercept_stderr)
    assert fit["slope_se"] == pytest.approx(ref.stderr)
    assert not fit["weighted"]
    assert convergence.fit_line([0.1, 0.1], [1, 2]) is None


def test_extrapolation_and_its_uncertainty_on_synthetic_replicates():
    """y = 0.5 - 8 L_n plus Gaussian scatter 0.02: over many draws the
    extrapolated values centre on 0.5 and spread as their standard errors say."""
    rng = np.random.default_rng(14)
    l_n = [0.037, 0.029, 0.023, 0.018]
    replicates = [4, 4, 1, 1]
    truth, slope, scatter = 0.5, -8.0, 0.02
    values, errors, covered = [], [], 0
    for _ in range(2000):
        levels = [(l, list(truth + slope * l + scatter * rng.standard_normal(n)))
                  for l, n in zip(l_n, replicates)]
        r = convergence.extrapolate(levels)
        values.append(r["extrapolated"])
        errors.append(r["extrapolated_se"])
        covered += abs(r["extrapolated"] - truth) <= 2 * r["extrapolated_se"]
        assert r["fit"]["weighted"]
    assert np.mean(values) == pytest.approx(truth, abs=3 * np.std(values) / math.sqrt(2000))
    # the reported standard error is the spread of the estimates (within 15 %)
    assert np.median(errors) == pytest.approx(np.std(values), rel=0.15)
    assert covered / 2000 > 0.9


def test_scatter_against_discretisation_error():
    """Means on y = 1 + 10 L_n, single-run scatter 0.25: the distance to the
    extrapolated value (10 L_n: 0.4, 0.3, 0.2, 0.1) falls below the scatter
    from L_n = 0.02 on, and the line is one scatter from its intercept at
    L_n* = 0.25 / 10."""
    d = 0.25 / math.sqrt(2)   # two replicates m -/+ d have a standard deviation 0.25
    levels = [(l, [1 + 10 * l - d, 1 + 10 * l + d]) for l in (0.01, 0.04, 0.02, 0.03)]
    r = convergence.extrapolate(levels, labels=["fine", "coarse", "mid", "coarser"])
    assert [e["label"] for e in r["levels"]] == ["coarse", "coarser", "mid", "fine"]
    assert r["extrapolated"] == pytest.approx(1.0)
    assert r["scatter"] == pytest.approx(0.25)
    assert [e["error"] for e in r["levels"]] == pytest.approx([0.4, 0.3, 0.2, 0.1])
    assert r["levels"][r["scatter_from"]]["label"] == "mid"
    assert r["L_n_scatter_dominates"] == pytest.approx(0.025)
    # without replicates there is no scatter to compare with
    single = convergence.extrapolate([(l, [1 + 10 * l]) for l in (0.01, 0.02, 0.03)])
    assert single["scatter_from"] is None and math.isnan(single["L_n_scatter_dominates"])
    assert not single["fit"]["weighted"]
    assert single["extrapolated"] == pytest.approx(1.0)
    assert convergence.extrapolate([(0.02, [1.0, 1.1])])["fit"] is None


# --- the study file's axes ---------------------------------------------------

AXES = """name: c
ranks: 2
sample: {sample_particles: 516}
lattice_bonds_per_particle: [1250, 2500, 5000]
pack_seeds: [1, 2, 3]
lattice_seeds: [4, 5, 6]
replicates_up_to: 2500
fracture_up_to: 2500
elastic: true
matrix_fractions: [0.06, 0.28]
sigma_pm_ratios: [0.6, 1.0]
"""


def study_file(tmp_path, text=AXES, name="c.yaml"):
    return write_study_file(tmp_path, text, name)


def test_axes_expand_into_the_run_list(tmp_path):
    s = Study(study_file(tmp_path), str(tmp_path / "out"))
    tags = [l["tag"] for l in s.lattices]
    assert len(tags) == 9 + 9 + 1
    assert tags[:3] == ["bpp1250_p1_l4", "bpp1250_p1_l5", "bpp1250_p1_l6"]
    assert tags[9] == "bpp2500_p1_l4" and tags[-1] == "bpp5000_p1_l4"
    assert s.lattices[-1]["sample_options"] == {"lattice_bonds": 5000 * 516, "pack_seed": 1,
                                                "lattice_seed": 4}
    assert s.lattices[0]["sample_options"]["lattice_bonds"] == 645000
    assert [l["fracture"] for l in s.lattices] == [True] * 18 + [False]
    samples = s.samples()
    assert len(samples) == 19 * 2
    assert samples[0]["stem"] == "bpp1250_p1_l4_rho_0.0600"
    runs = s.runs()
    assert len(runs) == 18 * 2 * 2
    assert runs[0] == {"id": "bpp1250_p1_l4_rho_0.0600_spm_0.6000", "rho_m": 0.06,
                       "sigma_pm_ratio": 0.6, "lattice": "bpp1250_p1_l4"}
    assert s.sample_file(s.lattice_of(runs[-1]), runs[-1]["rho_m"]).endswith(
        os.path.join("samples", "bpp2500_p3_l6_rho_0.2800.h5"))
    pulls = s.elastic_pulls()
    assert len(pulls) == 19 * 2 * 2
    assert pulls[-1]["id"] == "bpp5000_p1_l4_rho_0.2800_adhesive"
    assert s.calibration_dir(s.lattices[3]).endswith(os.path.join("calibration",
                                                                  "bpp1250_p2_l4"))


def test_axes_in_bonds_and_a_single_seed_axis(tmp_path):
    text = ("name: c\nsample: {sample_particles: 27}\nlattice_bonds: [20000, 40000]\n"
            "pack_seeds: [1, 2]\nmatrix_fractions: [0.13]\nsigma_pm_ratios: [1.0]\n")
    s = Study(study_file(tmp_path, text), str(tmp_path / "out"))
    assert [l["tag"] for l in s.lattices] == ["b20000_p1", "b20000_p2", "b40000_p1",
                                              "b40000_p2"]
    assert s.lattices[1]["sample_options"] == {"lattice_bonds": 20000, "pack_seed": 2}
    assert s.lattices[1]["lattice_seed"] == 1      # lem_sample's default, for the tables
    assert s.elastic_pulls() == []
    assert [r["id"] for r in s.runs()][:1] == ["b20000_p1_rho_0.1300_spm_1.0000"]


def test_subset_keys_leave_the_hash_alone(tmp_path):
    one = study.study_hash(load_study(study_file(tmp_path)))
    wider = AXES.replace("fracture_up_to: 2500", "fracture_up_to: 5000").replace(
        "replicates_up_to: 2500", "replicates_up_to: 1250")
    assert study.study_hash(load_study(study_file(tmp_path, wider, "w.yaml"))) == one
    other = AXES.replace("[1, 2, 3]", "[1, 2]")
    assert study.study_hash(load_study(study_file(tmp_path, other, "o.yaml"))) != one


def test_study_files_without_axes_keep_their_hash():
    """The results folders of the shipped studies stay theirs: same hash as
    before the axes existed (paper.yaml's since it took the paper's eight
    matrix fractions)."""
    root = os.path.join(os.path.dirname(__file__), "..", "..", "jobs", "studies")
    expected = {"ci.yaml": "c696fe8625421214", "bench3x3.yaml": "d56ab352323742ba",
                "paper.yaml": "d379db8bc12cc93a"}
    for name, value in expected.items():
        assert study.study_hash(load_study(os.path.join(root, name))) == value
    for name in ("convergence.yaml", "convergence-local.yaml", "scatter-local.yaml",
                 "strength-516-local.yaml", "strength-516-pm-local.yaml",
                 "strength-516-low-local.yaml", "strength-516-low-5000-local.yaml",
                 "strength-516-pm-5000-local.yaml", "strength-516-replicates-local.yaml",
                 "paper-64.yaml", "paper-64-packings.yaml", "paper-516-line.yaml",
                 "tiny-grid.yaml"):
        assert Study(os.path.join(root, name), "unused").runs()


@pytest.mark.parametrize("change, message", [
    (("[1250, 2500, 5000]", "[1250, 1250]"), "lattice_bonds_per_particle has repeated values"),
    (("[1250, 2500, 5000]", "[1250, -5]"), "lattice_bonds_per_particle value -5 is not a number"),
    (("[1250, 2500, 5000]", "[1250, true]"), "lattice_bonds_per_particle value True is not"),
    (("[1250, 2500, 5000]", "[1]"), r"value 1 gives 516 bonds, outside \[1000"),
    (("[1250, 2500, 5000]", "[]"), "lattice_bonds_per_particle must be a non-empty list"),
    (("lattice_bonds_per_particle: [1250, 2500, 5000]", "lattice_bonds: [20000, 25000.0]"),
     "lattice_bonds value 25000.0 is not an integer"),
    (("lattice_bonds_per_particle: [1250, 2500, 5000]", "lattice_bonds: [500]"),
     r"lattice_bonds value 500 is not an integer in \[1000"),
    (("elastic: true", "elastic: true\nlattice_bonds: [20000]"),
     "give lattice_bonds or lattice_bonds_per_particle, not both"),
    (("{sample_particles: 516}", "{sample_particles: 516, lattice_bonds: 9000}"),
     "sets the lattice size: remove sample.lattice_bonds"),
    (("{sample_particles: 516}", "{sample_particles: 516, lattice_Ln: 0.02}"),
     "remove sample.lattice_Ln"),
    (("{sample_particles: 516}", "{sample_particles: 516, pack_seed: 2}"),
     "pack_seeds sets the seed: remove sample.pack_seed"),
    (("{sample_particles: 516}", "{sample_particles: many}"),
     "needs an integer sample.sample_particles"),
    (("pack_seeds: [1, 2, 3]", "pack_seeds: [1, -2]"), r"pack_seeds value -2 is not an integer"),
    (("lattice_seeds: [4, 5, 6]", "lattice_seeds: [4, 4.5]"), "lattice_seeds value 4.5 is not"),
    (("lattice_seeds: [4, 5, 6]", "lattice_seeds: 4"), "lattice_seeds must be a non-empty list"),
    (("lattice_seeds: [4, 5, 6]", "lattice_seeds: [4, 4]"), "lattice_seeds has repeated"),
    (("replicates_up_to: 2500", "replicates_up_to: 2000"),
     r"replicates_up_to value 2000 is not one of lattice_bonds_per_particle \[1250, 2500, 5000\]"),
    (("fracture_up_to: 2500", "fracture_up_to: true"), "fracture_up_to value True is not one"),
    (("elastic: true", "elastic: yes please"), "elastic must be true or false"),
    (("elastic: true", "elastic: false"), "fracture_up_to leaves the larger lattices"),
    (("lattice_bonds_per_particle: [1250, 2500, 5000]\n", ""),
     "replicates_up_to needs a bond axis"),
    (("elastic: true", "elastic: true\nlattice_sizes: [1]"), r"unknown key\(s\) lattice_sizes"),
])
def test_bad_axis_values_are_refused(tmp_path, change, message):
    text = AXES.replace(*change)
    assert text != AXES
    with pytest.raises(StudyError, match=message):
        load_study(study_file(tmp_path, text))


# --- the gather step of a study with axes ------------------------------------

TRUE_E, SLOPE_E = 0.5, -6.0          # E_eff/E^[p] = 0.5 - 6 L_n (+ packing scatter)
TRUE_S, SLOPE_S = 0.6, -2.0          # sigma_eff/sigma^[p] = 0.6 - 2 L_n (+ scatter)
SMALL = """name: g
ranks: 1
sample: {sample_particles: 27}
lattice_bonds: [20000, 40000, 80000]
pack_seeds: [1, 2]
replicates_up_to: 40000
elastic: true
matrix_fractions: [0.13, 0.28]
sigma_pm_ratios: [1.0]
"""


def write_json(path, data):
    with open(path, "w") as f:
        json.dump(data, f)


def offset(lattice):
    """The packing's share: +d for pack seed 1, -d for 2 (a single run: 0)."""
    return {1: 0.01, 2: -0.01}[lattice["pack_seed"]] if lattice["level"] < 80000 else 0.0


def fake_study(tmp_path, text=SMALL, name="out"):
    """A study whose samples, calibrations, pulls and runs are written in
    tmp_path/name, their values on known lines in L_n."""
    s = Study(study_file(tmp_path, text, name + ".yaml"), str(tmp_path / name))
    s.plan()
    os.makedirs(os.path.join(s.out, "samples"))
    for sample in s.samples():
        bonds = sample["lattice"]["level"]
        write_json(os.path.join(s.out, "samples", sample["stem"] + "_summary.json"),
                   {"bonds": bonds, "nodes": bonds // 7, "rho_m": sample["rho_m"], "rho_v": 0.1})
    for lattice in s.lattices:
        d = s.calibration_dir(lattice)
        os.makedirs(d)
        write_json(os.path.join(d, "summary.json"), {"E_hom": 2.0, "sigma_hom": 0.02})
        write_manifest(d, ("summary.json",))
    for pull in s.elastic_pulls():
        lattice = s.lattice_of(pull)
        l_n = lattice["level"] ** (-1 / 3)
        e = TRUE_E + SLOPE_E * l_n + offset(lattice)
        d = s.pull_dir(pull)
        os.makedirs(d)
        write_json(os.path.join(d, "run.json"), s.run_record(pull))
        write_json(os.path.join(d, "summary.json"), {"E_eff": 2.0 * e, "nu": 0.2})
    for run in s.runs():
        lattice = s.lattice_of(run)
        l_n = lattice["level"] ** (-1 / 3)
        d = s.run_dir(run)
        os.makedirs(d)
        write_json(os.path.join(d, "run.json"), s.run_record(run))
        write_json(os.path.join(d, "summary.json"), {
            "E_eff_over_E_unit": TRUE_E + SLOPE_E * l_n,
            "sigma_eff_over_sigma_unit": TRUE_S + SLOPE_S * l_n + offset(lattice),
            "sigma_eff": 0.005, "strain_at_peak": 4e-3, "n_b": 0.1, "broken": 20,
            "broken_p": 2, "broken_m": 4, "broken_pp": 10, "broken_pm": 4,
            "end_reason": "stress below the stop fraction of the peak", "solves": 7,
            "seconds": 1.0})
        write_curve(os.path.join(d, "curve.csv"), [(1e-4, 0.1, 0.1, 0, 0, 10, 0),
                                                   (2e-4, 0.2, 0.1, 2, 4, 10, 4)])
        write_json(os.path.join(d, "stress.json"), {"tail": {"beta": 1.0}})
        write_manifest(d, ("summary.json", "curve.csv"))
    return s


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.long  # draws every figure of a study: 5-8 s
def test_gather_extrapolates_every_point(tmp_path, capsys):
    s = fake_study(tmp_path)
    assert s.status() == {"complete": 10 + 20, "failed": 0, "pending": 0}
    assert study.gather(s) == 0
    out = s.out
    results = read_rows(os.path.join(out, "results.csv"))
    assert len(results) == 10
    assert results[0]["lattice"] == "b20000_p1" and results[0]["pack_seed"] == "1"
    assert float(results[0]["L_n"]) == pytest.approx(20000 ** (-1 / 3))
    assert float(results[0]["share_broken_m"]) == pytest.approx(0.2)
    samples = read_rows(os.path.join(out, "samples.csv"))
    assert len(samples) == 10 and float(samples[0]["E_hom"]) == 2.0
    points = {(r["quantity"], r["rho_m"], r["sigma_pm_ratio"]): r
              for r in read_rows(os.path.join(out, "convergence.csv"))}
    e = points[("E_bare_over_E_unit", "0.28", "")]
    assert e["fit"] == "weighted" and e["levels"] == "3" and e["runs"] == "5"
    assert float(e["extrapolated"]) == pytest.approx(TRUE_E)
    assert float(e["slope"]) == pytest.approx(SLOPE_E)
    assert float(e["scatter"]) == pytest.approx(0.01 * math.sqrt(2))
    # exact means: the standard error is that of the weights alone
    assert 0 < float(e["extrapolated_se"]) < 0.1
    sigma = points[("sigma_eff_over_sigma_unit", "0.13", "1.0")]
    assert float(sigma["extrapolated"]) == pytest.approx(TRUE_S)
    # distance to the line at 2e4 bonds 2 * 0.0368 = 0.074 > scatter 0.014;
    # at 8e4 bonds 0.046 still above: the scatter never dominates here
    assert sigma["scatter_from_level"] == ""
    assert float(sigma["L_n_scatter_dominates"]) == pytest.approx(0.01 * math.sqrt(2) / 2)
    # without replicate scatter (the first-step modulus is the same for both
    # packings here): an unweighted fit of exact points
    first = points[("E_eff_over_E_unit", "0.13", "1.0")]
    assert first["fit"] == "unweighted"
    assert float(first["extrapolated"]) == pytest.approx(TRUE_E)
    levels = read_rows(os.path.join(out, "convergence_levels.csv"))
    assert {r["level"] for r in levels} == {"20000", "40000", "80000"}
    with open(os.path.join(out, "convergence.md")) as f:
        text = f.read()
    assert "## σ_eff/σ^[p]" in text and "20000 bonds (L_n 0.0368)" in text
    for name in ("convergence_elastic", "convergence_strength", "convergence_damage"):
        with open(os.path.join(out, "figures", name + ".png"), "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"
        assert os.path.getsize(os.path.join(out, "figures", name + ".pdf")) > 0
    with open(os.path.join(out, "fit.json")) as f:
        assert json.load(f)["figures_lattice"] == "b80000_p1"
    assert "convergence.csv" in capsys.readouterr().out


@pytest.mark.long  # draws every figure of a study: 5-8 s
def test_gather_reports_a_missing_elastic_pull(tmp_path, capsys):
    s = fake_study(tmp_path)
    pull = s.elastic_pulls()[0]
    os.remove(os.path.join(s.pull_dir(pull), "summary.json"))
    assert s.state(pull) == "pending"
    assert study.gather(s) == 1
    assert "%s not complete: left out" % pull["id"] in capsys.readouterr().out
    samples = read_rows(os.path.join(s.out, "samples.csv"))
    assert samples[0]["E_bare_over_E_unit"] == "nan"


def test_paper_marks_in_units_of_the_particle_modulus():
    from lem_tools import convergence_plots
    # the paper's phases: E^[m] = E^[p] / 3, so 1.6 E^[m] = 0.533 E^[p]
    phases = {"E_p": 3.0, "E_m": 1.0}
    marks = convergence_plots.paper_marks("E_bare_over_E_unit", [0.06, 0.28], phases)
    assert marks == [(0.28, pytest.approx(1.6 / 3))]
    assert convergence_plots.paper_marks("E_adhesive_over_E_unit", [0.28], {"E_p": 2.0,
                                         "E_m": 1.0}) == [(0.28, pytest.approx(1.25))]
    # no mark where the paper gives no value
    assert convergence_plots.paper_marks("E_bare_over_E_unit", [0.13], phases) == []
    assert convergence_plots.paper_marks("sigma_eff_over_sigma_unit", [0.28], phases) == []


# --- several gathered studies as one (study_combine) -------------------------

# the study SMALL split in two: its two coarse sizes, and its finest size
COARSE = SMALL.replace("name: g", "name: coarse").replace("[20000, 40000, 80000]",
                                                          "[20000, 40000]")
FINE = SMALL.replace("name: g", "name: fine").replace("[20000, 40000, 80000]", "[80000]") \
    .replace("[1, 2]", "[1]").replace("replicates_up_to: 40000\n", "")


def gathered(tmp_path, text, name, monkeypatch):
    """The output folder of a gathered fake study; its figures are not drawn
    (the tables are what combining reads)."""
    s = fake_study(tmp_path, text, name)
    with monkeypatch.context() as m:
        m.setattr(study_plots, "draw_all", lambda *args: [])
        m.setattr(convergence_plots, "draw_all", lambda *args: [])
        assert study.gather(s) == 0
    return s.out


@pytest.mark.long  # draws every figure of a study: 5-8 s
def test_combining_a_split_study_gives_the_extrapolations_of_the_whole(tmp_path, capsys,
                                                                      monkeypatch):
    whole = gathered(tmp_path, SMALL, "whole", monkeypatch)
    parts = [gathered(tmp_path, COARSE, "coarse", monkeypatch),
             gathered(tmp_path, FINE, "fine", monkeypatch)]
    out = str(tmp_path / "combined")
    assert study_combine.main([out] + parts) == 0
    assert "10 runs and 10 samples of 2 studies" in capsys.readouterr().out

    def points(folder):
        return {(r["quantity"], r["rho_m"], r["sigma_pm_ratio"]): r
                for r in read_rows(os.path.join(folder, "convergence.csv"))}
    expected, got = points(whole), points(out)
    assert set(got) == set(expected)
    for key, row in expected.items():
        for column in ("levels", "runs", "fit"):
            assert got[key][column] == row[column], (key, column)
        for column in ("extrapolated", "extrapolated_se", "slope", "scatter"):
            assert float(got[key][column]) == pytest.approx(float(row[column]), nan_ok=True), \
                (key, column)
    assert float(got[("sigma_eff_over_sigma_unit", "0.13", "1.0")]["extrapolated"]) \
        == pytest.approx(TRUE_S)
    rows = read_rows(os.path.join(out, "results.csv"))
    assert sorted({r["study"] for r in rows}) == sorted(parts)
    with open(os.path.join(out, "convergence.md")) as f:
        assert f.read().startswith("# Convergence in L_n: study coarse + fine")
    with open(os.path.join(out, "sources.json")) as f:
        assert [s["runs"] for s in json.load(f)["studies"]] == [8, 2]
    # a run left out when its study was gathered is named
    with open(os.path.join(parts[1], "fit.json")) as f:
        fit = json.load(f)
    with open(os.path.join(parts[1], "fit.json"), "w") as f:
        json.dump(dict(fit, missing_runs=["b80000_p1_rho_0.2800_spm_2.0000"]), f)
    assert study_combine.main([out] + parts) == 0
    assert "run b80000_p1_rho_0.2800_spm_2.0000 was not complete" in capsys.readouterr().out
    with open(os.path.join(out, "figures", "convergence_strength.png"), "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"


def test_combining_refuses_a_run_twice_other_physics_ungathered_and_study_folders(tmp_path, capsys,
                                                                         monkeypatch):
    coarse = gathered(tmp_path, COARSE, "coarse", monkeypatch)
    out = str(tmp_path / "combined")
    assert study_combine.main([out, coarse, coarse]) == 1
    assert "give each run once" in capsys.readouterr().err
    with open(os.path.join(coarse, "results.csv")) as f:
        gathered_table = f.read()
    assert study_combine.main([coarse, coarse]) == 1
    assert "is a study's folder: combine into a folder of its own" in capsys.readouterr().err
    with open(os.path.join(coarse, "results.csv")) as f:
        assert f.read() == gathered_table
    other = gathered(tmp_path, FINE + "phases: {E_p: 2.0, E_m: 1.0, E_pp: 1.0, E_pm: 1.0, "
                     "sigma_p: 0.01}\n", "other", monkeypatch)
    assert study_combine.main([out, coarse, other]) == 1
    assert "differ in their phases" in capsys.readouterr().err
    bare = fake_study(tmp_path, FINE, "bare").out
    assert study_combine.main([out, coarse, bare]) == 1
    err = capsys.readouterr().err
    assert "results.csv does not exist: run tools/study.py gather" in err
    assert not os.path.exists(os.path.join(out, "convergence.csv"))


def test_the_convergence_panel_draws_the_paper_mark_at_its_value():
    from lem_tools import convergence_plots
    from lem_tools.plotting import plt
    level = {"L_n": 0.02, "mean": 0.4, "std": 0.01, "n": 3}
    results = {("E_bare_over_E_unit", 0.28, None): {
        "levels": [level, dict(level, L_n=0.01, mean=0.45)],
        "fit": {"intercept": 0.5, "slope": -5.0}, "extrapolated_se": 0.01}}
    fig, ax = plt.subplots()
    convergence_plots.panel(ax, results, "E_bare_over_E_unit", "E", {}, {"phases": {
        "E_p": 3.0, "E_m": 1.0}})
    stars = [line for line in ax.get_lines() if line.get_marker() == "*"]
    assert len(stars) == 1 and stars[0].get_label().startswith("paper")
    assert stars[0].get_ydata()[0] == pytest.approx(1.6 / 3)
    plt.close(fig)


def test_the_convergence_figure_title_names_particles_and_samples(tmp_path, monkeypatch):
    from lem_tools import convergence_plots
    titles = []
    monkeypatch.setattr(convergence_plots, "save_figure",
                        lambda fig, path, **kw: titles.append(fig._suptitle.get_text()))
    level = {"L_n": 0.02, "mean": 0.4, "std": 0.01, "n": 1}
    results = {("beta", 0.28, 1.0): {"levels": [level, dict(level, L_n=0.01, n=3)],
                                     "fit": None, "extrapolated_se": float("nan")},
               ("n_b", 0.28, 1.0): {"levels": [dict(level, n=2)], "fit": None,
                                    "extrapolated_se": float("nan")}}
    convergence_plots.figure(results, [("beta", "beta")], {}, {}, "strength",
                             str(tmp_path / "f"), 516)
    assert "516 particles, 1–3 samples per point" in titles[0]
    assert convergence_plots.samples_text(results, ["n_b"]) == "2 samples per point"
    single = {("beta", 0.28, 1.0): {"levels": [level]}}
    assert convergence_plots.samples_text(single, ["beta"]) == "one sample per point"


def test_elastic_pulls_get_the_lattice_options_of_the_runs(tmp_path, monkeypatch):
    """-lattice_face_bonds changes the lattice a sample becomes: a study that
    sets it for its fracture runs must pull the same lattice, and leave the
    loading options to lem_fracture."""
    text = SMALL + "fracture: {lattice_face_bonds: halved, fracture_stop_fraction: 0.6}\n"
    s = Study(study_file(tmp_path, text, "h.yaml"), str(tmp_path / "out"))
    commands = []
    monkeypatch.setattr(study, "execute", lambda cmd, log: commands.append(cmd) or 0)
    s.pull_one(s.elastic_pulls()[0])
    pull = commands[0]
    assert os.path.basename(pull[pull.index("-sample_file") - 1]) == "lem_tension"
    assert pull[pull.index("-lattice_face_bonds") + 1] == "halved"
    assert "-fracture_stop_fraction" not in pull
