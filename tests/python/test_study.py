"""Study files, run states and the gather step on a study made here."""
import csv
import json
import math
import os
import signal
import sys
import textwrap
import threading
import time

import pytest

from conftest import write_curve, write_manifest, write_study_file
from lem_tools import results, study
from lem_tools.study import Study, StudyError, load_study

BASE = """name: t
ranks: 1
sample: {sample_particles: 8, lattice_bonds: 6000}
matrix_fractions: [0.13, 0.24]
sigma_pm_ratios: [0.4, 1.2]
"""


def study_file(tmp_path, text=BASE, name="s.yaml"):
    return write_study_file(tmp_path, text, name)


def test_valid_study_gets_the_defaults(tmp_path):
    spec = load_study(study_file(tmp_path, BASE.replace("ranks: 1\n", "")))
    assert spec["ranks"] == 2
    assert spec["phases"] == study.PHASE_KEYS
    assert spec["matrix_fractions"] == [0.13, 0.24]
    assert spec["fracture"] == {}


@pytest.mark.parametrize("change, message", [
    (("ranks: 1", "ranks: true"), "ranks must be a positive integer, not True"),
    (("ranks: 1", "ranks: 1.5"), "ranks must be a positive integer, not 1.5"),
    (("ranks: 1", "ranks: 0"), "ranks must be a positive integer, not 0$"),
    (("ranks: 1", "ranks: -1"), "ranks must be a positive integer, not -1$"),
    (("ranks: 1", "ranks: 1.0e+20"), r"ranks must be a positive integer, not 1e\+20$"),
    (("ranks: 1", "ranks: 1e20"), "ranks must be a positive integer, not '1e20'$"),
    # a count no machine has is a typo, not a run to plan
    (("ranks: 1", "ranks: 100000000000000000000"),
     "ranks must be a positive integer up to 1000000, not 100000000000000000000$"),
    (("ranks: 1", "ranks: 1000001"),
     "ranks must be a positive integer up to 1000000, not 1000001$"),
    (("[0.4, 1.2]", "[0.4, true]"), "sigma_pm_ratios value True is not a number"),
    (("[0.13, 0.24]", "[0.13, .nan]"), "matrix_fractions value nan is not a number"),
    (("[0.13, 0.24]", "[0.13, 0.9]"), r"matrix_fractions value 0.9 outside \(0, 0.5\]"),
    (("[0.4, 1.2]", "[]"), "the grid is empty"),
    (("[0.4, 1.2]", "[0.4, 0.4]"), "sigma_pm_ratios has repeated values"),
    # Runs are named by the values to 4 decimals: two that agree there would
    # share one run (and a sample, for matrix fractions).
    (("[0.4, 1.2]", "[0.4, 0.40001]"), r"sigma_pm_ratios values 0.4 and 0.40001 agree to 4 "
                                       r"decimals \(0.4000\)"),
    (("[0.13, 0.24]", "[0.13, 0.130004]"), "matrix_fractions values 0.13 and 0.130004 agree"),
    # A key given twice is not the last one silently.
    (("ranks: 1", "ranks: 1\nranks: 3"), r"key 'ranks' is given twice \(lines 2 and 3\)"),
    (("sample: {sample_particles: 8,", "sample: {sample_particles: 8, sample_particles: 9,"),
     "key 'sample_particles' is given twice"),
    (("name: t", "name: t\nphases: {sigma_p: true}"), "phases.sigma_p must be a number > 0"),
    (("name: t", "name: t\nphases: {E_p: .inf}"), "phases.E_p must be a number > 0"),
    (("name: t", "name: t\nphases: {E_p: -3}"), "phases.E_p must be a number > 0"),
    (("name: t", "name: t\nphases: {E_x: 3}"), "phases accepts only"),
    (("name: t", "name: t\nphases: {sigma_pp: -0.003}"), r"phases.sigma_pp must be a number > 0 \(or 0\)"),
    (("name: t", "name: t\nfracture_options: {}"), r"unknown key\(s\) fracture_options"),
    (("name: t", "name: t\nfracture: {output_dir: x}"), "output_dir are set by the study"),
    (("name: t", "name: t\nfracture: {ksp_type: [cg]}"), "fracture.ksp_type must be a single"),
    (("sample: {sample_particles: 8, lattice_bonds: 6000}", "sample: 3"),
     "sample must be a mapping"),
    # Each field has its type: nothing falls back silently to a default.
    (("name: t", "name: [t]"), r"name must be a non-empty text, not \['t'\]"),
    (("name: t", "name: true"), "name must be a non-empty text, not True"),
    (("name: t", "name: 12"), "name must be a non-empty text, not 12"),
    (("sample: {sample_particles: 8, lattice_bonds: 6000}", "sample: 0"),
     "sample must be a mapping, not 0"),
    (("sample: {sample_particles: 8, lattice_bonds: 6000}", "sample: false"),
     "sample must be a mapping, not False"),
    (("name: t", "name: t\nphases: []"), r"phases must be a mapping, not \[\]"),
    (("name: t", "name: t\nfracture: {-ksp_type: cg}"), "fracture: '-ksp_type' is not an option"),
    (("name: t", "name: t\nfracture: {1: 2}"), "fracture: 1 is not an option name"),
    (("name: t", "name: t\nfracture: {ksp rtol: 1e-8}"), "'ksp rtol' is not an option name"),
    (("name: t", "name: t\nfracture: {ksp_rtol: .nan}"), "fracture.ksp_rtol must be finite"),
    (("name: t", "name: t\nfracture: {ksp_rtol: ''}"), "fracture.ksp_rtol is empty"),
    (("name: t", "name: t\nfracture: {ksp_rtol: }"), "fracture.ksp_rtol must be a single value, "
                                                      "not None"),
])
def test_bad_study_files_are_refused(tmp_path, change, message):
    text = BASE.replace(*change)
    assert text != BASE
    with pytest.raises(StudyError, match=message):
        load_study(study_file(tmp_path, text))


def test_unreadable_study_files(tmp_path):
    with pytest.raises(StudyError, match="cannot read the study file"):
        load_study(str(tmp_path / "missing.yaml"))
    with pytest.raises(StudyError, match="not valid YAML"):
        load_study(study_file(tmp_path, "a: [1,"))
    with pytest.raises(StudyError, match="expected a mapping"):
        load_study(study_file(tmp_path, "- 1\n- 2\n"))


def test_an_output_path_that_is_a_file_is_named(tmp_path):
    out = tmp_path / "out"
    out.write_text("a file of the user's\n")
    with pytest.raises(StudyError, match="output folder .*out is a file, not a folder"):
        Study(study_file(tmp_path), str(out))
    assert out.read_text() == "a file of the user's\n"


def test_a_data_path_that_is_a_file_is_named_before_any_work(tmp_path, capsys):
    data = tmp_path / "data"
    data.write_text("a file of the user's\n")
    out = tmp_path / "out"
    assert study.main(["plan", study_file(tmp_path), str(out), "--data", str(data)]) == 1
    assert capsys.readouterr().err.endswith(
        ": error: the data folder (--data) %s is a file, not a folder: choose another path\n"
        % data)
    assert data.read_text() == "a file of the user's\n"
    assert not out.exists()                         # no study.json left behind either


def test_the_largest_rank_count_is_planned(tmp_path):
    assert load_study(study_file(tmp_path, BASE.replace("ranks: 1", "ranks: 1000000")))[
        "ranks"] == 1000000


def test_hash_ignores_the_rank_count_only(tmp_path):
    one = study.study_hash(load_study(study_file(tmp_path)))
    assert study.study_hash(load_study(study_file(tmp_path, BASE.replace("ranks: 1", "ranks: 4"),
                                                  "r.yaml"))) == one
    assert study.study_hash(load_study(study_file(tmp_path, BASE.replace("0.24", "0.25"),
                                                  "g.yaml"))) != one


def test_solver_options_reach_the_runs_but_not_the_hash(tmp_path):
    """The solver section changes how the runs are solved (the same ruptures:
    docs/notes/solver-lever-fidelity.md), so a study keeps its rows when a
    lever is added; the runs get the options."""
    plain = Study(study_file(tmp_path), str(tmp_path / "a"), bin_dir=str(tmp_path / "no-bin"))
    text = BASE + "solver: {solver_direct_tail: 100, ksp_rtol: 1.0e-6}\n"
    routed = Study(study_file(tmp_path, text, "dt.yaml"), str(tmp_path / "b"),
                   bin_dir=str(tmp_path / "no-bin"))
    assert study.study_hash(routed.spec) == study.study_hash(plain.spec)
    options = routed.fracture_options([])
    assert options[options.index("-solver_direct_tail") + 1] == "100"
    assert options[options.index("-ksp_rtol") + 1] == "1e-06"
    assert "-solver_direct_tail" not in plain.fracture_options([])


@pytest.mark.parametrize("solver, message", [
    ("{fracture_stop_fraction: 0.5}", "solver.fracture_stop_fraction is not a solver option"),
    ("{ksp_rtol: [1, 2]}", "solver.ksp_rtol must be a single value"),
])
def test_solver_section_takes_solver_options_only(tmp_path, solver, message):
    with pytest.raises(StudyError, match=message):
        load_study(study_file(tmp_path, BASE + "solver: %s\n" % solver))


def test_a_solver_option_given_twice_is_an_error(tmp_path):
    text = BASE + "fracture: {ksp_rtol: 1.0e-6}\nsolver: {ksp_rtol: 1.0e-7}\n"
    with pytest.raises(StudyError, match="ksp_rtol is given under both fracture and solver"):
        load_study(study_file(tmp_path, text))


def test_particle_contact_strength_reaches_the_runs(tmp_path):
    """phases.sigma_pp (the paper's fig. 3: 0.3 sigma^p) is -phase_sigma_pp of
    every run; left out, the runs have bare contacts and the hash is that of
    a study file that never knew the key."""
    bare = Study(study_file(tmp_path), str(tmp_path / "a"), bin_dir=str(tmp_path / "no-bin"))
    options = bare.fracture_options([])
    assert options[options.index("-phase_sigma_pp") + 1] == "0"
    assert "sigma_pp" not in bare.spec["phases"]
    text = BASE.replace("name: t", "name: t\nphases: {sigma_pp: 0.003}")
    glued = Study(study_file(tmp_path, text, "pp.yaml"), str(tmp_path / "b"),
                  bin_dir=str(tmp_path / "no-bin"))
    options = glued.fracture_options([])
    assert options[options.index("-phase_sigma_pp") + 1] == "0.003"
    assert study.study_hash(glued.spec) != study.study_hash(bare.spec)


def test_options_list():
    assert study.options_list({"a": True, "b": False, "c": 0.5}) == \
        ["-a", "true", "-b", "false", "-c", "0.5"]


# --- a study whose runs are written here, as lem_fracture would -----------
A_TRUE, K_TRUE = 0.3, 2.5
SIGMA_P = 0.01


def complete_run(s, run, beta=0.8):
    d = s.run_dir(run)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, "run.json"), "w") as f:
        json.dump(s.run_record(run), f)
    rho, ratio = run["rho_m"], run["sigma_pm_ratio"]
    strength = A_TRUE * rho * (2 * 0.28 - rho) / (1 - K_TRUE * rho)   # eq. 10
    summary = {"E_eff_over_E_unit": rho, "sigma_eff_over_sigma_unit": 2 * strength,
               "sigma_eff": strength * ratio * SIGMA_P, "strain_at_peak": 1e-3, "n_b": 0.1,
               "broken": 20, "broken_p": 2, "broken_m": 3, "broken_pp": 10, "broken_pm": 5,
               "end_reason": "stress below the stop fraction of the peak", "solves": 7,
               "seconds": 1.5}
    with open(os.path.join(d, "summary.json"), "w") as f:
        json.dump(summary, f)
    write_curve(os.path.join(d, "curve.csv"), [(1e-4, 0.1, 0.1, 0, 0, 10, 0),
                                               (2e-4, 0.2, 0.1, 2, 3, 10, 5)])
    with open(os.path.join(d, "stress.json"), "w") as f:
        json.dump({"tail": {"beta": beta + rho}}, f)
    write_manifest(d, ("summary.json", "curve.csv"))


@pytest.fixture
def made_study(tmp_path):
    s = Study(study_file(tmp_path), str(tmp_path / "out"), bin_dir=str(tmp_path / "no-bin"))
    s.plan()
    return s


def test_runs_and_their_states(made_study):
    runs = made_study.runs()
    assert [r["id"] for r in runs] == ["rho_0.1300_spm_0.4000", "rho_0.1300_spm_1.2000",
                                       "rho_0.2400_spm_0.4000", "rho_0.2400_spm_1.2000"]
    complete_run(made_study, runs[0])
    os.makedirs(made_study.run_dir(runs[1]))
    with open(os.path.join(made_study.run_dir(runs[1]), "failed.json"), "w") as f:
        f.write("{}")
    assert [made_study.state(r) for r in runs] == ["complete", "failed", "pending", "pending"]
    # a run of another study in the same place is not complete
    with open(os.path.join(made_study.run_dir(runs[0]), "run.json"), "w") as f:
        json.dump(dict(made_study.run_record(runs[0]), study_hash="other"), f)
    assert made_study.state(runs[0]) == "pending"


def test_plan_refuses_another_study_in_the_same_folder(made_study, tmp_path):
    other = Study(study_file(tmp_path, BASE.replace("0.24", "0.25"), "o.yaml"), made_study.out)
    with pytest.raises(StudyError, match="holds the results of a different study"):
        other.plan()


def test_gather_writes_the_table_the_fit_and_the_figures(made_study, capsys):
    for run in made_study.runs():
        complete_run(made_study, run)
    assert study.gather(made_study) == 0
    out = made_study.out
    table = results.read_study_results(os.path.join(out, "results.csv"))
    assert table.header == list(results.STUDY_COLUMNS)
    assert table.text("id") == [r["id"] for r in made_study.runs()]
    rows = table.records_by("id")
    row = rows["rho_0.2400_spm_1.2000"]
    assert float(row["sigma_eff_over_sigma_pm"]) == pytest.approx(
        A_TRUE * 0.24 * (0.56 - 0.24) / (1 - K_TRUE * 0.24))
    assert float(row["n_b_without_bare_contacts"]) == 0.2       # 2 / (20 - 10)
    assert float(row["K_c_r_eq14"]) == pytest.approx((0.24 * 3 * 1.2) ** 0.5)
    assert float(row["beta"]) == pytest.approx(0.8 + 0.24)
    with open(os.path.join(out, "fit.json")) as f:
        fit = json.load(f)
    assert fit["eq10"]["A"] == pytest.approx(A_TRUE, rel=1e-5)
    assert fit["eq10"]["k"] == pytest.approx(K_TRUE, rel=1e-5)
    assert fit["beta_by_rho_m"] == {"0.1300": pytest.approx(0.93), "0.2400": pytest.approx(1.04)}
    assert fit["complete_runs"] == 4 and fit["missing_runs"] == []
    # one run per point: the figures show the runs, and eq. 10 is fitted to them
    assert "each a single run" in fit["eq10_fitted_to"] and "beta_std_by_rho_m" not in fit
    # no sample summary here: the bonds the study file asks for
    assert fit["figures"] == {"sample_particles": 8, "bonds": 6000.0, "bonds_per_particle": 750.0,
                              "L_n": pytest.approx(6000 ** (-1 / 3)),
                              "bonds_from": "study file (sample.lattice_bonds)",
                              "runs_per_point": [1, 1]}
    for name in ("strength", "damage", "stiffness_stress"):
        with open(os.path.join(out, "figures", name + ".png"), "rb") as f:
            assert f.read(8) == b"\x89PNG\r\n\x1a\n"
        with open(os.path.join(out, "figures", name + ".pdf"), "rb") as f:
            assert f.read(5) == b"%PDF-"
    assert sorted(os.listdir(out)) == ["figures", "fit.json", "results.csv", "runs", "study.json"]
    assert "gather: 4 runs" in capsys.readouterr().out


def test_gather_takes_the_resolution_from_the_samples(made_study):
    """lem_sample's bond count of the samples of the figures' runs, not
    the one the study file asks for."""
    os.makedirs(os.path.join(made_study.out, "samples"))
    for rho, bonds in ((0.13, 6100), (0.24, 6300)):
        with open(os.path.join(made_study.out, "samples", "rho_%.4f_summary.json" % rho),
                  "w") as f:
            json.dump({"bonds": bonds, "sample_particles": 8}, f)
    for run in made_study.runs():
        complete_run(made_study, run)
    assert study.gather(made_study) == 0
    with open(os.path.join(made_study.out, "fit.json")) as f:
        figures = json.load(f)["figures"]
    assert figures["bonds_from"] == "samples"
    assert figures["bonds"] == 6200.0 and figures["bonds_per_particle"] == 775.0
    assert figures["L_n"] == pytest.approx((6100 ** (-1 / 3) + 6300 ** (-1 / 3)) / 2)


def test_gather_leaves_out_incomplete_runs(made_study, capsys):
    runs = made_study.runs()
    complete_run(made_study, runs[0])
    complete_run(made_study, runs[3])
    os.remove(os.path.join(made_study.run_dir(runs[3]), "stress.json"))
    assert study.gather(made_study) == 1
    assert "rho_0.1300_spm_1.2000 not complete: left out" in capsys.readouterr().out
    with open(os.path.join(made_study.out, "results.csv"), newline="") as f:
        rows = list(csv.DictReader(f))
    assert [r["id"] for r in rows] == [runs[0]["id"], runs[3]["id"]]
    assert math.isnan(float(rows[1]["beta"]))
    with open(os.path.join(made_study.out, "fit.json")) as f:
        assert json.load(f)["missing_runs"] == [runs[1]["id"], runs[2]["id"]]


def test_gather_without_complete_runs_writes_nothing(made_study):
    assert study.gather(made_study) == 1
    assert not os.path.exists(os.path.join(made_study.out, "results.csv"))


def test_status_command_counts(made_study, capsys):
    complete_run(made_study, made_study.runs()[2])
    assert made_study.status() == {"complete": 1, "failed": 0, "pending": 3}
    assert "1 complete, 0 failed, 3 pending" in capsys.readouterr().out


def test_index_out_of_range(made_study):
    with pytest.raises(StudyError, match="the study has 4 runs"):
        made_study.run_all(index=4)


def test_index_picks_one_run_of_all_and_is_refused_elsewhere(tmp_path, monkeypatch, capsys):
    """`all --index I` makes what the study lacks, then runs only run I; a
    command without samples, lattices or runs to pick from refuses it."""
    calls = []
    monkeypatch.setattr(Study, "make_samples", lambda self, index=None: calls.append(("s", index)))
    monkeypatch.setattr(Study, "calibrate", lambda self, index=None: calls.append(("c", index)) or 0)
    monkeypatch.setattr(Study, "run_all", lambda self, index=None: calls.append(("r", index)) or 0)
    monkeypatch.setattr(study, "gather", lambda s: 0)
    monkeypatch.setattr(study, "launcher", lambda ranks: ["mpirun"])
    args = [study_file(tmp_path), str(tmp_path / "out"), "--index", "3"]
    assert study.main(["all"] + args) == 0
    assert calls == [("s", None), ("c", None), ("r", 3)]
    calls.clear()                                       # a run it lacks: refused before any work
    assert study.main(["all"] + args[:2] + ["--index", "4"]) == 1
    assert calls == [] and "--index 4: the study has 4 runs" in capsys.readouterr().err
    for command in ("plan", "status", "gather"):
        assert study.main([command] + args) == 1
        assert "--index picks a sample, lattice or run; `%s` takes none" % command \
            in capsys.readouterr().err


def test_execute_hands_sigterm_on_as_sigusr1(tmp_path):
    """Open MPI's mpirun kills the ranks on SIGTERM and passes SIGUSR1 on, so
    the study turns a SIGTERM it gets into SIGUSR1 for its child."""
    ready, got = tmp_path / "ready", tmp_path / "got"
    child = tmp_path / "child.py"
    child.write_text(textwrap.dedent(f"""
        import signal, sys, time
        def stop(number, _):
            open({str(got)!r}, "w").write(signal.Signals(number).name)
            sys.exit(4)
        for s in (signal.SIGUSR1, signal.SIGTERM):
            signal.signal(s, stop)
        open({str(ready)!r}, "w").close()
        time.sleep(60)
        """))

    def signal_the_study():
        for _ in range(1000):
            if ready.exists():
                break
            time.sleep(0.01)
        os.kill(os.getpid(), signal.SIGTERM)

    threading.Thread(target=signal_the_study).start()
    assert study.execute([sys.executable, str(child)], str(tmp_path / "log")) == 4
    assert got.read_text() == "SIGUSR1"


def test_an_interrupted_run_stops_the_others(made_study, monkeypatch):
    started = []

    def run_one(run):
        started.append(run["id"])
        return study.EXIT_INTERRUPTED

    monkeypatch.setattr(made_study, "run_one", run_one)
    assert made_study.run_all() == study.EXIT_INTERRUPTED
    assert len(started) == 1
