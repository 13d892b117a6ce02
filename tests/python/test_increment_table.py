"""The load-increment comparison (increment_table): each run set against the
same sample's run at the reference increment, and the verdict against the
scatter between samples."""
import json
import math
import os

import pytest

from lem_tools import increment_table
from lem_tools.errors import ToolError
from lem_tools.results import STUDY_COLUMNS
from lem_tools.study_data import CURVE_KEEP, FORMAT, VERSION

SPEC = {"name": "inc", "ranks": 2, "sample": {"sample_particles": 64}, "phases": {},
        "fracture": {"fracture_stop_fraction": 0.3}}


def write_folder(path, increment, values, spec=SPEC, rho_m=0.13):
    """A data folder of a study at `increment` with one row per (seed,
    sigma_eff, broken_p) of `values`, at `rho_m` and sigma^pm = sigma^p."""
    spec = json.loads(json.dumps(spec))
    if increment is not None:
        spec["fracture"]["fracture_increment"] = increment
    spec["hash"] = "h%s" % increment
    os.makedirs(os.path.join(path, "runs"))
    with open(os.path.join(path, "study.json"), "w") as f:
        json.dump(spec, f)
    for seed, sigma, broken_p in values:
        run = {"id": "p%d_rho_%.4f_spm_1.0000" % (seed, rho_m), "rho_m": rho_m,
               "sigma_pm_ratio": 1.0}
        row = dict.fromkeys(STUDY_COLUMNS, None)
        row.update(id=run["id"], sigma_eff_over_sigma_unit=sigma, strain_at_peak=4e-3, n_b=0.1,
                   broken_p=broken_p, broken_m=10, broken_pp=100)
        data = {"format": FORMAT, "version": VERSION, "study": spec["name"],
                "study_hash": spec["hash"], "run": run, "row": row,
                "sample": {"packing_seed": seed, "lattice_seed": 1},
                "curve": {"columns": list(CURVE_KEEP), "rows": [[4e-3, 0.5, 0.5, 3, 0.1]]}}
        with open(os.path.join(path, "runs", run["id"] + ".json"), "w") as f:
            json.dump(data, f)
    return path


def test_changes_are_paired_by_sample_and_judged_against_the_scatter(tmp_path):
    # The samples scatter by 0.1 in sigma at x1; x2 moves each sample by
    # +0.01 (within the scatter) and x4 by -0.3 (outside it).
    x1 = write_folder(tmp_path / "x1", None, [(1, 0.4, 5), (2, 0.5, 7), (3, 0.6, 9)])
    x2 = write_folder(tmp_path / "x2", 6e-4, [(1, 0.41, 5), (2, 0.51, 7), (3, 0.61, 9)])
    x4 = write_folder(tmp_path / "x4", 1.2e-3, [(1, 0.1, 15), (2, 0.2, 17), (3, 0.3, 19)])
    rows = increment_table.read_rows([str(x4), str(x1), str(x2)])
    table = increment_table.compare(rows, 3e-4)
    stats = table[(0.13, 1.0)]
    assert sorted(stats) == [3e-4, 6e-4, 1.2e-3]
    sigma = "sigma_eff_over_sigma_unit"
    assert stats[3e-4][sigma]["mean"] == pytest.approx(0.5)
    assert stats[3e-4][sigma]["std"] == pytest.approx(0.1)
    assert stats[6e-4][sigma]["change"] == pytest.approx(0.01)
    assert stats[1.2e-3][sigma]["change"] == pytest.approx(-0.3)
    judge = increment_table.within_scatter(stats, 3e-4, sigma)
    assert judge(6e-4) and not judge(1.2e-3)
    assert stats[1.2e-3]["broken_p"]["change"] == pytest.approx(10)
    # a missing value stays missing: no change is made up from it
    assert math.isnan(stats[6e-4]["broken_pm"]["mean"])
    text = increment_table.markdown(table, 3e-4)
    assert "| 2 | 3 | 0.51 ± 0.1 (+0.01*)" in text
    assert "| 4 | 3 | 0.2 ± 0.1 (-0.3)" in text


def test_a_change_is_not_within_a_scatter_of_one_sample(tmp_path):
    x1 = write_folder(tmp_path / "x1", None, [(1, 0.4, 5)])
    x2 = write_folder(tmp_path / "x2", 6e-4, [(1, 0.4, 5)])
    stats = increment_table.compare(increment_table.read_rows([str(x1), str(x2)]), 3e-4)
    assert not increment_table.within_scatter(stats[(0.13, 1.0)], 3e-4,
                                              "sigma_eff_over_sigma_unit")(6e-4)


def test_studies_of_other_physics_or_without_the_reference_are_refused(tmp_path):
    x1 = write_folder(tmp_path / "x1", None, [(1, 0.4, 5)])
    other = dict(SPEC, fracture={"fracture_stop_fraction": 0.5})
    x2 = write_folder(tmp_path / "x2", 6e-4, [(1, 0.4, 5)], spec=other)
    with pytest.raises(ToolError, match="differ in more than fracture_increment"):
        increment_table.read_rows([str(x1), str(x2)])
    x4 = write_folder(tmp_path / "x4", 1.2e-3, [(1, 0.4, 5)])
    with pytest.raises(ToolError, match="no run at the reference increment"):
        increment_table.compare(increment_table.read_rows([str(x4)]), 3e-4)
    with pytest.raises(ToolError, match="not a study data folder"):
        increment_table.read_rows([str(tmp_path)])


def test_a_point_without_its_reference_run_is_left_out_and_named(tmp_path, capsys):
    # A study carried on in parts: rho^m 0.28 has its x4 run, not yet its x1.
    x1 = write_folder(tmp_path / "x1", None, [(1, 0.4, 5)])
    x4 = write_folder(tmp_path / "x4", 1.2e-3, [(1, 0.39, 5)])
    x4b = write_folder(tmp_path / "x4b", 1.2e-3, [(1, 0.5, 5)], rho_m=0.28)
    rows = increment_table.read_rows([str(x1), str(x4), str(x4b)])
    table = increment_table.compare(rows, 3e-4)
    assert list(table) == [(0.13, 1.0)]
    assert table[(0.13, 1.0)][1.2e-3]["sigma_eff_over_sigma_unit"]["change"] == pytest.approx(-0.01)
    assert increment_table.without_reference(rows, table) == [(0.28, 1.0)]
    out = tmp_path / "out"
    assert increment_table.main([str(x1), str(x4), str(x4b), "--out", str(out)]) == 0
    assert "left out: rho^m 0.28" in capsys.readouterr().out


def test_the_command_writes_its_table_and_figure(tmp_path, capsys):
    x1 = write_folder(tmp_path / "x1", None, [(1, 0.4, 5), (2, 0.5, 7)])
    x2 = write_folder(tmp_path / "x2", 6e-4, [(1, 0.42, 5), (2, 0.52, 7)])
    out = tmp_path / "out"
    assert increment_table.main([str(x1), str(x2), "--out", str(out)]) == 0
    for name in ("increment.csv", "increment.json", "increment.png"):
        assert (out / name).stat().st_size > 0
    assert "ρ^m = 0.13" in capsys.readouterr().out
    assert increment_table.main([str(tmp_path / "none")]) == 1
