"""The tools name the files of a result folder as the programs write them:
every name of lem_tools.results is in the C++ ResultLayout of its program
(src/run/result_folder.cpp), and every plot the tools draw into a result
folder is one its layout counts as the result's (so -output_overwrite and a
new run take it away with the old result)."""
import os
import re

from lem_tools import results

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def layout_names(function):
    """The quoted names in the body of `function` of result_folder.cpp."""
    with open(os.path.join(ROOT, "src", "run", "result_folder.cpp")) as f:
        text = f.read()
    match = re.search(r"const ResultLayout& %s\(\) \{(.*?)\n\}" % function, text, re.S)
    assert match, "no %s() in src/run/result_folder.cpp" % function
    return set(re.findall(r'"([^"]+)"', match.group(1)))


def test_fracture_files_named_alike():
    names = layout_names("fracture_layout")
    for name in (results.CURVE, results.BROKEN, results.SUMMARY, results.FRACTURE_PLOT,
                 results.STRESS_PLOT, results.STRESS_FIT):
        assert name in names, name
    assert results.ELASTIC.split(".")[0] in names  # the family of elastic.h5
    for plot in (results.FRACTURE_PLOT, results.STRESS_PLOT):  # drawn with a PDF beside
        assert plot.replace(".png", ".pdf") in names, plot


def test_other_programs_plots_belong_to_their_result():
    assert "tension.png" in layout_names("tension_layout")
    assert {"stiffness.png", "interface.png"} <= layout_names("stiffness_layout")
    assert "convergence.png" in layout_names("convergence_layout")


def test_manifest_named_alike():
    with open(os.path.join(ROOT, "src", "base", "files.cpp")) as f:
        assert 'kManifestName[] = "%s"' % results.MANIFEST in f.read()
