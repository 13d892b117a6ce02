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
import os
import socket
import zlib

import numpy as np

from .analysis import node_stress_statistics, stress_pdf
from .errors import ToolError
from .files import atomic_open, write_json
from .results import (CURVE, ELASTIC, ResultsError, read_curve, read_elastic, read_json)

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
        if not all(isinstance(data.get(k), (int, float)) for k in ("sigma_hom", "E_hom")):
            raise DataError("%s: sigma_hom and E_hom must be numbers" % path)
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

    def rows(self):
        """Every kept run's data (runs/*.json as written), in name order."""
        folder = os.path.join(self.path, "runs")
        if not os.path.isdir(folder):
            return []
        out = []
        for name in sorted(os.listdir(folder)):
            if not name.endswith(".json"):
                continue
            path = os.path.join(folder, name)
            data = read_json(path)
            if data.get("format") != FORMAT or data.get("version") != VERSION:
                raise DataError("%s is not a study row of version %d (format %r, version %r)"
                                % (path, VERSION, data.get("format"), data.get("version")))
            out.append(data)
        return out


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
