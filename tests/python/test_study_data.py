"""Results kept as data (study_data): the rows a study keeps, a study
resumed from them running only what they lack, and the paper's figures
redrawn from the committed data folder of a real small study."""
import json
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import TOOLS, write_curve, write_manifest, write_study_file
from lem_tools import analysis, convergence_table, paper, study, study_data
from lem_tools.study import Study

ROOT = os.path.dirname(TOOLS)
TINY = os.path.join(ROOT, "docs", "data", "tiny-grid")   # jobs/studies/tiny-grid.yaml
STUDY = """name: d
ranks: 1
sample: {sample_particles: 8, lattice_bonds: 6000}
matrix_fractions: [0.13, 0.24]
sigma_pm_ratios: [0.4, 1.2]
"""
CALIBRATION = {"sigma_hom": 0.0193, "E_hom": 7.6}


# --- the row's content ----------------------------------------------------------

def test_thinning_keeps_the_peak_the_falls_and_the_end():
    strain = np.linspace(1e-5, 1e-2, 1000)
    before = np.where(strain < 5e-3, strain * 100, 0.1)     # rises to 0.5, falls to 0.1
    before[700] = 0.3                                        # a single spike after the fall
    curve = {"strain": strain, "stress_before_norm": before, "stress_norm": before * 0.99,
             "n_b": np.where(strain < 5e-3, 0.0, 0.2)}
    keep = study_data.thin_curve(curve)
    assert len(keep) < 400
    assert keep[0] == 0 and keep[-1] == 999
    peak = int(np.argmax(before))
    assert peak in keep and peak + 1 in keep                 # both sides of the fall
    assert 700 in keep and 701 in keep                       # the spike and its end
    # the rise is sampled finely enough to redraw it: no gap above 1/250 of the strain
    # range in the rise, or of 1/100 of the stress
    gaps = np.diff(strain[keep])
    assert gaps.max() <= (strain[-1] - strain[0]) / study_data.THIN_STRAIN + 1e-5


def write_sample(path, values, start_time):
    import h5py

    with h5py.File(path, "w") as f:
        f["nodes/coordinates"] = np.asarray(values, dtype=float)
        f.attrs["start_time"] = start_time


def test_sample_checksum_is_of_the_data_not_of_the_file(tmp_path):
    """lem_sample writes the same datasets from the same options but other
    timings and times into the attributes: the checksum follows the data."""
    paths = [str(tmp_path / name) for name in ("a.h5", "b.h5", "c.h5")]
    write_sample(paths[0], [[0, 0, 0], [1, 1, 1]], "2026-11-28T07:00:00Z")
    write_sample(paths[1], [[0, 0, 0], [1, 1, 1]], "2026-11-28T08:00:00Z")
    write_sample(paths[2], [[0, 0, 0], [1, 1, 1.5]], "2026-11-28T07:00:00Z")
    sums = [study_data.sample_checksum(p) for p in paths]
    assert sums[0] == sums[1] != sums[2]
    assert sums[0].startswith("crc32:")
    with open(paths[0], "rb") as a, open(paths[1], "rb") as b:
        assert a.read() != b.read()


# --- a study resumed from its data ------------------------------------------------

def write_lattice(path, rho):
    """A sample file of two bonds in a box of height 2: a solid bond of
    length 0.1 and a void one of length 0.3, so a / L = 0.1 (a counts the
    void bonds); a node without bonds at rho."""
    import h5py

    with h5py.File(path, "w") as f:
        f["nodes/coordinates"] = np.array([[0, 0, 0], [0, 0, 0.1], [0.3, 0, 0], [rho, 1, 1]])
        f["bonds/connectivity"] = np.array([[0, 1], [0, 2]])
        f["bonds/phase"] = np.array([0, 2])          # p, v (phases.PHASES)
        f.attrs["box_lo"], f.attrs["box_hi"] = [0.0, 0.0, 0.0], [2.0, 2.0, 2.0]


class FakePrograms:
    """study.execute standing in for lem_sample and lem_fracture: writes what
    they write (a sample, a calibration, a complete run) and records what ran."""

    def __init__(self):
        self.ran, self.increments = [], []

    def __call__(self, cmd, log):
        program = os.path.basename(cmd[cmd.index("-n") + 2] if "-n" in cmd else cmd[0])
        opts = {cmd[i]: cmd[i + 1] for i in range(len(cmd) - 1) if cmd[i].startswith("-")}
        if program == "lem_sample":
            out, stem = opts["-output_dir"], opts["-output_stem"]
            rho = float(opts["-matrix_fraction"])
            write_lattice(os.path.join(out, stem + ".h5"), rho)
            with open(os.path.join(out, stem + "_summary.json"), "w") as f:
                json.dump({"bonds": 6000, "sample_particles": 8, "packing_seed": 1,
                           "lattice_seed": 1, "interface_ratio_Spm_Sp": rho / 0.28}, f)
            self.ran.append(("sample", stem))
            return 0
        out = opts["-output_dir"]
        if opts.get("-fracture_max_steps") == "1":
            with open(os.path.join(out, "summary.json"), "w") as f:
                json.dump(CALIBRATION, f)
            write_manifest(out, ("summary.json",))
            self.ran.append(("calibration", None))
            return 0
        ratio = float(opts["-phase_sigma_pm"]) / 0.01
        write_curve(os.path.join(out, "curve.csv"),
                    [(1e-4 * i, 0.1 * i, 0.1 * i, 0, 0, 10, 0) for i in range(1, 6)]
                    + [(6e-4, 0.5, 0.1, 3, 4, 10, 5)])
        with open(os.path.join(out, "summary.json"), "w") as f:
            json.dump({"E_eff_over_E_unit": 0.3, "sigma_eff_over_sigma_unit": 0.5,
                       "sigma_eff": 0.5 * float(opts["-fracture_sigma_unit"]),
                       "strain_at_peak": 5e-4, "n_b": 3 / 22, "broken": 22, "broken_p": 3,
                       "broken_m": 4, "broken_pp": 10, "broken_pm": 5,
                       "end_reason": "stress below the stop fraction of the peak",
                       "solves": 9, "seconds": 1.0}, f)
        write_manifest(out, ("curve.csv", "summary.json"))
        self.ran.append(("run", os.path.basename(out), ratio, opts["-fracture_sigma_unit"]))
        self.increments.append(opts.get("-fracture_increment"))
        return 0


@pytest.fixture
def programs(monkeypatch):
    fake = FakePrograms()
    monkeypatch.setattr(study, "execute", fake)
    # the stress figure of each run is its own process: not wanted here
    monkeypatch.setattr(study.subprocess, "run", lambda *a, **k: None)
    monkeypatch.setenv("LEM_LAUNCHER", "mpirun")
    return fake


def test_a_resumed_study_runs_only_the_rows_its_data_lacks(tmp_path, programs, monkeypatch,
                                                           capsys):
    monkeypatch.setattr(study, "gather", lambda s: 0)   # the figures: tested below
    path = write_study_file(tmp_path, STUDY, "d.yaml")
    data = str(tmp_path / "data")
    first = str(tmp_path / "here")
    assert study.main(["all", path, first, "--data", data]) == 0
    runs = [run["id"] for run in Study(path, first).runs()]
    assert [r[1] for r in programs.ran if r[0] == "run"] == runs
    assert sorted(os.listdir(os.path.join(data, "runs"))) == [r + ".json" for r in runs]
    kept = json.load(open(os.path.join(data, "runs", runs[1] + ".json")))
    assert kept["row"]["sigma_pm_ratio"] == 1.2 and kept["row"]["n_b"] == pytest.approx(3 / 22, rel=1e-5)
    assert kept["options"][-8:] == ["-phase_sigma_pm", "0.012", "-fracture_calibrate", "false",
                                    "-fracture_sigma_unit", "0.0193", "-fracture_modulus_unit",
                                    "7.6"]
    assert kept["sample"]["checksum"] == study_data.sample_checksum(
        os.path.join(first, "samples", "rho_0.1300.h5"))
    assert kept["curve"]["columns"][0] == "strain" and len(kept["curve"]["rows"]) == 6
    assert json.load(open(os.path.join(data, "calibration", "default.json"))) == CALIBRATION

    # here again, one row's run folder and data deleted: that row alone runs
    import shutil

    shutil.rmtree(os.path.join(first, "runs", runs[2]))
    os.remove(os.path.join(data, "runs", runs[2] + ".json"))
    programs.ran.clear()
    assert study.main(["all", path, first, "--data", data]) == 0
    assert programs.ran == [("run", runs[2], 0.4, repr(CALIBRATION["sigma_hom"]))]

    # on another machine (a new output folder, the data folder as committed,
    # one row less): its sample alone is built, the kept calibration is used
    os.remove(os.path.join(data, "runs", runs[3] + ".json"))
    programs.ran.clear()
    elsewhere = str(tmp_path / "elsewhere")
    assert study.main(["all", path, elsewhere, "--data", data]) == 0
    assert programs.ran == [("sample", "rho_0.2400"),
                            ("run", runs[3], 1.2, repr(CALIBRATION["sigma_hom"]))]
    assert len(os.listdir(os.path.join(data, "runs"))) == 4
    # status there counts the kept rows as complete, and names a kept row
    # whose sample differs from the one built here
    assert Study(path, elsewhere, data=data).status()["complete"] == 4
    capsys.readouterr()
    write_sample(os.path.join(elsewhere, "samples", "rho_0.2400.h5"), [[9, 9, 9]], "now")
    Study(path, elsewhere, data=data).status()
    told = capsys.readouterr().out
    assert re.search(r"%s +kept with sample crc32:\w+, the sample here is crc32:" % runs[3], told)
    assert "not started" not in told                # the samples of kept rows are not needed
    # and gather's samples.csv describes them from their kept rows (a resumed
    # study's plots against L_n once failed on their NaN)
    described = {s["sample"]: s for s in convergence_table.sample_rows(Study(path, elsewhere, data=data))}
    assert not os.path.exists(os.path.join(elsewhere, "samples", "rho_0.1300_summary.json"))
    assert described["rho_0.1300"]["bonds"] == 6000
    assert described["rho_0.1300"]["L_n"] == pytest.approx(6000 ** (-1 / 3))


def test_strain_increment_sets_the_increment_of_each_lattice(tmp_path, programs, monkeypatch):
    """strain_increment: each run's -fracture_increment (in bond lengths a)
    is the strain step times L / a of its sample, a the mean length of its
    bonds, void ones included; the default increment is left alone without it."""
    monkeypatch.setattr(study, "gather", lambda s: 0)
    path = write_study_file(tmp_path, STUDY + "strain_increment: 2.0e-5\n", "d.yaml")
    assert study.main(["all", path, str(tmp_path / "out")]) == 0
    assert [float(i) for i in programs.increments] == pytest.approx([2e-4] * 4)  # 2e-5 / 0.1
    programs.increments.clear()
    path = write_study_file(tmp_path, STUDY, "plain.yaml")
    assert study.main(["all", path, str(tmp_path / "plain")]) == 0
    assert programs.increments == [None] * 4
    for text, message in (("strain_increment: 0\n", "strain_increment must be a number > 0"),
                          ("strain_increment: 1.0e-5\nfracture: {fracture_increment: 1.0e-4}\n",
                           "not both")):
        with pytest.raises(study.StudyError, match=message):
            study.load_study(write_study_file(tmp_path, STUDY + text, "bad.yaml"))


def test_a_data_folder_keeps_one_study(tmp_path, programs, monkeypatch):
    monkeypatch.setattr(study, "gather", lambda s: 0)
    data = str(tmp_path / "data")
    path = write_study_file(tmp_path, STUDY, "d.yaml")
    assert study.main(["plan", path, str(tmp_path / "a"), "--data", data]) == 0
    other = write_study_file(tmp_path, STUDY.replace("0.24", "0.25"), "o.yaml")
    assert study.main(["plan", other, str(tmp_path / "b"), "--data", data]) == 1
    assert not os.path.exists(str(tmp_path / "b" / "runs"))


# --- the paper's figures from the committed data --------------------------------------

# Every data folder committed under docs/data/: its study file, and whether
# the study has run to the end (a study carried on elsewhere may keep part
# of its rows: each must still be one of its runs, of its hash).
KEPT = [("tiny-grid", True), ("paper-64", True), ("paper-64-packings", False),
        ("increment-64-x0.5", False), ("increment-64-x1", False), ("increment-64-x2", False),
        ("increment-64-x4", False), ("increment-516-x0.5", True), ("increment-516-x1", True),
        ("increment-516-x2", True), ("increment-516-x4", True), ("paper-516-line", True),
        ("paper-516-grid", False), ("coating-64", True), ("coating-516", False), ("fig3-64", True), ("fig3-pp-64", True)]


def test_every_data_folder_is_listed():
    data = os.path.join(ROOT, "docs", "data")
    folders = [n for n in os.listdir(data) if os.path.isdir(os.path.join(data, n))]
    assert set(folders) <= {name for name, _ in KEPT}


@pytest.mark.parametrize("name, complete", KEPT)
def test_the_committed_data_is_small_and_complete(name, complete):
    """docs/data/<study>: the runs of jobs/studies/<study>.yaml (every one
    when complete), each row a few kB, with the pdf and the thinned curve
    the figures need."""
    folder = os.path.join(ROOT, "docs", "data", name)
    if not complete and not os.path.isdir(folder):
        pytest.skip("no data kept yet for %s" % name)
    spec = Study(os.path.join(ROOT, "jobs", "studies", name + ".yaml"), "unused")
    rows = study_data.DataFolder(folder).rows()
    ids, wanted = sorted(d["run"]["id"] for d in rows), sorted(r["id"] for r in spec.runs())
    assert ids == wanted if complete else set(ids) <= set(wanted)
    assert all(d["study_hash"] == spec.hash for d in rows)
    sizes = [os.path.getsize(os.path.join(folder, "runs", d["run"]["id"] + ".json"))
             for d in rows]
    assert max(sizes, default=0) < 30_000
    for d in rows:
        assert d["stress_pdf"]["beta"] > 0
        assert len(d["curve"]["rows"]) < d["curve"]["steps"] or d["curve"]["steps"] < 300


def test_the_figure_command_redraws_every_figure_from_the_data(tmp_path):
    out = str(tmp_path / "figures")
    done = subprocess.run([sys.executable, os.path.join(TOOLS, "paper_figures.py"), TINY,
                           "--out", out], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    names = sorted(os.listdir(out))
    assert names == ["fig03.png", "fig05.png", "fig08.png", "fig09.png", "fig11.png",
                     "fig12.png", "fig13.png", "fig14.png", "fig15.png", "fig16.png",
                     "fit.json", "results.csv"]
    for name in names[:-2]:
        with open(os.path.join(out, name), "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    fit = json.load(open(os.path.join(out, "fit.json")))
    assert fit["runs"] == 18 and fit["points"] == 9
    assert fit["figures"]["runs_per_point"] == [2, 2]


# --- a damaged or foreign row is named, nothing drawn ---------------------------------

DRAWN_RUN = "p1_rho_0.0600_spm_0.8000"   # a run whose curve fig. 3 draws (sigma^pm near sigma^p)
DELETE = object()


@pytest.fixture
def tiny_copy(tmp_path):
    folder = str(tmp_path / "tiny-grid")
    shutil.copytree(TINY, folder)
    return folder


def edit_row(folder, keys, value, run=DRAWN_RUN):
    """runs/<run>.json of `folder` with the field at `keys` (a path of
    mapping keys and list indices) set to `value`, or deleted (DELETE); its path."""
    path = os.path.join(folder, "runs", run + ".json")
    with open(path) as f:
        data = json.load(f)
    parent = data
    for key in keys[:-1]:
        parent = parent[key]
    if value is DELETE:
        del parent[keys[-1]]
    else:
        parent[keys[-1]] = value
    with open(path, "w") as f:
        json.dump(data, f)
    return path


def paper_figures_error(folder, out, capsys):
    """(exit status, stderr) of paper_figures.py FOLDER --out OUT, run here."""
    from lem_tools import paper_figures

    status = paper_figures.main([folder, "--out", out])
    return status, capsys.readouterr().err


@pytest.mark.parametrize("keys, value, message", [
    (("row", "sigma_eff_over_sigma_unit"), float("nan"),
     r"row\.sigma_eff_over_sigma_unit is nan: a kept value must be a finite number or null"),
    (("curve", "rows", 1, 0), float("inf"), r"curve\.rows\[1\]\[0\] is inf"),
    (("stress_pdf", "beta"), float("-inf"), r"stress_pdf\.beta is -inf"),
    (("sample", "bonds"), float("nan"), r"sample\.bonds is nan"),
    (("row",), DELETE, "no row section"),
    (("curve",), DELETE, "no curve section"),
    (("run",), DELETE, "no run section"),
    (("curve", "rows"), [], r"curve\.rows is empty: no step of the curve is kept"),
    (("curve", "rows", 2), [1e-4, 0.1], r"curve\.rows\[2\] is not 5 numbers"),
    (("curve", "columns"), ["strain", "stress_norm"], r"curve\.columns lacks stress_before_norm"),
    (("row", "beta"), DELETE, "row has no beta"),
    (("row", "n_b"), "many", r"row\.n_b is 'many', not a number or null"),
    (("run", "rho_m"), DELETE, r"run\.rho_m is None, not a number"),
    (("stress_pdf", "edges"), DELETE, "stress_pdf has no edges and inside"),
])
def test_a_damaged_row_is_named_and_nothing_drawn(tiny_copy, tmp_path, capsys, keys, value,
                                                  message):
    """A row with NaN or infinity in a value, a section missing or an empty
    curve: one line naming the file and the field, exit 1, no figure."""
    path = edit_row(tiny_copy, keys, value)
    out = str(tmp_path / "figures")
    status, err = paper_figures_error(tiny_copy, out, capsys)
    assert status == 1
    assert re.fullmatch(r"[^\n]*: error: %s: %s[^\n]*\n" % (re.escape(path), message), err), err
    assert not os.path.exists(out)


def test_a_row_of_another_study_is_refused(tiny_copy, tmp_path):
    """A row of another study under the name of one of this study's runs:
    refused naming the file and both studies (the command as run)."""
    other = os.path.join(ROOT, "docs", "data", "paper-64")
    row = sorted(os.listdir(os.path.join(other, "runs")))[0]
    path = os.path.join(tiny_copy, "runs", DRAWN_RUN + ".json")
    shutil.copy(os.path.join(other, "runs", row), path)
    out = str(tmp_path / "figures")
    done = subprocess.run([sys.executable, os.path.join(TOOLS, "paper_figures.py"), tiny_copy,
                           "--out", out], capture_output=True, text=True, timeout=300)
    theirs = json.load(open(os.path.join(other, "study.json")))["hash"]
    ours = json.load(open(os.path.join(TINY, "study.json")))["hash"]
    assert done.returncode == 1
    assert done.stderr == ("paper_figures.py: error: %s is a row of study paper-64 (hash %s), "
                           "not of tiny-grid (hash %s) whose data folder holds it: move it to "
                           "its own study's data folder\n" % (path, theirs, ours))
    assert not os.path.exists(out)


def test_studies_of_other_phases_are_not_drawn_beside(tmp_path, capsys):
    """--beside draws another resolution of the same physics only: studies
    with another sigma^pp are refused naming the phases, and nothing is
    drawn."""
    from lem_tools import paper_figures

    data = os.path.join(ROOT, "docs", "data")
    out = str(tmp_path / "figures")
    status = paper_figures.main([os.path.join(data, "fig3-64"), "--out", out,
                                 "--beside", os.path.join(data, "fig3-pp-64")])
    err = capsys.readouterr().err
    assert status == 1
    assert "--beside %s differs in its phases" % os.path.join(data, "fig3-pp-64") in err, err
    assert "sigma_pp" in err
    assert not os.path.exists(out)


def test_beside_points_are_drawn_at_the_shared_matrix_fractions():
    """The 64-particle grid drawn beside the 516-particle line: one open
    series per matrix fraction the line has, at the 64-particle values."""
    from lem_tools import paper_figures
    from lem_tools.plotting import plt

    data = os.path.join(ROOT, "docs", "data")
    drawn, _, points, _ = paper_figures.figures(
        [os.path.join(data, "paper-516-line")], [os.path.join(data, "paper-64")])
    ax = drawn["fig09"].axes[0]
    open_lines = [line for line in ax.get_lines()
                  if isinstance(line.get_markerfacecolor(), str)
                  and line.get_markerfacecolor() == "white"]
    rhos = {p["rho_m"] for p in points}
    assert len(open_lines) == len(rhos) == 8
    grid = [json.load(open(os.path.join(data, "paper-64", "runs", f)))["row"]
            for f in sorted(os.listdir(os.path.join(data, "paper-64", "runs")))]
    at_028 = sorted((r["sigma_pm_ratio"], r["sigma_eff_over_sigma_unit"]) for r in grid
                    if r["rho_m"] == 0.28)
    assert any(np.allclose(line.get_xydata(), at_028) for line in open_lines)
    for fig in drawn.values():
        plt.close(fig)


def test_a_row_under_another_runs_name_is_refused(tiny_copy, tmp_path, capsys):
    path = os.path.join(tiny_copy, "runs", DRAWN_RUN + ".json")
    shutil.copy(os.path.join(tiny_copy, "runs", "p1_rho_0.0600_spm_0.2000.json"), path)
    status, err = paper_figures_error(tiny_copy, str(tmp_path / "figures"), capsys)
    assert status == 1
    assert err.endswith(": error: %s: holds the run p1_rho_0.0600_spm_0.2000, not %s (its file "
                        "name)\n" % (path, DRAWN_RUN)), err


def test_an_output_path_that_is_a_file_is_named_not_errno(tmp_path):
    out = tmp_path / "figures"
    out.write_text("a file of the user's\n")
    done = subprocess.run([sys.executable, os.path.join(TOOLS, "paper_figures.py"), TINY,
                           "--out", str(out)], capture_output=True, text=True, timeout=300)
    assert done.returncode == 1
    assert done.stderr == ("paper_figures.py: error: the figures' folder (--out) %s is a file, "
                           "not a folder: choose another path\n" % out)
    assert out.read_text() == "a file of the user's\n"


@pytest.mark.parametrize("value, shown", [(float("nan"), "nan"), (float("inf"), "inf"),
                                          (0.0, "0.0"), (-0.02, "-0.02"), (True, "True"),
                                          ("0.02", "'0.02'"), (None, "None")])
def test_a_kept_calibration_must_be_positive_numbers(tmp_path, value, shown):
    folder = study_data.DataFolder(str(tmp_path))
    os.makedirs(str(tmp_path / "calibration"))
    for key in ("sigma_hom", "E_hom"):
        kept = dict(CALIBRATION, **{key: value})
        with open(folder.calibration_path("p1"), "w") as f:
            json.dump(kept, f)
        with pytest.raises(study_data.DataError, match=r"^%s: %s must be a number > 0, not %s$"
                           % (re.escape(folder.calibration_path("p1")), key, re.escape(shown))):
            folder.calibration("p1")


@pytest.fixture(scope="module")
def tiny_figures():
    from lem_tools import paper_figures
    from lem_tools.plotting import plt

    yield paper_figures.figures([TINY])
    plt.close("all")


def line(ax, label):
    """The one line of `ax` whose label contains `label`."""
    (found,) = [l for l in ax.get_lines() if label in l.get_label()]
    return np.asarray(found.get_xdata(), dtype=float), np.asarray(found.get_ydata(), dtype=float)


def test_the_paper_statements_are_drawn_on_its_figures(tiny_figures):
    figs, rows, points, _ = tiny_figures
    (ax,) = figs["fig03"].axes
    x, _ = line(ax, "paper: peak")
    assert x[0] == pytest.approx(4.0)                                  # 4e-3, in 1e-3
    # each curve: the stresses before each step's ruptures, then the run's
    # end after its last step's (a failure in the last step shows as a fall)
    drawn = sorted((tuple(l.get_xdata()[-2:]), tuple(l.get_ydata()[-2:]))
                   for l in ax.get_lines() if len(l.get_xdata()) > 2)
    ends = []
    for d in study_data.DataFolder(TINY).rows():
        if d["run"]["sigma_pm_ratio"] == 0.8:                        # the ratio nearest 1
            c = study_data.curve_of(d)
            ends.append(((c["strain"][-1] * 1e3,) * 2,
                         (c["stress_before_norm"][-1], c["stress_norm"][-1])))
    assert len(drawn) == len(ends) == 6
    assert np.array(drawn) == pytest.approx(np.array(sorted(ends)))
    (ax,) = figs["fig05"].axes
    stars = {l.get_label().split(":")[0]: l.get_ydata()[0] for l in ax.get_lines()
             if l.get_marker() == "*"}
    assert sorted(stars.values()) == pytest.approx([1.6 / 3, 2.5 / 3])  # in E^[p] = 3 E^[m]
    a, b = figs["fig08"].axes[:2]
    for rho, beta in ((0.06, 0.7), (0.28, 2.1)):
        s, pdf = line(a, r"paper, $\rho^m$ = %.2f" % rho)
        assert np.diff(np.log(pdf)) / np.diff(s) == pytest.approx(-beta)
    (ax,) = figs["fig11"].axes
    x, y = line(ax, "eq. 6")
    assert y == pytest.approx(x / 0.28)
    a = figs["fig12"].axes[0]
    for label, slope in (("A = 0.3", 0.3), ("slope 0.2", 0.2)):
        x, y = line(a, label)
        assert y[1:] / x[1:] == pytest.approx(slope)
    # n_b both ways: (a) as the paper counts it, (b) without the bare contacts
    a, b = figs["fig14"].axes
    for ax, column in ((a, "n_b"), (b, "n_b_without_bare_contacts")):
        assert line(ax, "onset")[0][0] == 0.4 and line(ax, "inflection")[0][0] == 1.0
        last = [float(c.lines[0].get_ydata()[-1]) for c in ax.containers]   # at sigma^pm 1.4
        assert last == pytest.approx([float(p[column]) for p in points
                                      if p["sigma_pm_ratio"] == 1.4])
    e_eff = {p["rho_m"]: p["E_eff_over_E_unit"] for p in analysis.sample_means(rows)}
    for c in figs["fig15"].axes[:2]:
        assert line(c, "eq. 13")[1][0] == 0.4
        # eq. 14's frontier: sigma^pm/sigma^p = 0.7^2 E^pm / (E^p E_eff/E^[p]) per rho^m,
        # with the samples' E_eff and with E_eff at L_n -> 0 (interpolated in rho^m)
        rhos, frontier = line(c, "the samples'")
        assert list(rhos) == sorted(e_eff)
        assert frontier == pytest.approx([0.49 / 3 / e_eff[rho] for rho in rhos])
        rhos, frontier = line(c, "L_n")
        converged = np.interp(rhos, sorted(paper.CONVERGED_MODULI),
                              [paper.CONVERGED_MODULI[r] for r in sorted(paper.CONVERGED_MODULI)])
        assert frontier == pytest.approx(0.49 / 3 / converged)
    a, b, c = figs["fig16"].axes[:3]
    assert line(a, "eq. 14")[0][0] == 0.7 and line(c, "eq. 13")[0][0] == 0.4
    # (b): K_c^r of eq. 14 with E_eff at L_n -> 0 of the rho^m series
    for container, rho in zip(b.containers, sorted(e_eff)):
        e = np.interp(rho, sorted(paper.CONVERGED_MODULI),
                      [paper.CONVERGED_MODULI[r] for r in sorted(paper.CONVERGED_MODULI)])
        ratios = sorted({p["sigma_pm_ratio"] for p in points})
        assert np.asarray(container.lines[0].get_xdata(), dtype=float) == \
            pytest.approx(np.sqrt(3 * e * np.array(ratios)))


def test_the_error_bars_are_the_scatter_between_packings(tiny_figures):
    """Two packings per grid point: fig. 9 draws their mean and standard
    deviation of sigma_eff, as the kept rows give them."""
    figs, rows, points, record = tiny_figures
    assert record["figures"]["runs_per_point"] == [2, 2]
    by_point = {}
    for r in rows:
        by_point.setdefault((r["rho_m"], r["sigma_pm_ratio"]), []).append(
            r["sigma_eff_over_sigma_unit"])
    (ax,) = figs["fig09"].axes
    rhos = sorted({p["rho_m"] for p in points})
    for rho, container in zip(rhos, ax.containers):
        line_, _, (bars,) = container.lines
        for x, y, segment in zip(line_.get_xdata(), line_.get_ydata(), bars.get_segments()):
            values = by_point[(rho, x)]
            assert y == pytest.approx(np.mean(values))
            assert (segment[1][1] - segment[0][1]) / 2 == pytest.approx(np.std(values, ddof=1))
