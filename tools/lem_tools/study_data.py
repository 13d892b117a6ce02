"""A study's results kept as data: one small JSON file per run in a folder
that can be committed (docs/data/<study>/), from which the figures redraw
and which a study resumed elsewhere reads to run only what it lacks.

Layout of a data folder:
  study.json                 the study as read, with its hash (study.study_hash)
  calibration/<lattice>.json sigma^[p] and E^[p] of each lattice ("default"
                             for a study without axes), so that rows added
                             later share the units of the first ones
  runs/<id>.json             one run: its grid point, its results.csv row,
                             the lem_fracture options it ran with, its sample
                             (stem, content checksum, bonds, S^pm/S^p ...),
                             the curve thinned to what figs. 3 and 13 need
                             and the node-stress pdf of fig. 8

The sample checksum is a CRC-32 of the sample file's datasets (not of the
file: HDF5 keeps timestamps and lem_sample its timings in attributes), so
the same options give the same checksum on any machine with the same build.
"""
import json
import math
import os
import socket
import zlib

import numpy as np

from .analysis import node_stress_statistics, stress_pdf
from .errors import ToolError
from .files import atomic_open, write_json
from .results import (CURVE, ELASTIC, STUDY_COLUMNS, ResultsError, read_curve, read_elastic,
                      read_json)
from .study_axes import is_number

FORMAT = "lem3d study data"
VERSION = 1
# Columns of the thinned curve: strain, the stress before and after each
# step's avalanche (in sigma^[p]), the broken bonds and n_b.
CURVE_KEEP = ("strain", "stress_before_norm", "stress_norm", "broken", "n_b")
# Thinning: a point is kept once the strain has moved 1/THIN_STRAIN of its
# range or a stress or n_b 1/THIN_VALUE of its range since the last kept one.
THIN_STRAIN = 250
THIN_VALUE = 100
DIGITS = 6  # significant digits of the stored numbers
# What the runs take from a lattice's calibration: the units of stress and modulus.
CALIBRATION_KEEP = ("sigma_hom", "E_hom")
# The sections of a row that the figures and tables read, and the columns
# of its results.csv row that are texts (the others are numbers or null).
ROW_SECTIONS = ("run", "row", "sample", "curve")
TEXT_COLUMNS = ("id", "end_reason")
# Sample summary keys kept with each row (fig. 11 and the figures' subtitle).
SAMPLE_KEEP = ("sample_particles", "particles", "side", "nodes", "bonds", "rho_m", "rho_p",
               "rho_v", "interface_ratio_Spm_Sp", "bridges_per_particle", "packing_seed",
               "lattice_seed", "void_bonds")


class DataError(ToolError):
    pass


def rounded(value):
    """`value` (a number or nested lists of them) to DIGITS significant digits."""
    if isinstance(value, (list, tuple, np.ndarray)):
        return [rounded(v) for v in value]
    if isinstance(value, (bool, str, int, np.integer)) or value is None:
        return value if not isinstance(value, np.integer) else int(value)
    value = float(value)
    if not np.isfinite(value):
        return None  # JSON has no NaN
    return float("%.*g" % (DIGITS, value))


def thin_curve(curve):
    """Indices of the curve's steps to keep: the first, the last, the peak and
    every step where the strain, a stress or n_b has moved enough since the
    last one kept (abrupt falls are kept whole, the smooth rise sampled)."""
    strain = curve["strain"]
    n = len(strain)
    if n <= 2:
        return list(range(n))
    scales = [(strain, (strain.max() - strain.min()) / THIN_STRAIN)]
    for name in ("stress_before_norm", "stress_norm", "n_b"):
        v = curve[name]
        scales.append((v, max(v.max() - v.min(), 1e-12) / THIN_VALUE))
    keep, last = [0], 0
    for i in range(1, n - 1):
        if any(abs(v[i] - v[last]) >= step for v, step in scales):
            keep.append(i)
            last = i
    peaks = {int(np.argmax(curve["stress_before_norm"])), int(np.argmax(curve["stress_norm"]))}
    return sorted(set(keep) | peaks | {n - 1})


def sample_checksum(path):
    """"crc32:<hex>" over the datasets of an HDF5 sample file (names, types,
    shapes and values, in name order)."""
    import h5py

    crc, found = 0, []
    try:
        with h5py.File(path, "r") as f:
            f.visititems(lambda name, obj: found.append(name)
                         if isinstance(obj, h5py.Dataset) else None)
            for name in sorted(found):
                data = np.ascontiguousarray(f[name][()])
                crc = zlib.crc32(("%s %s %s" % (name, data.dtype.str, data.shape)).encode(), crc)
                crc = zlib.crc32(data.tobytes(), crc)
    except OSError as e:
        raise DataError("cannot read the sample %s: %s" % (path, e)) from None
    return "crc32:%08x" % crc


def is_flat_list(value):
    """A list of numbers or texts (no list or mapping in it)."""
    return isinstance(value, list) and all(
        v is None or isinstance(v, (int, float, str)) for v in value)


def data_text(data):
    """`data` as indented JSON with each flat list on one line (a curve row, a
    histogram, the options), which keeps a row file small and readable."""
    lists = {}

    def mark(value):
        if is_flat_list(value):
            key = "@%d@" % len(lists)
            lists[key] = json.dumps(value, separators=(",", ":"))
            return key
        if isinstance(value, dict):
            return {k: mark(v) for k, v in value.items()}
        if isinstance(value, list):
            return [mark(v) for v in value]
        return value
    text = json.dumps(mark(data), indent=1)
    for key, compact in lists.items():
        text = text.replace('"%s"' % key, compact, 1)
    return text + "\n"


def lattice_name(tag):
    return tag or "default"


class DataFolder:
    """The data folder `path` of a study (study.Study) or, without one, as read."""

    def __init__(self, path, study=None):
        self.path = path
        self.study = study

    def run_path(self, run_id):
        return os.path.join(self.path, "runs", run_id + ".json")

    def calibration_path(self, tag):
        return os.path.join(self.path, "calibration", lattice_name(tag) + ".json")

    # --- writing (with a study) ----------------------------------------------
    def claim(self):
        """Create the folder for `study`, or check that it holds its results."""
        record = os.path.join(self.path, "study.json")
        if os.path.exists(record):
            old = read_json(record)
            if old.get("hash") != self.study.hash:
                raise DataError("%s holds the data of a different study (%s, hash %s; this one "
                                "is %s, hash %s): use another data folder"
                                % (self.path, old.get("name"), old.get("hash"),
                                   self.study.spec["name"], self.study.hash))
            return
        os.makedirs(self.path, exist_ok=True)
        write_json(record, dict(self.study.spec, hash=self.study.hash))

    def write_calibration(self, tag, calibration):
        path = self.calibration_path(tag)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        write_json(path, {k: calibration[k] for k in CALIBRATION_KEEP
                                if calibration.get(k) is not None})

    def calibration(self, tag):
        """The calibration of lattice `tag` kept here, or None."""
        path = self.calibration_path(tag)
        if not os.path.exists(path):
            return None
        data = read_json(path)
        for key in CALIBRATION_KEEP:
            if not (is_number(data.get(key)) and data[key] > 0):
                raise DataError("%s: %s must be a number > 0, not %r" % (path, key, data.get(key)))
        return data

    def has_row(self, run):
        """Whether the row of `run` is kept here, for this study."""
        try:
            data = read_json(self.run_path(run["id"]))
        except ResultsError:
            return False
        return data.get("study_hash") == self.study.hash and data.get("run") == run

    def write_row(self, run, row, options, run_dir, sample_file, calibration):
        """runs/<id>.json of a complete run: `row` (study_table.run_row),
        the lem_fracture `options` (list of words, paths left out), its
        folder `run_dir` (curve.csv, elastic.h5) and sample."""
        curve = read_curve(os.path.join(run_dir, CURVE))
        keep = thin_curve(curve)
        summary_path = os.path.splitext(sample_file)[0] + "_summary.json"
        sample = read_json(summary_path) if os.path.exists(summary_path) else {}
        data = {
            "format": FORMAT, "version": VERSION, "study": self.study.spec["name"],
            "study_hash": self.study.hash, "run": run,
            "row": {k: rounded(v) if not isinstance(v, str) else v for k, v in row.items()},
            "options": list(options),
            "calibration": {k: calibration[k] for k in CALIBRATION_KEEP
                                if calibration.get(k) is not None},
            "sample": dict({k: sample[k] for k in SAMPLE_KEEP if k in sample},
                           stem=os.path.splitext(os.path.basename(sample_file))[0],
                           checksum=sample_checksum(sample_file)),
            "curve": {"columns": list(CURVE_KEEP), "steps": len(curve["strain"]),
                      "rows": [rounded([curve[c][i] for c in CURVE_KEEP]) for i in keep]},
            "stress_pdf": node_stress_pdf(run_dir),
            "host": socket.gethostname(),
        }
        os.makedirs(os.path.dirname(self.run_path(run["id"])), exist_ok=True)
        with atomic_open(self.run_path(run["id"])) as f:
            f.write(data_text(data))
        return data

    def remove_row(self, run_id):
        path = self.run_path(run_id)
        if os.path.exists(path):
            os.remove(path)

    # --- reading --------------------------------------------------------------
    def spec(self):
        return read_json(os.path.join(self.path, "study.json"))

    def owner(self):
        """(name, hash) of the study whose rows this folder keeps."""
        if self.study is not None:
            return self.study.spec["name"], self.study.hash
        spec = self.spec()
        return spec.get("name"), spec.get("hash")

    def row(self, run_id, owner=None):
        """The data of runs/<run_id>.json, checked (check_row) against the
        study `owner` (default: this folder's)."""
        path = self.run_path(run_id)
        data = read_json(path)
        check_row(path, data, owner or self.owner())
        return data

    def rows(self):
        """Every kept run's data (runs/*.json as written, each checked), in
        name order."""
        folder = os.path.join(self.path, "runs")
        if not os.path.isdir(folder):
            return []
        owner = self.owner()
        return [self.row(os.path.splitext(name)[0], owner)
                for name in sorted(os.listdir(folder)) if name.endswith(".json")]


def check_row(path, data, owner):
    """Raise DataError naming `path` unless `data` is a row of the study
    `owner` ((name, hash)), of the run its file name says, with every
    section the figures and tables read and no NaN or infinity in it."""
    if data.get("format") != FORMAT or data.get("version") != VERSION:
        raise DataError("%s is not a study row of version %d (format %r, version %r)"
                        % (path, VERSION, data.get("format"), data.get("version")))
    if (data.get("study"), data.get("study_hash")) != tuple(owner):
        raise DataError("%s is a row of study %s (hash %s), not of %s (hash %s) whose data "
                        "folder holds it: move it to its own study's data folder"
                        % ((path, data.get("study"), data.get("study_hash")) + tuple(owner)))
    problem = row_problem(data, os.path.splitext(os.path.basename(path))[0])
    if problem:
        raise DataError("%s: %s" % (path, problem))


def row_problem(data, run_id):
    """What is wrong with the sections of the data of the row of `run_id`, or None."""
    missing = [s for s in ROW_SECTIONS if not isinstance(data.get(s), dict)]
    if missing:
        return "no %s section" % missing[0]
    if data["run"].get("id") != run_id:
        return "holds the run %s, not %s (its file name)" % (data["run"].get("id"), run_id)
    found = non_finite(data)
    if found:
        return "%s is %r: a kept value must be a finite number or null" % found
    for key in ("rho_m", "sigma_pm_ratio"):
        if not is_number(data["run"].get(key)):
            return "run.%s is %r, not a number" % (key, data["run"].get(key))
    row = data["row"]
    for column in STUDY_COLUMNS:
        if column not in row:
            return "row has no %s" % column
        if column not in TEXT_COLUMNS and not (row[column] is None or is_number(row[column])):
            return "row.%s is %r, not a number or null" % (column, row[column])
    return curve_problem(data["curve"]) or pdf_problem(data.get("stress_pdf"))


def non_finite(value, where=""):
    """(field, value) of the first NaN or infinity in `value` (nested
    mappings and lists), the field named as in `section.key[index]`."""
    if isinstance(value, float) and not math.isfinite(value):
        return where, value
    if isinstance(value, dict):
        items = (("%s.%s" % (where, k) if where else k, v) for k, v in value.items())
    elif isinstance(value, list):
        items = (("%s[%d]" % (where, i), v) for i, v in enumerate(value))
    else:
        return None
    return next(filter(None, (non_finite(v, field) for field, v in items)), None)


def numbers(value):
    """A non-empty list of finite numbers."""
    return isinstance(value, list) and bool(value) and all(map(is_number, value))


def curve_problem(curve):
    """What is wrong with a row's thinned curve, or None."""
    columns, rows = curve.get("columns"), curve.get("rows")
    lacking = [c for c in CURVE_KEEP if not isinstance(columns, list) or c not in columns]
    if lacking:
        return "curve.columns lacks %s" % lacking[0]
    if not isinstance(rows, list) or not rows:
        return "curve.rows is empty: no step of the curve is kept"
    for i, step in enumerate(rows):
        if not (numbers(step) and len(step) == len(columns)):
            return "curve.rows[%d] is not %d numbers: %r" % (i, len(columns), step)
    return None


def pdf_problem(pdf):
    """What is wrong with a row's node-stress pdf (null without elastic.h5), or None."""
    if pdf is None:
        return None
    if not (isinstance(pdf, dict) and numbers(pdf.get("edges")) and numbers(pdf.get("inside"))
            and len(pdf["edges"]) == len(pdf["inside"]) + 1):
        return "stress_pdf has no edges and inside (n + 1 and n numbers)"
    if pdf.get("beta") is not None and not all(
            is_number(pdf.get(k)) for k in ("beta", "tail_start", "tail_share")):
        return "stress_pdf has a beta without the numbers tail_start and tail_share"
    return None


def open_data_folder(folder):
    """(DataFolder, its study as kept) of the data folder `folder`."""
    if not os.path.isfile(os.path.join(folder, "study.json")):
        raise DataError("%s is not a study data folder (no study.json)" % folder)
    data = DataFolder(folder)
    return data, data.spec()


def node_stress_pdf(run_dir):
    """The pdf of s = sigma_zz^i / sigma_zz at the first equilibrium
    (elastic.h5), split into the nodes inside the box and on its faces as
    tools/plot_stress.py draws it, with beta off the faces; None without
    elastic.h5 (a run made with -output_fields false)."""
    path = os.path.join(run_dir, ELASTIC)
    if not os.path.exists(path):
        return None
    statistics, s, _, on_face = node_stress_statistics(read_elastic(path))
    edges, inside, faces = stress_pdf(s, on_face)
    tail = statistics["tail"]
    return {"edges": rounded(edges), "inside": rounded(inside), "faces": rounded(faces),
            "loaded_nodes": int(s.size), "beta": rounded(tail["beta"]) if tail else None,
            "tail_start": tail["tail_start"] if tail else None,
            # the tail's share of the loaded nodes, which scales its density
            "tail_share": rounded(np.sum(s[~on_face] > tail["tail_start"]) / s.size)
            if tail else None}


def curve_of(data):
    """The thinned curve of a run's data as {column: array}."""
    rows = np.array(data["curve"]["rows"], dtype=float).reshape(-1, len(data["curve"]["columns"]))
    return {c: rows[:, i] for i, c in enumerate(data["curve"]["columns"])}
