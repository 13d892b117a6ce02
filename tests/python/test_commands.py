"""The command-line scripts in tools/ and the package's structure."""
import ast
import glob
import json
import os
import re
import subprocess
import sys

import numpy as np
import pytest

from conftest import TOOLS, cube_lattice, write_elastic, write_manifest
from lem_tools import phases

SCRIPTS = sorted(glob.glob(os.path.join(TOOLS, "*.py")))
PACKAGE = os.path.join(TOOLS, "lem_tools")
ROOT = os.path.dirname(TOOLS)


def run_script(name, *args):
    return subprocess.run([sys.executable, os.path.join(TOOLS, name), *args],
                          capture_output=True, text=True, timeout=120)


def test_the_scripts_are_there():
    assert [os.path.basename(s) for s in SCRIPTS] == [
        "combine_studies.py", "convergence_data.py", "increment_table.py", "options_reference.py", "paper_figures.py",
        "paper_numbers.py", "plot_bridge_geometry.py",
        "plot_convergence.py", "plot_crack.py", "plot_fracture.py", "plot_stiffness.py",
        "plot_stress.py",
        "plot_tension.py", "scaling.py", "study.py", "study_figures.py", "work_split.py"]


@pytest.mark.parametrize("script", [os.path.basename(s) for s in SCRIPTS])
def test_help_exits_0(script):
    done = run_script(script, "--help")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("usage: " + script)
    assert done.stderr == ""


@pytest.mark.parametrize("script", ["plot_fracture.py", "plot_crack.py", "plot_stress.py",
                                    "plot_tension.py", "plot_stiffness.py", "plot_convergence.py", "work_split.py"])
def test_missing_results_give_one_error_line(script, tmp_path):
    done = run_script(script, str(tmp_path / "none"))
    assert done.returncode == 1
    assert re.fullmatch(re.escape(script) + r": error: [^\n]*none[^\n]*\n", done.stderr), \
        done.stderr


def test_wrong_argument_count_is_a_usage_error():
    done = run_script("plot_fracture.py")
    assert done.returncode == 2 and "the following arguments are required" in done.stderr
    done = run_script("plot_convergence.py", "a", "b")
    assert done.returncode == 2 and "needs both RESULTS_DIR_2 and LABEL_2" in done.stderr


def test_plot_fracture_draws_a_run(fracture_dir):
    done = run_script("plot_fracture.py", fracture_dir + "/")
    assert done.returncode == 0, done.stderr
    assert done.stdout == "wrote %s/fracture.png and fracture.pdf\n" % fracture_dir
    with open(os.path.join(fracture_dir, "fracture.png"), "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    with open(os.path.join(fracture_dir, "fracture.pdf"), "rb") as f:
        assert f.read(5) == b"%PDF-"


def test_plot_fracture_reports_a_broken_table(fracture_dir):
    with open(os.path.join(fracture_dir, "curve.csv"), "a") as f:
        f.write("4,0.1\n")
    write_manifest(fracture_dir, ("curve.csv", "broken.csv", "summary.json"))
    done = run_script("plot_fracture.py", fracture_dir)
    assert done.returncode == 1
    assert "curve.csv: line 5 has 2 fields" in done.stderr
    assert not os.path.exists(os.path.join(fracture_dir, "fracture.png"))


def test_plot_crack_draws_a_run_with_and_without_its_sample(fracture_dir):
    """No sample file: the slice says so; a sample named with --sample: drawn
    with its particles; a missing --sample: one error line, nothing drawn."""
    done = run_script("plot_crack.py", fracture_dir)
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith("wrote %s/crack.png and crack.pdf (crack at z = " % fracture_dir)
    with open(os.path.join(fracture_dir, "crack.png"), "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    os.remove(os.path.join(fracture_dir, "crack.png"))
    done = run_script("plot_crack.py", fracture_dir, "--sample", os.path.join(ROOT, "meshes", "tiny.h5"))
    assert done.returncode == 0, done.stderr
    assert os.path.exists(os.path.join(fracture_dir, "crack.png"))
    os.remove(os.path.join(fracture_dir, "crack.png"))
    done = run_script("plot_crack.py", fracture_dir, "--sample", fracture_dir + "/none.h5")
    assert done.returncode == 1 and "none.h5: no such sample file" in done.stderr
    assert not os.path.exists(os.path.join(fracture_dir, "crack.png"))


def test_crack_height_and_slice_geometry():
    from lem_tools.plot_crack import crack_height, slice_discs

    rng = np.random.default_rng(1)
    z = np.concatenate([rng.uniform(0, 10, 200), rng.normal(6.3, 0.05, 300)])
    edges, z_crack = crack_height(z, 0.0, 10.0, bins=40)
    assert edges[0] == 0 and edges[-1] == 10 and abs(z_crack - 6.3) <= 0.125
    # a sphere of radius 5 at y = 0 cut at y = 3: a circle of radius 4; one
    # that the plane misses is not drawn
    x, zc, r = slice_discs(np.array([[1.0, 0.0, 2.0], [0.0, 9.0, 0.0]]), np.array([5.0, 1.0]), 3.0)
    assert list(x) == [1.0] and list(zc) == [2.0] and r[0] == pytest.approx(4.0)


def test_plot_stress_fits_the_tail_and_writes_stress_json(tmp_path):
    coords, volume = cube_lattice(30)
    rng = np.random.default_rng(3)
    applied, beta = 1e-3, 2.0
    s = np.where(rng.random(len(coords)) < 0.5, rng.uniform(0, 1, len(coords)),
                 1 + rng.exponential(1 / beta, len(coords)))
    stress = np.zeros((len(coords), 6))
    stress[:, 5] = s * applied
    write_elastic(str(tmp_path / "elastic.h5"), coords, stress, volume, applied)
    done = run_script("plot_stress.py", str(tmp_path))
    assert done.returncode == 0, done.stderr
    with open(tmp_path / "stress.json") as f:
        result = json.load(f)
    assert result["tail"]["beta"] == pytest.approx(beta, rel=0.05)
    assert result["face_nodes"] == 30 ** 3 - 28 ** 3  # left out of the fit
    assert result["tail_all_nodes"]["beta"] == pytest.approx(beta, rel=0.05)
    assert result["loaded_nodes"] == len(coords)
    assert result["volume_average_stress_zz"] == pytest.approx(applied * s.mean())
    assert os.path.exists(tmp_path / "stress.png")
    assert sorted(os.listdir(tmp_path)) == ["elastic.h5", "stress.json", "stress.pdf", "stress.png"]


def test_plot_stress_maps_side_by_side(tmp_path):
    """--maps: one figure of several runs' mid-plane maps and nothing else
    written; several folders without --maps are a usage error."""
    coords, volume = cube_lattice(12)
    stress = np.zeros((len(coords), 6))
    stress[:, 5] = 1e-3
    for name in ("a", "b"):
        os.makedirs(tmp_path / name)
        write_elastic(str(tmp_path / name / "elastic.h5"), coords, stress, volume, 1e-3)
    out = tmp_path / "maps.png"
    done = run_script("plot_stress.py", "--maps", str(out), str(tmp_path / "a"), str(tmp_path / "b"))
    assert done.returncode == 0, done.stderr
    assert done.stdout == "wrote %s (2 maps)\n" % out
    assert os.listdir(tmp_path / "a") == ["elastic.h5"]
    done = run_script("plot_stress.py", str(tmp_path / "a"), str(tmp_path / "b"))
    assert done.returncode == 2 and "one RESULTS_DIR, or several with --maps" in done.stderr


def test_study_command_line(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("name: t\nranks: 1\nmatrix_fractions: [0.13]\nsigma_pm_ratios: [0.6]\n")
    done = run_script("study.py", "plan", str(path), str(tmp_path / "out"))
    assert done.returncode == 0, done.stderr
    assert "1 samples x 1 sigma^pm = 1 runs" in done.stdout
    assert os.path.exists(tmp_path / "out" / "study.json")
    done = run_script("study.py", "plan", str(path), str(tmp_path / "out"), "--ranks", "0")
    assert done.returncode == 1
    assert done.stderr == "study.py: error: --ranks 0 is not a positive integer\n"
    for ranks in ("1000001", "100000000000000000000"):
        done = run_script("study.py", "plan", str(path), str(tmp_path / "out"), "--ranks", ranks)
        assert done.returncode == 1
        assert done.stderr == ("study.py: error: --ranks %s is not a positive integer up to "
                               "1000000\n" % ranks)
    absurd = tmp_path / "absurd.yaml"
    absurd.write_text(path.read_text().replace("ranks: 1", "ranks: 100000000000000000000"))
    done = run_script("study.py", "plan", str(absurd), str(tmp_path / "absurd"))
    assert done.returncode == 1
    assert done.stderr == ("study.py: error: study file %s: ranks must be a positive integer up "
                           "to 1000000, not 100000000000000000000\n" % absurd)
    assert not os.path.exists(tmp_path / "absurd")
    done = run_script("study.py", "plan", str(path), str(tmp_path / "out"), "--ranks", "true")
    assert done.returncode == 2 and "invalid int value: 'true'" in done.stderr
    done = run_script("study.py", "plans", str(path), str(tmp_path / "out"))
    assert done.returncode == 2 and "invalid choice: 'plans'" in done.stderr
    done = run_script("study.py", "status", str(path), str(tmp_path / "out"))
    assert done.returncode == 1 and "0 complete, 0 failed, 1 pending" in done.stdout


@pytest.mark.parametrize("script, args, what", [
    ("combine_studies.py", ["OUT", "STUDY"], "the output folder"),
    ("increment_table.py", ["DATA", "--out", "OUT"], "the output folder (--out)"),
    ("scaling.py", ["run", "SAMPLE", "OUT", "--ranks", "1"], "the output folder"),
])
def test_an_output_folder_that_is_a_file_is_named(script, args, what, tmp_path):
    """Not os.makedirs' "[Errno 17] File exists" (or "[Errno 20] Not a
    directory" below it): the folder named, the user's file left alone."""
    out = tmp_path / "out"
    out.write_text("a file of the user's\n")
    (tmp_path / "sample.h5").write_text("")
    paths = {"STUDY": str(tmp_path), "DATA": str(tmp_path), "SAMPLE": str(tmp_path / "sample.h5")}
    for target, named in ((out, str(out)), (out / "sub", "%s: %s" % (out / "sub", out))):
        done = run_script(script, *[str(target) if a == "OUT" else paths.get(a, a) for a in args])
        assert done.returncode == 1
        assert done.stderr == ("%s: error: %s %s is a file, not a folder: choose another path\n"
                               % (script, what, named))
    assert out.read_text() == "a file of the user's\n"


def package_imports():
    """{module: modules of lem_tools it imports}, read from the source."""
    graph = {}
    for path in glob.glob(os.path.join(PACKAGE, "*.py")):
        name = os.path.splitext(os.path.basename(path))[0]
        with open(path) as f:
            tree = ast.parse(f.read())
        found = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.level == 1:
                found |= {node.module} if node.module else {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and \
                    node.module.startswith("lem_tools"):
                found.add(node.module.partition(".")[2] or node.names[0].name)
        graph[name] = found
    return graph


def test_no_import_circle():
    graph = package_imports()
    assert "study" in graph and "study_table" in graph["study"]
    done, visiting = set(), []

    def visit(module):
        assert module not in visiting, "import circle: " + " -> ".join(visiting + [module])
        if module in done:
            return
        visiting.append(module)
        for imported in graph.get(module, ()):
            visit(imported)
        visiting.pop()
        done.add(module)
    for module in graph:
        visit(module)


def test_analysis_reading_and_study_steps_do_not_load_matplotlib():
    code = ("import sys; import lem_tools.analysis, lem_tools.results, lem_tools.files, "
            "lem_tools.study; print('matplotlib' in sys.modules)")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=dict(os.environ, PYTHONPATH=TOOLS), timeout=60)
    assert done.stdout.strip() == "False", done.stderr


def test_no_sys_path_edits():
    for path in SCRIPTS + glob.glob(os.path.join(PACKAGE, "*.py")):
        with open(path) as f:
            assert "sys.path" not in f.read(), path


def test_phase_names_follow_the_cpp_enum():
    headers = glob.glob(os.path.join(ROOT, "include", "**", "*.hpp"), recursive=True)
    for header in headers:
        with open(header) as f:
            match = re.search(r"enum class Phase\b[^{]*\{([^}]*)\}", f.read())
        if match:
            break
    else:
        pytest.fail("enum class Phase not found under include/: update this test and phases.py")
    order = [re.match(r"\s*(\w+)\s*=\s*(\d+)", e).groups() for e in match.group(1).split(",")]
    assert tuple(name for name, _ in sorted(order, key=lambda e: int(e[1]))) == phases.PHASES


def test_plot_fracture_refuses_an_unfinished_run(fracture_dir):
    os.remove(os.path.join(fracture_dir, "manifest.txt"))
    done = run_script("plot_fracture.py", fracture_dir)
    assert done.returncode == 1
    assert "holds no finished result (no manifest.txt" in done.stderr
    assert not os.path.exists(os.path.join(fracture_dir, "fracture.png"))


BENCH_LOG = """lattice: 2962 nodes, 21000 bonds (15000 active), {n} ranks, set up in parallel (cells), edge cut {cut}
balance:  owned nodes max/mean {balance}, bonds held max/mean 1.020; set-up 0.12 s
peak RSS MB: max 90; per rank after set-up [{rss}], at end [{rss}]
# MESSAGES columns: ranks,bonds,messages_mean,messages_max,bytes_mean,bytes_max,reductions (per CG iteration and rank)
MESSAGES,{n},21000,{msgs},{msgs},4000,4100,3.00
# BENCH columns: ranks,bonds,nodes,gen_s,partition_s,distribute_s,assembly_s,pcsetup_s,solve_s,its,mem_max_MB,stream_GBs,constraints_s,morton,pcsetup_rep_s,solve_rep_s,its_rep,ms_per_it,matmult_ms,matmult_MB,matmult_GBs,it_in_matmults,stream_fraction_matmult
BENCH,{n},21000,2962,0.1,0.01,0.01,0.002,0.05,0.1,30,90,20,0.01,1,0.04,0.09,31,{ms},0.1,1,10,4,0.5
"""


def test_scaling_table_from_bench_logs(tmp_path):
    (tmp_path / "np1.log").write_text(BENCH_LOG.format(n=1, cut=0, balance="1.000", rss="80",
                                                       msgs="0.00", ms="4.000"))
    (tmp_path / "np2.log").write_text(BENCH_LOG.format(n=2, cut=900, balance="1.040",
                                                       rss="50, 46", msgs="14.00", ms="2.500"))
    done = run_script("scaling.py", "table", str(tmp_path))
    assert done.returncode == 0, done.stderr
    rows = (tmp_path / "scaling.csv").read_text().splitlines()
    assert rows[0].startswith("ranks,bonds,setup_s")
    two = dict(zip(rows[0].split(","), rows[2].split(",")))
    # 4 ms on 1 rank, 2.5 ms on 2: speed-up 1.6, efficiency 0.8.
    assert float(two["speedup"]) == pytest.approx(1.6)
    assert float(two["efficiency"]) == pytest.approx(0.8)
    assert float(two["memory_max_mb"]) == 50 and float(two["memory_mean_mb"]) == 48
    assert two["edge_cut"] == "900" and float(two["messages"]) == 14
    assert done.stdout.count("\n") == 4  # header, rule, two rows
    # lem_bench's options pass as one word (they start with a dash).
    done = run_script("scaling.py", "run", str(tmp_path / "none.h5"), str(tmp_path), "--ranks", "2",
                      "--bench=-bench_repeat 1")
    assert done.returncode == 1 and "none.h5 does not exist" in done.stderr, done.stderr
    (tmp_path / "np4.log").write_text("lattice: 2962 nodes\n")  # a run that failed
    done = run_script("scaling.py", "table", str(tmp_path))
    assert done.returncode == 1 and "np4.log is not a complete lem_bench log" in done.stderr
