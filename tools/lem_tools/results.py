"""The one reader of the files that lem's drivers and the study write.

A lem_fracture folder holds a finished result only if its manifest.txt
(written last, listing every result file and its size) is there and agrees
with the files: require_finished checks that before anything is read.

CSV tables (curve.csv, broken.csv, summary.csv, a study's results.csv, the
tables of lem_convergence and lem_stiffness) start with their header row;
'#' lines, which files of older versions start with, are skipped.  JSON files (summary.json, stress.json, run records) must hold an
object; HDF5 fields are read with h5py, imported only when needed.
Every problem is raised as ResultsError naming the file.
"""
import csv
import json
import math
import os
import re
import zlib

import numpy as np

from .errors import ToolError
from .phases import BREAKABLE, broken_column

CURVE_COLUMNS = ("strain", "stress_before_norm", "stress_norm", "broken",
                 *(broken_column(p) for p in BREAKABLE), "n_b")
BROKEN_COLUMNS = ("phase", "x", "y", "z", "threshold")
STUDY_COLUMNS = ("id", "rho_m", "sigma_pm_ratio", "E_eff_over_E_unit", "sigma_eff_over_sigma_unit",
                 "sigma_eff_over_sigma_pm", "strain_at_peak", "n_b", "n_b_without_bare_contacts",
                 "broken", *(broken_column(p) for p in BREAKABLE), "K_c_r_eq13",
                 "K_c_r_eq14", "beta", "end_reason", "solves", "seconds")


class ResultsError(ToolError):
    """A result file is missing or not what its writer makes."""


class Table:
    """A CSV table: its header and its rows, values kept as text until a
    column is asked for as numbers."""

    def __init__(self, path, header, rows):
        self.path, self.header, self.rows = path, header, rows

    def __len__(self):
        return len(self.rows)

    def text(self, name):
        i = self._index(name)
        return [row[i] for row in self.rows]

    def numbers(self, name):
        try:
            return np.array(self.text(name), dtype=float)
        except ValueError as e:
            raise ResultsError("cannot read %s: column %s: %s" % (self.path, name, e)) from None

    def records(self):
        """The rows as {column: text}."""
        return [dict(zip(self.header, row)) for row in self.rows]

    def records_by(self, key):
        """{value of column `key`: row as {column: text}}."""
        self._index(key)
        return {r[key]: r for r in self.records()}

    def _index(self, name):
        try:
            return self.header.index(name)
        except ValueError:
            raise ResultsError("cannot read %s: no column %s" % (self.path, name)) from None


def read_csv(path, required=(), need_rows=False):
    """The table in `path`; '#' lines and blank lines are skipped, every row
    must have as many fields as the header."""
    try:
        with open(path, newline="") as f:
            # comment lines become empty rows so that line_num stays the file's
            reader = csv.reader("\n" if line.startswith("#") else line for line in f)
            header = next((row for row in reader if row), None)
            if header is None:
                raise ValueError("no header line")
            header = [h.strip() for h in header]
            missing = [c for c in required if c not in header]
            if missing:
                raise ValueError("header lacks column(s) %s" % ", ".join(missing))
            rows = []
            for row in reader:
                if not row:
                    continue
                if len(row) != len(header):
                    raise ValueError("line %d has %d fields, the header has %d"
                                     % (reader.line_num, len(row), len(header)))
                rows.append(row)
    except FileNotFoundError:
        raise ResultsError("%s does not exist" % path) from None
    except (OSError, UnicodeDecodeError, csv.Error, ValueError) as e:
        raise ResultsError("cannot read %s: %s" % (path, e)) from None
    if need_rows and not rows:
        raise ResultsError("cannot read %s: no data row" % path)
    return Table(path, header, rows)


def read_json(path):
    """The JSON object in `path`."""
    try:
        with open(path) as f:
            data = json.load(f)
    except FileNotFoundError:
        raise ResultsError("%s does not exist" % path) from None
    except (OSError, UnicodeDecodeError, ValueError) as e:
        raise ResultsError("cannot read %s: %s" % (path, e)) from None
    if not isinstance(data, dict):
        raise ResultsError("cannot read %s: not a JSON object" % path)
    return data


def scalar(text):
    """A CSV field as int, float or, failing both, text."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


# The files of a result folder that the tools read or draw, named as the
# programs write them (ResultLayout in src/run/result_folder.cpp; the test
# tests/python/test_result_names.py keeps the two in step).
MANIFEST = "manifest.txt"
CURVE = "curve.csv"
BROKEN = "broken.csv"
SUMMARY = "summary.json"
ELASTIC = "elastic.h5"
FRACTURE_PLOT = "fracture.png"
STRESS_PLOT = "stress.png"
STRESS_FIT = "stress.json"


def read_manifest(directory):
    """{file name: size} committed by the manifest of `directory`, or None if
    it has none (the run did not finish)."""
    path = os.path.join(directory, MANIFEST)
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except FileNotFoundError:
        return None
    except (OSError, UnicodeDecodeError) as e:
        raise ResultsError("cannot read %s: %s" % (path, e)) from None
    files = {}
    for line in lines:
        if line.startswith("file="):
            name, _, size = line[len("file="):].rpartition(" ")
            if not name or not size.isdigit():
                raise ResultsError("cannot read %s: bad line %r" % (path, line))
            files[name] = int(size)
    if "end" not in lines:
        raise ResultsError("cannot read %s: no end line (damaged)" % path)
    return files


def read_manifest_checksums(directory):
    """{file name: "crc32:<hex>"} of the manifest of `directory` (empty for a
    manifest written before checksums, or none)."""
    sums = {}
    try:
        with open(os.path.join(directory, MANIFEST)) as f:
            for line in f:
                if line.startswith("checksum="):
                    name, _, value = line[len("checksum="):].strip().rpartition(" ")
                    sums[name] = value
    except (OSError, UnicodeDecodeError):
        pass  # read_manifest reports it
    return sums


def file_checksum(path):
    """"crc32:<8 hex digits>" of the file's content, as lem_fracture writes it."""
    crc = 0
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            crc = zlib.crc32(block, crc)
    return "crc32:%08x" % crc


def finished_problem(directory):
    """Why `directory` holds no finished result, or None if it does."""
    files = read_manifest(directory)
    if files is None:
        return "%s holds no finished result (no %s: the run did not complete)" % (
            directory, MANIFEST)
    sums = read_manifest_checksums(directory)
    # Checksums are written for every file or (before they existed) for none:
    # one line missing would let a changed file pass.
    unsummed = [name for name in files if name not in sums]
    if sums and unsummed:
        return "%s is damaged: no checksum of %s, though it has those of the other files" % (
            os.path.join(directory, MANIFEST), unsummed[0])
    for name, size in files.items():
        path = os.path.join(directory, name)
        if not os.path.isfile(path):
            return "%s is missing (listed in %s)" % (path, MANIFEST)
        if os.path.getsize(path) != size:
            return "%s has %d bytes, %s says %d (changed since the run)" % (
                path, os.path.getsize(path), MANIFEST, size)
        if name in sums and file_checksum(path) != sums[name]:
            return "%s has other content than the run wrote (checksum %s, %s says %s)" % (
                path, file_checksum(path), MANIFEST, sums[name])
    return None


def require_finished(directory):
    """Raise ResultsError unless `directory` holds a finished result."""
    problem = finished_problem(directory)
    if problem:
        raise ResultsError(problem)


def read_summary(path):
    """A run's summary as {key: value}, from summary.json or summary.csv (whose
    one row is keyed by the header without its units, e.g. E_eff[stress])."""
    if not path.endswith(".csv"):
        return read_json(path)
    table = read_csv(path, need_rows=True)
    if len(table) != 1:
        raise ResultsError("cannot read %s: %d rows, expected one" % (path, len(table)))
    keys = [re.sub(r"\[.*\]$", "", h) for h in table.header]
    return {k: scalar(v) for k, v in zip(keys, table.rows[0])}


def finite_number(mapping, key):
    """mapping[key] as a float if it is a finite number, else None."""
    value = mapping.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return None
    return float(value) if math.isfinite(value) else None


def read_curve(path):
    """The stress-strain curve of lem_fracture as {column: array}."""
    table = read_csv(path, CURVE_COLUMNS, need_rows=True)
    return {name: table.numbers(name) for name in CURVE_COLUMNS}


def read_broken(path):
    """Broken bonds of lem_fracture: midpoints (n x 3), phase names, thresholds."""
    table = read_csv(path, BROKEN_COLUMNS)
    xyz = np.column_stack([table.numbers(c) for c in "xyz"])
    phase = np.array([p.strip() for p in table.text("phase")], dtype=object)
    return xyz, phase, table.numbers("threshold")


def read_stress_beta(path):
    """beta of stress.json (written by plot_stress.py); NaN when the file or
    its tail fit is missing."""
    if not os.path.exists(path):
        return float("nan")
    tail = read_json(path).get("tail")
    return tail["beta"] if tail else float("nan")


def read_study_results(path):
    """A study's results.csv (one row per complete run)."""
    return read_csv(path, STUDY_COLUMNS)


def read_hdf5(path, datasets, attributes=()):
    """{name: array} of the datasets and {name: value} of the root attributes."""
    import h5py  # only the commands that read fields need it

    if not os.path.isfile(path):
        raise ResultsError("%s does not exist" % path)
    try:
        with h5py.File(path, "r") as f:
            data = {name: f[name][:] for name in datasets}
            data.update({name: f.attrs[name] for name in attributes})
    except (OSError, KeyError, ValueError) as e:
        raise ResultsError("cannot read %s: %s" % (path, e)) from None
    return data


def hdf5_has(path, name):
    import h5py

    try:
        with h5py.File(path, "r") as f:
            return name in f
    except OSError as e:
        raise ResultsError("cannot read %s: %s" % (path, e)) from None


def read_elastic(path):
    """Node coordinates, Tensor6 stresses, Voronoi volumes and the applied
    stress and strain of elastic.h5 (lem_fracture's first equilibrium)."""
    if not os.path.isfile(path):
        raise ResultsError("%s not found (run lem_fracture with -output_fields true on a "
                           "sample file)" % path)
    if not hdf5_has(path, "nodes/stress"):
        raise ResultsError("%s has no node stresses (the lattice had no Voronoi volumes: "
                           "use a sample file)" % path)
    d = read_hdf5(path, ("nodes/coordinates", "nodes/stress", "nodes/volume"),
                  ("applied_stress", "strain"))
    elastic = {"coords": d["nodes/coordinates"], "stress": d["nodes/stress"],
               "volume": d["nodes/volume"], "applied": float(d["applied_stress"]),
               "strain": float(d["strain"])}
    if not elastic["applied"] > 0:
        raise ResultsError("%s: applied stress %g is not positive" % (path, elastic["applied"]))
    return elastic


REPO_ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def sample_path(summary, directory, given=None):
    """The sample file of the run: `given`, else summary.json's sample_file as
    written (absolute, or relative to where the run was started: this folder's
    parent, the current folder or the repository); None when none exists."""
    if given:
        if not os.path.exists(given):
            raise ResultsError(f"{given}: no such sample file")
        return given
    name = summary.get("sample_file")
    if not isinstance(name, str) or not name:
        return None
    if os.path.isabs(name):
        return name if os.path.exists(name) else None
    for base in (os.path.dirname(os.path.abspath(directory)), os.getcwd(), REPO_ROOT):
        if os.path.exists(os.path.join(base, name)):
            return os.path.join(base, name)
    return None
