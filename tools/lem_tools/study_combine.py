"""Convergence tables and figures over several gathered studies.

Reads results.csv, samples.csv and study.json of each STUDY_DIR (written by
`tools/study.py gather`) and writes in OUT_DIR what gather writes for one
study with a bond axis, over all their runs together:
  results.csv         every run, with the study it comes from (column study)
  samples.csv, convergence.csv, convergence_levels.csv, convergence.md
  figures/convergence_elastic, _strength, _damage (.png, .pdf)
  sources.json        the folders, their study names and hashes
A study of one size adds that size to the others' lines; a study of other
seeds at a size adds replicates there.  The studies must describe the same
physics: the same sample options, phases and fracture_* options (solver
and checkpoint options may differ).  A run (matrix fraction, sigma^pm, size,
pack and lattice seed) may come from one study only; a sample shared by
two studies (their samples are made from the same options) is counted once.
OUT_DIR may not be a study's folder (its own tables would be replaced).
"""
import math
import os

from . import cli
from .convergence_table import (RUN_AXIS_COLUMNS, SAMPLE_COLUMNS, optional_json,
                                write_convergence)
from .errors import ToolError
from .files import require_folder_path, write_json
from .results import STUDY_COLUMNS, read_csv, read_json, scalar
from .study_axes import BOND_AXES, bond_axis
from .study_table import write_table

RUN_KEY = ("rho_m", "sigma_pm_ratio", "level", "pack_seed", "lattice_seed")
SAMPLE_KEY = ("rho_m", "level", "pack_seed", "lattice_seed")


def read_gathered(folder):
    """(spec, run rows, sample rows) of a gathered study folder."""
    spec = read_json(os.path.join(folder, "study.json"))
    if bond_axis(spec)[0] is None:
        raise ToolError("%s: study %s has no bond axis (one of %s): nothing to combine in L_n"
                        % (folder, spec.get("name"), ", ".join(BOND_AXES)))
    tables = []
    for name, columns in (("results.csv", STUDY_COLUMNS + RUN_AXIS_COLUMNS),
                          ("samples.csv", SAMPLE_COLUMNS)):
        path = os.path.join(folder, name)
        if not os.path.exists(path):
            raise ToolError("%s does not exist: run tools/study.py gather on that study first"
                            % path)
        tables.append([{k: scalar(v) for k, v in r.items()}
                       for r in read_csv(path, columns, need_rows=True).records()])
    return spec, tables[0], tables[1]


def physics(spec):
    """The parts of a study file that change the numbers."""
    return {"sample": spec.get("sample", {}), "phases": spec.get("phases", {}),
            "fracture": {k: v for k, v in spec.get("fracture", {}).items()
                         if k.startswith("fracture_")},
            "bond axis": bond_axis(spec)[0]}


def same(a, b):
    return a == b or (isinstance(a, float) and isinstance(b, float)
                      and math.isnan(a) and math.isnan(b))


def key_text(row, key):
    return ", ".join("%s %s" % (k, row[k]) for k in key)


def combine(folders):
    """(spec, run rows, sample rows, sources) of the studies in `folders`."""
    first, runs, samples, sources = None, {}, {}, []
    for folder in folders:
        spec, run_rows, sample_rows = read_gathered(folder)
        if first is None:
            first, reference = spec, folder
        theirs = physics(spec)
        for part, wanted in physics(first).items():
            if theirs[part] != wanted:
                raise ToolError("%s and %s differ in their %s: %s against %s"
                                % (reference, folder, part, theirs[part], wanted))
        missing = optional_json(os.path.join(folder, "fit.json")).get("missing_runs", [])
        for run_id in missing:
            print("combine: %s: run %s was not complete when gathered: left out" % (folder, run_id))
        sources.append({"folder": folder, "study": spec.get("name"), "hash": spec.get("hash"),
                        "runs": len(run_rows), "missing_runs": missing})
        for row in run_rows:
            k = tuple(row[c] for c in RUN_KEY)
            if k in runs:
                raise ToolError("the run of %s is in %s and in %s: give each run once"
                                % (key_text(row, RUN_KEY), runs[k]["study"], folder))
            runs[k] = dict(row, study=folder)
        for row in sample_rows:
            k = tuple(row[c] for c in SAMPLE_KEY)
            if k in samples and not same(samples[k]["bonds"], row["bonds"]):
                raise ToolError("the sample of %s has %s bonds in one study and %s in %s"
                                % (key_text(row, SAMPLE_KEY), samples[k]["bonds"], row["bonds"],
                                   folder))
            samples.setdefault(k, row)
    axis = bond_axis(first)[0]
    spec = dict(first, name=" + ".join(s["study"] for s in sources))
    spec[axis] = sorted({k[2] for k in runs} | {k[1] for k in samples})
    return spec, list(runs.values()), list(samples.values()), sources


def write(out, folders):
    require_folder_path(out, "the output folder")
    if os.path.exists(os.path.join(out, "study.json")):
        # its results.csv and samples.csv would be replaced by the combined ones
        raise ToolError("%s is a study's folder: combine into a folder of its own" % out)
    spec, runs, samples, sources = combine(folders)
    os.makedirs(out, exist_ok=True)
    write_table(os.path.join(out, "results.csv"), runs,
                ("study",) + STUDY_COLUMNS + RUN_AXIS_COLUMNS)
    write_json(os.path.join(out, "sources.json"), {"studies": sources})
    points = write_convergence(out, spec, runs, samples, made_by="tools/combine_studies.py")
    fitted = sum(1 for p in points if isinstance(p["extrapolated"], float)
                 and math.isfinite(p["extrapolated"]))
    print("combine: %d runs and %d samples of %d studies -> %s: convergence.csv (%d of %d "
          "quantity x grid points extrapolated), convergence.md, figures/convergence_*.png"
          % (len(runs), len(samples), len(sources), out, fitted, len(points)))
    return 0


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("out", metavar="OUT_DIR", help="where the combined tables go")
    arg_parser.add_argument("folders", metavar="STUDY_DIR", nargs="+",
                            help="gathered study folders (tools/study.py gather)")
    return cli.run(arg_parser, lambda args: write(args.out, args.folders), argv)
