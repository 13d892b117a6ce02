"""Under CI=true a skip is a failure, for pytest (ci_skips.py) and for ctest
(jobs/check-no-skips.sh): checked on a real skipping test of each kind."""
import os
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, "..", ".."))


def run(cmd, cwd, ci):
    env = dict(os.environ)
    env.pop("CI", None)
    if ci:
        env["CI"] = "true"
    env["PYTHONPATH"] = HERE
    return subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)


@pytest.mark.parametrize("body", [
    "import pytest\n\ndef test_one():\n    pytest.skip('no data')\n",
    "import pytest\npytest.importorskip('no_such_module_here')\n\ndef test_one():\n    pass\n",
])
def test_a_pytest_skip_fails_only_under_ci(tmp_path, body):
    (tmp_path / "test_skipping.py").write_text(body)
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "ci_skips", "."]
    assert run(cmd, tmp_path, ci=False).returncode in (0, 5)  # 5: nothing collected
    under_ci = run(cmd, tmp_path, ci=True)
    assert under_ci.returncode != 0
    assert "CI=true" in under_ci.stdout


def test_an_expected_failure_is_not_a_skip(tmp_path):
    (tmp_path / "test_xfail.py").write_text(
        "import pytest\n\n@pytest.mark.xfail(reason='known')\ndef test_one():\n    assert False\n")
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "ci_skips", "."]
    assert run(cmd, tmp_path, ci=True).returncode == 0


@pytest.mark.skipif(shutil.which("cmake") is None or shutil.which("ctest") is None,
                    reason="cmake is not installed")
def test_a_ctest_skip_is_named(tmp_path):
    """A CMake project with one passing and one skipping test (SKIP_RETURN_CODE)."""
    (tmp_path / "CMakeLists.txt").write_text(
        "cmake_minimum_required(VERSION 3.20)\nproject(skips NONE)\nenable_testing()\n"
        "add_test(NAME passes COMMAND sh -c \"exit 0\")\n"
        "add_test(NAME skips_here COMMAND sh -c \"exit 77\")\n"
        "set_tests_properties(skips_here PROPERTIES SKIP_RETURN_CODE 77)\n")
    build = tmp_path / "build"
    assert run(["cmake", "-S", str(tmp_path), "-B", str(build)], tmp_path, False).returncode == 0
    ctest = run(["ctest"], build, ci=False)
    assert ctest.returncode == 0  # ctest itself counts a skip as a pass
    log = tmp_path / "ctest.log"
    log.write_text(ctest.stdout)
    check = run(["bash", os.path.join(ROOT, "jobs", "check-no-skips.sh"), str(log)], tmp_path, True)
    assert check.returncode == 1
    assert "skips_here (Skipped)" in check.stderr and "passes" not in check.stderr
    log.write_text(ctest.stdout.replace("skips_here", "x").replace("(Skipped)", ""))
    assert run(["bash", os.path.join(ROOT, "jobs", "check-no-skips.sh"), str(log)],
               tmp_path, True).returncode == 0
