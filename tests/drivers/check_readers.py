#!/usr/bin/python3
"""The result files open in the standard readers, as they are.

Usage: check_readers.py DIR [DIR ...]

In every DIR: each *.csv starts with its header row and reads the same
through csv.DictReader, numpy.genfromtxt(names=True) and, when installed,
pandas; each *.json summary or sidecar names the code version, git hash,
start time, rank count and the options (solver defaults included); each
single-grid *.xmf opens in meshio with its cells, and snapshots.xmf as a
temporal series whose times (strains) increase; each *.h5 carries the
provenance, stores phases and flags as integers and compresses its large
datasets.  Exit 1 with every problem listed.
"""
import csv
import glob
import json
import os
import sys

import h5py
import meshio
import numpy as np

problems = []


def check(condition, message):
    if not condition:
        problems.append(message)


def check_csv(path):
    with open(path, newline="") as f:
        first = f.readline()
    check(not first.startswith("#"), "%s starts with a comment line" % path)
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    names = first.strip().split(",")
    check(rows and list(rows[0]) == names, "%s: csv.DictReader finds no rows" % path)
    table = np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8")
    check(table.size == len(rows), "%s: numpy reads %d rows, csv %d" % (path, table.size, len(rows)))
    check(len(table.dtype.names) == len(names), "%s: numpy reads %d columns, the header has %d"
          % (path, len(table.dtype.names), len(names)))
    try:
        import pandas
    except ImportError:
        return
    frame = pandas.read_csv(path)
    check(frame.shape == (len(rows), len(names)), "%s: pandas reads %s" % (path, frame.shape))


def check_provenance(where, mapping, ranks_key):
    for key in ("version", "git_hash", "start_time", ranks_key):
        check(key in mapping, "%s has no %s" % (where, key))
    options = mapping.get("options")
    if isinstance(options, bytes):
        options = options.decode()
    text = "\n".join(options) if isinstance(options, list) else str(options)
    # The program's own defaults, given or not, and the solver's defaults
    # in the programs that solve.
    program = mapping.get("program", b"")
    program = program.decode() if isinstance(program, bytes) else program
    solver = program not in ("lem_sample", "lem_pack")
    for option in ("-output_dir",) + (("-ksp_type", "-pc_type") if solver else ()):
        check(option in text, "%s: the options lack %s" % (where, option))


def check_xdmf(path, h5, points="nodes/coordinates"):
    mesh = meshio.read(path)
    check(len(mesh.points) > 0, "%s: no points" % path)
    check(len(mesh.cells) == 1 and len(mesh.cells[0].data) > 0, "%s: no cells" % path)
    kind = mesh.cells[0].type
    check(kind in ("line", "vertex"), "%s: cells of type %s" % (path, kind))
    if kind == "vertex":
        check(len(mesh.cells[0].data) == len(mesh.points), "%s: not one vertex per point" % path)
    with h5py.File(h5, "r") as f:
        check(len(mesh.points) == f[points].shape[0],
              "%s: %d points, the HDF5 file %d" % (path, len(mesh.points), f[points].shape[0]))


def check_series(path):
    with meshio.xdmf.TimeSeriesReader(path) as reader:
        points, cells = reader.read_points_cells()
        check(len(points) > 0 and len(cells) == 1, "%s: no mesh" % path)
        times = [reader.read_data(k)[0] for k in range(reader.num_steps)]
    check(len(times) >= 2, "%s: %d snapshots" % (path, len(times)))
    check(all(a < b for a, b in zip(times, times[1:])), "%s: times %s do not increase"
          % (path, times))


def check_h5(path):
    with h5py.File(path, "r") as f:
        check_provenance(path, dict(f.attrs), "ranks")
        for group in ("nodes", "bonds"):
            for name, data in f[group].items():
                if name in ("phase", "dof_flags", "id", "vertices", "particle", "connectivity"):
                    check(data.dtype.kind in "iu", "%s: /%s/%s is %s, not an integer"
                          % (path, group, name, data.dtype))
                if data.size >= 4096:
                    check(data.compression == "gzip", "%s: /%s/%s (%d values) is not compressed"
                          % (path, group, name, data.size))


def main(directories):
    for d in directories:
        csvs = glob.glob(os.path.join(d, "**", "*.csv"), recursive=True)
        check(csvs, "%s: no CSV file" % d)
        for path in csvs:
            check_csv(path)
        for name in ("summary.json", "curve.json"):
            path = os.path.join(d, name)
            if os.path.exists(path):
                with open(path) as f:
                    check_provenance(path, json.load(f), "mpi_ranks")
        if glob.glob(os.path.join(d, "snapshot_*.h5")):
            check(os.path.exists(os.path.join(d, "snapshots.xmf")), "%s: no snapshots.xmf" % d)
        for path in glob.glob(os.path.join(d, "*.xmf")):
            if os.path.basename(path) == "snapshots.xmf":
                check_series(path)
                continue
            stem, points = path[:-len(".xmf")], "nodes/coordinates"
            if stem.endswith("_particles"):
                stem, points = stem[:-len("_particles")], "particles/centres"
            elif stem.endswith("_nodes"):
                stem = stem[:-len("_nodes")]
            check_xdmf(path, stem + ".h5", points)
        for path in glob.glob(os.path.join(d, "*.h5")):
            check_h5(path)
    for p in problems:
        print("FAIL:", p)
    if not problems:
        print("every result file of %s opens in csv, numpy, meshio and h5py"
              % ", ".join(directories))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
