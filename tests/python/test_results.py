"""The one results reader on small files written here."""
import csv
import json
import math
import os

import numpy as np
import pytest

from conftest import cube_lattice, write_elastic, write_manifest
from lem_tools import results
from lem_tools.results import ResultsError


def write(path, text):
    with open(path, "w") as f:
        f.write(text)
    return str(path)


def test_csv_skips_the_comment_line_and_reads_columns(tmp_path):
    path = write(tmp_path / "t.csv", "# written by a driver, units: none\nname,a,b\nx,1,2.5\ny,3,-4\n")
    table = results.read_csv(path, required=("a", "b"))
    assert table.header == ["name", "a", "b"]
    assert len(table) == 2
    assert table.text("name") == ["x", "y"]
    np.testing.assert_array_equal(table.numbers("b"), [2.5, -4.0])
    assert table.records_by("name")["y"] == {"name": "y", "a": "3", "b": "-4"}


def test_csv_missing_column_is_named(tmp_path):
    path = write(tmp_path / "t.csv", "a,b\n1,2\n")
    with pytest.raises(ResultsError, match=r"t\.csv: header lacks column\(s\) c, d"):
        results.read_csv(path, required=("a", "c", "d"))


def test_csv_short_row_gives_the_file_line(tmp_path):
    # line 4 of the file: the comment line counts
    path = write(tmp_path / "t.csv", "# comment\na,b\n1,2\n3\n")
    with pytest.raises(ResultsError, match="line 4 has 1 fields, the header has 2"):
        results.read_csv(path)


def test_csv_text_in_a_number_column(tmp_path):
    path = write(tmp_path / "t.csv", "a\n1\nnot-a-number\n")
    with pytest.raises(ResultsError, match="column a"):
        results.read_csv(path).numbers("a")


def test_csv_missing_file_and_empty_file(tmp_path):
    with pytest.raises(ResultsError, match="does not exist"):
        results.read_csv(str(tmp_path / "none.csv"))
    with pytest.raises(ResultsError, match="no header line"):
        results.read_csv(write(tmp_path / "e.csv", "# only a comment\n"))
    with pytest.raises(ResultsError, match="no data row"):
        results.read_csv(write(tmp_path / "h.csv", "a,b\n"), need_rows=True)


def test_curve_of_a_fracture_run(fracture_dir):
    curve = results.read_curve(os.path.join(fracture_dir, "curve.csv"))
    assert set(curve) == set(results.CURVE_COLUMNS)
    np.testing.assert_allclose(curve["strain"], [1e-4, 2e-4, 3e-4])
    np.testing.assert_array_equal(curve["broken"], [3, 6, 12])
    np.testing.assert_allclose(curve["n_b"], [0, 1 / 6, 2 / 12])


def test_curve_reads_in_standard_readers(fracture_dir):
    # The header row first: csv, numpy and the tools agree without options.
    path = os.path.join(fracture_dir, "curve.csv")
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    table = np.genfromtxt(path, delimiter=",", names=True)
    curve = results.read_curve(path)
    np.testing.assert_allclose(table["strain"], [float(r["strain"]) for r in rows])
    np.testing.assert_allclose(table["strain"], curve["strain"])


def test_curve_of_an_older_version_with_a_comment_line(tmp_path, fracture_dir):
    with open(os.path.join(fracture_dir, "curve.csv")) as f:
        text = f.read()
    path = write(tmp_path / "curve.csv", "# stress-strain curve of lem_fracture\n" + text)
    np.testing.assert_allclose(results.read_curve(path)["strain"], [1e-4, 2e-4, 3e-4])


def test_curve_without_rows_is_refused(tmp_path):
    path = write(tmp_path / "curve.csv", "# header only\n" + ",".join(results.CURVE_COLUMNS) + "\n")
    with pytest.raises(ResultsError, match="no data row"):
        results.read_curve(path)


def test_broken_bonds(fracture_dir):
    xyz, phase, threshold = results.read_broken(os.path.join(fracture_dir, "broken.csv"))
    assert xyz.shape == (12, 3)
    np.testing.assert_allclose(xyz[5], [0.5, 0.4, 0.25])
    assert list(phase[:4]) == ["pp", "pp", "pp", "p"]
    assert (threshold <= 0).sum() == 3


def test_no_broken_bond(tmp_path):
    path = write(tmp_path / "broken.csv", "step,cycle,strain,bond_id,phase,x,y,z,force,threshold\n")
    xyz, phase, threshold = results.read_broken(path)
    assert xyz.shape == (0, 3) and len(phase) == 0 and len(threshold) == 0


def test_summary_json_and_csv_agree(tmp_path):
    write(tmp_path / "summary.csv",
          "sample_file,nodes,E_eff[stress],n_b,end_reason,seconds[s]\n"
          "meshes/mini.h5,2962,0.85,0.0037,stress below the stop fraction of the peak,1.5\n")
    from_csv = results.read_summary(str(tmp_path / "summary.csv"))
    expected = {"sample_file": "meshes/mini.h5", "nodes": 2962, "E_eff": 0.85, "n_b": 0.0037,
                "end_reason": "stress below the stop fraction of the peak", "seconds": 1.5}
    assert from_csv == expected
    assert isinstance(from_csv["nodes"], int)
    write(tmp_path / "summary.json", json.dumps(expected))
    assert results.read_summary(str(tmp_path / "summary.json")) == from_csv


def test_json_must_be_an_object(tmp_path):
    with pytest.raises(ResultsError, match="not a JSON object"):
        results.read_json(write(tmp_path / "a.json", "[1, 2]"))
    with pytest.raises(ResultsError, match="cannot read"):
        results.read_json(write(tmp_path / "b.json", "{not json"))


def test_finite_number():
    values = {"a": 1, "b": 2.5, "c": True, "d": float("nan"), "e": "3", "f": float("inf")}
    assert [results.finite_number(values, k) for k in "abcdefg"] == \
        [1.0, 2.5, None, None, None, None, None]


def test_stress_beta(tmp_path):
    assert math.isnan(results.read_stress_beta(str(tmp_path / "missing.json")))
    assert math.isnan(results.read_stress_beta(write(tmp_path / "s.json", '{"tail": null}')))
    assert results.read_stress_beta(write(tmp_path / "t.json", '{"tail": {"beta": 0.7}}')) == 0.7


def test_elastic_fields(tmp_path):
    coords, volume = cube_lattice(3)
    stress = np.zeros((len(coords), 6))
    stress[:, 5] = 2.0
    path = str(tmp_path / "elastic.h5")
    write_elastic(path, coords, stress, volume, applied=2.0, strain=1e-5)
    elastic = results.read_elastic(path)
    np.testing.assert_array_equal(elastic["coords"], coords)
    assert elastic["applied"] == 2.0 and elastic["strain"] == 1e-5
    assert elastic["stress"].shape == (27, 6)


def test_elastic_fields_problems(tmp_path):
    coords, volume = cube_lattice(2)
    with pytest.raises(ResultsError, match="not found"):
        results.read_elastic(str(tmp_path / "elastic.h5"))
    write_elastic(str(tmp_path / "a.h5"), coords, None, volume, applied=1.0)
    with pytest.raises(ResultsError, match="has no node stresses"):
        results.read_elastic(str(tmp_path / "a.h5"))
    write_elastic(str(tmp_path / "b.h5"), coords, np.ones((8, 6)), volume, applied=0.0)
    with pytest.raises(ResultsError, match="applied stress 0 is not positive"):
        results.read_elastic(str(tmp_path / "b.h5"))
    with pytest.raises(ResultsError, match="cannot read"):
        results.read_hdf5(str(tmp_path / "b.h5"), ("bonds/force",))


def test_a_finished_run_is_one_whose_manifest_agrees(fracture_dir):
    assert results.finished_problem(fracture_dir) is None
    with open(os.path.join(fracture_dir, "broken.csv"), "a") as f:
        f.write("9,0,1e-4,99,p,0,0,0,1e-6,0.1\n")
    with pytest.raises(ResultsError, match="broken.csv has .* bytes, manifest.txt says"):
        results.require_finished(fracture_dir)
    os.remove(os.path.join(fracture_dir, "broken.csv"))
    assert "broken.csv is missing" in results.finished_problem(fracture_dir)
    manifest = os.path.join(fracture_dir, "manifest.txt")
    with open(manifest) as f:
        text = f.read()
    with open(manifest, "w") as f:
        f.write(text.replace("end\n", ""))
    with pytest.raises(ResultsError, match="no end line"):
        results.require_finished(fracture_dir)
    os.remove(manifest)
    assert "holds no finished result" in results.finished_problem(fracture_dir)


def test_a_file_changed_at_its_size_is_not_finished(fracture_dir):
    """The manifest's checksums catch what the sizes cannot."""
    path = os.path.join(fracture_dir, "curve.csv")
    with open(path, "r+b") as f:
        text = f.read()
        f.seek(0)
        f.write(text.replace(b"1", b"2", 1))
    assert os.path.getsize(path) == len(text)
    with pytest.raises(ResultsError, match="curve.csv has other content than the run wrote "
                       r"\(checksum crc32:[0-9a-f]{8}, manifest.txt says crc32:[0-9a-f]{8}\)"):
        results.require_finished(fracture_dir)
    # A manifest written before checksums: the sizes alone are checked.
    write_manifest(fracture_dir, ("curve.csv", "broken.csv", "summary.json"), checksums=False)
    assert results.finished_problem(fracture_dir) is None


def test_a_manifest_without_one_checksum_is_damaged(fracture_dir):
    """A checksum line removed does not let a changed file pass as complete."""
    manifest = os.path.join(fracture_dir, "manifest.txt")
    with open(manifest) as f:
        lines = f.read().splitlines(keepends=True)
    with open(manifest, "w") as f:
        f.writelines(line for line in lines if not line.startswith("checksum=curve.csv "))
    with pytest.raises(ResultsError, match="manifest.txt is damaged: no checksum of curve.csv"):
        results.require_finished(fracture_dir)
