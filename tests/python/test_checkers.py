"""The fracture tests' checker (tests/drivers/fracture_check.py) refuses a
missing, null or NaN value: each comparison holds only for a finite number."""
import importlib.util
import math
import os
import shutil
import subprocess
import sys

import pytest

from conftest import write_fracture_results

CHECK = os.path.join(os.path.dirname(__file__), "..", "drivers", "fracture_check.py")


def load_checker():
    spec = importlib.util.spec_from_file_location("fracture_check", CHECK)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("value", [None, math.nan, math.inf, "0.5", True])
def test_every_comparison_refuses_what_is_not_a_finite_number(value):
    check = load_checker().Checker()
    check.close("close", value, 0.5, rtol=1.0)
    check.at_most("at_most", value, 1.0)
    check.at_least("at_least", value, 0.0)
    assert check.failed == ["close", "at_most", "at_least"]


def test_sound_values_pass():
    check = load_checker().Checker()
    check.close("close", 0.5, 0.5, rtol=1e-9)
    check.at_most("at_most", 0.5, 1.0)
    check.at_least("at_least", 2, 1)
    assert check.failed == []


def damage_curve(directory, step, column, value):
    path = os.path.join(directory, "curve.csv")
    lines = open(path).read().splitlines()
    header = lines[0].split(",")
    cells = lines[step].split(",")
    cells[header.index(column)] = value
    lines[step] = ",".join(cells)
    open(path, "w").write("\n".join(lines) + "\n")


def run_check(*args):
    return subprocess.run([sys.executable, CHECK, *args], capture_output=True, text=True)


@pytest.mark.parametrize("what", ["ruptures", "curves"])
def test_a_nan_on_a_curve_fails(tmp_path, what):
    a = write_fracture_results(str(tmp_path / "a"))
    b = str(tmp_path / "b")
    shutil.copytree(a, b)
    assert run_check(what, a, b, "1e-6").returncode == 0
    damage_curve(a, 2, "stress_norm", "nan")
    result = run_check(what, a, b, "1e-6")
    assert result.returncode != 0, result.stdout
    assert "FAIL" in result.stdout + result.stderr
