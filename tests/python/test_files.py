"""The atomic writer: a file appears whole or not at all."""
import json
import os

import pytest

from lem_tools.files import atomic_open, atomic_path, write_json


def test_written_file_appears_and_no_temporary_is_left(tmp_path):
    target = tmp_path / "table.csv"
    with atomic_open(str(target), newline="") as f:
        f.write("a,b\n1,2\n")
        assert not target.exists()  # not visible before the block ends
    assert target.read_text() == "a,b\n1,2\n"
    assert os.listdir(tmp_path) == ["table.csv"]


def test_error_leaves_no_partial_file(tmp_path):
    target = tmp_path / "fit.json"
    with pytest.raises(RuntimeError):
        with atomic_open(str(target)) as f:
            f.write('{"A": ')
            raise RuntimeError("the writer failed half-way")
    assert os.listdir(tmp_path) == []


def test_error_keeps_the_previous_file(tmp_path):
    target = tmp_path / "results.csv"
    target.write_text("old complete table\n")
    with pytest.raises(ValueError):
        with atomic_path(str(target)) as temporary:
            with open(temporary, "w") as f:
                f.write("new half")
            raise ValueError("interrupted")
    assert target.read_text() == "old complete table\n"
    assert os.listdir(tmp_path) == ["results.csv"]


def test_write_json(tmp_path):
    target = str(tmp_path / "run.json")
    write_json(target, {"id": "rho_0.1300", "rho_m": 0.13})
    with open(target) as f:
        assert json.load(f) == {"id": "rho_0.1300", "rho_m": 0.13}
