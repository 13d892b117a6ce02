"""Small result folders written the way lem's drivers write them, and the
rows of a documentation table."""
import json
import os
import re
import zlib

import numpy as np
import pytest

# Under CI=true a skip is a failure (ci_skips.py).
pytest_plugins = ["ci_skips"]

TOOLS = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", "tools"))

CURVE_HEADER = ("step,strain,displacement_over_a,stress_before_norm,stress_norm,stress,broken,"
                "broken_p,broken_m,broken_pp,broken_pm,n_b,cycles")


def write_curve(path, rows):
    """rows: (strain, stress_before_norm, stress_norm, broken_p, broken_m, broken_pp,
    broken_pm) per step; the other columns follow from them."""
    lines = [CURVE_HEADER]
    for step, (strain, before, after, bp, bm, bpp, bpm) in enumerate(rows, 1):
        broken = bp + bm + bpp + bpm
        n_b = bp / broken if broken else 0.0
        lines.append(",".join(str(v) for v in (step, strain, strain * 10, before, after,
                                               after * 0.02, broken, bp, bm, bpp, bpm, n_b, 1)))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def write_fracture_results(directory, summary_extra=None):
    """A complete small lem_fracture output folder: curve.csv, broken.csv, summary.json."""
    os.makedirs(directory, exist_ok=True)
    write_curve(os.path.join(directory, "curve.csv"), [
        (1e-4, 0.05, 0.05, 0, 0, 3, 0),
        (2e-4, 0.10, 0.08, 1, 1, 3, 1),
        (3e-4, 0.09, 0.02, 2, 3, 3, 4),
    ])
    with open(os.path.join(directory, "broken.csv"), "w") as f:
        f.write("step,cycle,strain,bond_id,phase,x,y,z,force,threshold\n")
        rows = [("pp", 0.0), ("pp", 0.0), ("pp", 0.0), ("p", 0.1), ("m", 0.1), ("pm", 0.05),
                ("p", 0.1), ("m", 0.1), ("m", 0.1), ("pm", 0.05), ("pm", 0.05), ("pm", 0.05)]
        for i, (phase, threshold) in enumerate(rows):
            f.write("1,0,1e-4,%d,%s,%g,%g,%g,1e-6,%g\n"
                    % (i, phase, 0.1 * i, 0.2 * (i % 3), 0.05 * i, threshold))
    summary = {"sample_file": "meshes/test.h5", "E_eff_over_E_unit": 0.5,
               "sigma_eff_over_sigma_unit": 0.1, "strain_at_peak": 2e-4, "broken": 12,
               "broken_p": 2, "broken_m": 3, "broken_pp": 3, "broken_pm": 4, "n_b": 2 / 12,
               "steps": 3, "solves": 4, "energy_balance_error": 1e-7,
               "end_reason": "stress below the stop fraction of the peak"}
    summary.update(summary_extra or {})
    with open(os.path.join(directory, "summary.json"), "w") as f:
        json.dump(summary, f)
    write_manifest(directory, ("curve.csv", "broken.csv", "summary.json"))
    return directory


def write_manifest(directory, names, checksums=True):
    """The manifest lem_fracture writes last, listing `names` with their sizes
    and (unless `checksums` is false, as before checksums) their checksums."""
    with open(os.path.join(directory, "manifest.txt"), "w") as f:
        f.write("program=lem_fracture\n")
        for name in names:
            f.write("file=%s %d\n" % (name, os.path.getsize(os.path.join(directory, name))))
        for name in names if checksums else ():
            with open(os.path.join(directory, name), "rb") as g:
                f.write("checksum=%s crc32:%08x\n" % (name, zlib.crc32(g.read())))
        f.write("fingerprint ranks=1\nend\n")


def write_elastic(path, coords, stress, volume, applied, strain=1e-5):
    import h5py

    with h5py.File(path, "w") as f:
        f["nodes/coordinates"] = np.asarray(coords, dtype=float)
        if stress is not None:
            f["nodes/stress"] = np.asarray(stress, dtype=float)
        f["nodes/volume"] = np.asarray(volume, dtype=float)
        f.attrs["applied_stress"] = applied
        f.attrs["strain"] = strain


def cube_lattice(n):
    """Nodes of an n x n x n grid in the unit cube with equal volumes (their
    sum is the box volume)."""
    axis = np.linspace(0.0, 1.0, n)
    coords = np.array(np.meshgrid(axis, axis, axis, indexing="ij")).reshape(3, -1).T
    return coords, np.full(len(coords), 1.0 / len(coords))


def markdown_table(path, first_heading):
    """The body rows of the Markdown table in `path` whose heading row starts
    with the cell `first_heading`, each a list of its cells, stripped (a `\\|`
    inside a cell stays part of it)."""
    rows, inside = [], False
    with open(path, encoding="utf-8") as f:
        for line in f:
            line = line.strip()
            cells = [c.strip() for c in re.split(r"(?<!\\)\|", line.strip("|"))]
            if not inside:
                inside = line.startswith("|") and cells[0] == first_heading
            elif not line.startswith("|"):
                break
            elif not set(line) <= set("|-: "):
                rows.append(cells)
    assert inside, "%s: no table headed %r" % (path, first_heading)
    return rows


def write_study_file(tmp_path, text, name):
    """`text` written to tmp_path/name; the path as a string."""
    path = tmp_path / name
    path.write_text(text)
    return str(path)


@pytest.fixture
def fracture_dir(tmp_path):
    return write_fracture_results(str(tmp_path / "run"))

