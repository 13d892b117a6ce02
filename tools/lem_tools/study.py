"""Parametric study of Affes et al. (2012): grid of rho^m x sigma^pm tension runs.

Commands (each skips what is already complete, so any can be rerun):
  plan       check the study file, record it in OUT_DIR/study.json, list the runs
  samples    build the shared samples, one per lattice and matrix fraction
             (lem_sample); --index I for one
  calibrate  sigma^[p] and E^[p] on the homogeneous lattice (lem_fracture), one
             per lattice (--index I for one), then the elastic pulls of that
             lattice's samples if the study asks for them (lem_tension)
  run        the tension runs (lem_fracture under the MPI launcher); --index I
             for one
  gather     one table (results.csv) and the paper's figures from complete runs;
             with a bond axis or replicates also the convergence table and figures
  status     complete / failed / pending runs (and elastic pulls); missing
             samples and calibrations with their logs' last error
  all        plan, samples, calibrate, run and gather on this machine; --index I
             runs only run I (after every sample and calibration the study lacks)

Study file keys (YAML; anything else is an error):
  name               label of the study
  ranks              MPI ranks per run (default 2, at most 1000000)
  sample             lem_sample options shared by every sample, without the
                     dash (e.g. sample_particles: 64); -matrix_fraction is set
                     per sample
  matrix_fractions   list of rho^m (one sample each)
  sigma_pm_ratios    list of sigma^pm / sigma^p (one run per sample and value)
  phases             E_p, E_m, E_pp, E_pm, sigma_p (defaults: the paper's
                     3, 1, 1, 1 and 0.01; sigma^m = sigma^p) and sigma_pp
                     (default 0: bare contacts; the paper's fig. 3 has 0.3 sigma^p)
  fracture           lem_fracture / PETSc options of every run, without the dash
  solver             solver options of every run (solver_*, ksp_*, pc_*, mg_*),
                     without the dash: how the runs are solved, not what they
                     give, so left out of the study's hash (like ranks)
  strain_increment   load step of every run as a strain: -fracture_increment
                     = this x L / a of the run's sample (a the mean length of
                     its bonds, L its height); not with fracture_increment
Resolution and replicate axes (optional; docs/convergence.md):
  lattice_bonds or lattice_bonds_per_particle   list of lattice sizes
  pack_seeds, lattice_seeds                     lists of lem_sample seeds
  replicates_up_to   bond-axis value up to which every seed pair is run
  fracture_up_to     bond-axis value up to which the fracture runs are made
  elastic            true: pull every sample with lem_tension (E_eff, nu; bare
                     and adhesive contacts)

Layout of OUT_DIR: study.json, samples/rho_<r>.h5, calibration/, runs/<id>/
(run.json, the lem_fracture results, log, failed.json after a failure),
results.csv, figures/*.png, fit.json.  With axes, every lattice has a tag
(e.g. bpp1250_p2_l3: bonds per particle, pack seed, lattice seed) that
prefixes its samples (samples/<tag>_rho_<r>.h5) and runs and names its
calibration (calibration/<tag>/); elastic pulls go to elastic/<sample>_bare/
and elastic/<sample>_adhesive/, and gather adds samples.csv,
convergence.csv, convergence.md and figures/convergence_*.png.  A run is
complete when its manifest.txt agrees with its files and its run.json matches
the study; an interrupted run (exit 4, checkpoint written) resumes from its
checkpoint when run again.

Results kept as data (--data DATA_DIR, e.g. docs/data/<study>): every
complete run is also kept as DATA_DIR/runs/<id>.json (study_data: its
results.csv row, options, sample checksum, thinned curve, node-stress pdf)
with the calibrations in DATA_DIR/calibration/; a run kept there is not run
again, a new OUT_DIR builds only the samples of the runs it lacks and uses
the kept calibration, and gather draws the paper's figures from DATA_DIR
into figures/paper/ (tools/paper_figures.py draws them from the data alone).

MPI launcher (environment): LEM_LAUNCHER=srun or mpirun (default: srun inside
a Slurm allocation, else mpirun); LEM_SRUN and LEM_MPIRUN, the command of
each with any flags (default: the bare name), e.g.
LEM_SRUN="srun --mpi=pmix" or LEM_MPIRUN="mpirun --oversubscribe".
Logs are appended to, one "--- study.py" line before each attempt.
"""
import datetime
import hashlib
import json
import math
import os
import re
import shlex
import signal
import socket
import subprocess
import sys

import yaml

from . import cli
from .errors import ToolError
from .files import require_folder_path, write_json
from .results import SUMMARY, ResultsError, finished_problem, read_json
from .study_data import DataFolder, sample_checksum
from .study_axes import (AXIS_KEYS, SUBSET_KEYS, has_axes, is_integer, is_number, lattices,
                         read_axes)

TOOLS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(TOOLS)
KEYS = {"name", "ranks", "sample", "matrix_fractions", "sigma_pm_ratios", "phases",
        "fracture", "solver", "strain_increment"} | AXIS_KEYS
PHASE_KEYS = {"E_p": 3.0, "E_m": 1.0, "E_pp": 1.0, "E_pm": 1.0, "sigma_p": 0.01}
GRID_RANGES = {"matrix_fractions": (0.0, 0.5), "sigma_pm_ratios": (0.0, 100.0)}
OPTION_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
RESERVED_OPTIONS = {"matrix_fraction", "output_dir", "output_stem", "sample_file"}
# What the solver section may set: the solves' levers and PETSc's Krylov and
# preconditioner options (docs/guide/solver-options.md).
SOLVER_PREFIXES = ("solver_", "ksp_", "pc_", "mg_")
# Options of the fracture section that change the lattice a sample file
# becomes (not only the loading): the elastic pulls get them too, so that
# pulls and runs measure the same lattice.
LATTICE_OPTIONS = ("lattice_face_bonds",)
COMMANDS = ("plan", "samples", "calibrate", "run", "gather", "status", "all")
EXIT_INTERRUPTED = 4  # lem_fracture: checkpoint written after SIGTERM / SIGUSR1
LAUNCHERS = ("srun", "mpirun")
LOG_MARK = "--- study.py "  # starts every attempt in an appended log
# srun's own lines about the exit of its tasks, which tail() leaves out
SRUN_NOISE = re.compile(r"srun: (error: .*: (Exited with exit code|Killed)|Job step|forcing)")
ELASTIC_CONTACTS = ("bare", "adhesive")
MAX_RANKS = 1_000_000  # more than any machine these runs are made on: a larger count is a typo


class StudyError(ToolError):
    pass


class _UniqueKeyLoader(yaml.SafeLoader):
    """YAML's safe loader, but a key given twice in one mapping is an error
    (PyYAML keeps the last one silently)."""

    def construct_mapping(self, node, deep=False):
        seen = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            try:
                if key in seen:
                    raise yaml.constructor.ConstructorError(
                        None, None, "key %r is given twice (lines %d and %d)"
                        % (key, seen[key] + 1, key_node.start_mark.line + 1),
                        key_node.start_mark)
                seen[key] = key_node.start_mark.line
            except TypeError:  # an unhashable key: the base class says so
                pass
        return super().construct_mapping(node, deep=deep)


def options_list(d):
    """{name: value} -> ['-name', 'value', ...] (booleans as true/false)."""
    out = []
    for k, v in d.items():
        out += ["-" + k, ("true" if v else "false") if isinstance(v, bool) else str(v)]
    return out


def load_study(path):
    """The study file checked and completed with defaults; StudyError names
    the first problem."""
    try:
        with open(path) as f:
            s = yaml.load(f, Loader=_UniqueKeyLoader)
    except OSError as e:
        raise StudyError("cannot read the study file %s: %s" % (path, e))
    except yaml.YAMLError as e:
        raise StudyError("study file %s is not valid YAML: %s" % (path, e))

    def bad(message, *args):
        return StudyError("study file %s: %s" % (path, message % args))

    if not isinstance(s, dict):
        raise bad("expected a mapping of keys")
    unknown = sorted(set(s) - KEYS)
    if unknown:
        raise bad("unknown key(s) %s (allowed: %s)", ", ".join(unknown), ", ".join(sorted(KEYS)))
    def mapping(key):
        """An optional mapping: absent or empty (None) is {}, anything else
        that is not a mapping is an error (not silently {})."""
        value = s.get(key)
        if value is None:
            return {}
        if not isinstance(value, dict):
            raise bad("%s must be a mapping, not %r", key, value)
        return value

    name = s.get("name", os.path.splitext(os.path.basename(path))[0])
    if not isinstance(name, str) or not name.strip():
        raise bad("name must be a non-empty text, not %r", name)
    study = {"name": name, "ranks": s.get("ranks", 2), "sample": mapping("sample"),
             "fracture": mapping("fracture"), "solver": mapping("solver")}
    wanted = rank_count_wanted(study["ranks"])
    if wanted:
        raise bad("ranks must be %s, not %r", wanted, study["ranks"])
    for key in ("sample", "fracture", "solver"):
        for option, value in study[key].items():
            # The name becomes "-name" on the command line.
            if not isinstance(option, str) or not OPTION_NAME.match(option):
                raise bad("%s: %r is not an option name (letters, digits and _, without the "
                          "dash)", key, option)
            if isinstance(value, float) and not math.isfinite(value):
                raise bad("%s.%s must be finite, not %r", key, option, value)
            if isinstance(value, str) and not value.strip():
                raise bad("%s.%s is empty: give a value", key, option)
            if not isinstance(value, (str, int, float, bool)):
                raise bad("%s.%s must be a single value, not %r", key, option, value)
    for option in study["solver"]:
        if not option.startswith(SOLVER_PREFIXES):
            raise bad("solver.%s is not a solver option (%s...): give it under fracture", option,
                      ", ".join(SOLVER_PREFIXES))
        if option in study["fracture"]:
            raise bad("%s is given under both fracture and solver", option)
    for key, (low, high) in GRID_RANGES.items():
        values = s.get(key)
        if not isinstance(values, list) or not values:
            raise bad("%s must be a non-empty list (the grid is empty)", key)
        for v in values:
            if not is_number(v):
                raise bad("%s value %r is not a number", key, v)
            if not low < v <= high:
                raise bad("%s value %r outside (%g, %g]", key, v, low, high)
        if len(set(values)) != len(values):
            raise bad("%s has repeated values", key)
        # Samples and runs are named by their values to 4 decimals.
        named = {}
        for v in values:
            if "%.4f" % v in named:
                raise bad("%s values %r and %r agree to 4 decimals (%.4f), which name the "
                          "samples and runs: they would share one; give values that differ "
                          "there", key, named["%.4f" % v], v, v)
            named["%.4f" % v] = v
        study[key] = [float(v) for v in values]
    phases = dict(PHASE_KEYS)
    given = mapping("phases")
    if set(given) - set(PHASE_KEYS) - {"sigma_pp"}:
        raise bad("phases accepts only %s", ", ".join(sorted(set(PHASE_KEYS) | {"sigma_pp"})))
    for k, v in given.items():
        if not is_number(v) or v < 0 or (v == 0 and k != "sigma_pp"):
            raise bad("phases.%s must be a number > 0%s, not %r", k,
                      " (or 0)" if k == "sigma_pp" else "", v)
        # sigma_pp only when given, so that the hash of the other studies stays theirs
        phases[k] = float(v)
    study["phases"] = phases
    clash = RESERVED_OPTIONS & (set(study["sample"]) | set(study["fracture"]))
    if clash:
        raise bad("%s are set by the study itself", ", ".join(sorted(clash)))
    if "strain_increment" in s:
        # only when given, so that the hash of the other studies stays theirs
        value = s["strain_increment"]
        if not is_number(value) or not value > 0:
            raise bad("strain_increment must be a number > 0, not %r", value)
        if "fracture_increment" in study["fracture"]:
            raise bad("give strain_increment or fracture.fracture_increment, not both")
        study["strain_increment"] = float(value)
    study.update(read_axes(s, study["sample"], bad))
    return study


def rank_count_wanted(value):
    """None if `value` is an MPI rank count (an integer, not true/false, in
    [1, MAX_RANKS]), else what it must be, in words."""
    if not is_integer(value) or value < 1:
        return "a positive integer"
    if value > MAX_RANKS:
        return "a positive integer up to %d" % MAX_RANKS
    return None


def check_ranks_option(ranks):
    """Raise StudyError unless the --ranks of a command is a rank count."""
    wanted = rank_count_wanted(ranks)
    if wanted:
        raise StudyError("--ranks %d is not %s" % (ranks, wanted))


def study_hash(study):
    """Identity of a study's results: everything but the rank count and the
    solver options, which change how runs are made, not what they give, and
    the keys that only choose which runs of the grid are made
    (replicates_up_to, fracture_up_to)."""
    left_out = {"ranks", "solver", *SUBSET_KEYS}
    text = json.dumps({k: v for k, v in study.items() if k not in left_out}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class Study:
    def __init__(self, path, out, bin_dir=None, data=None):
        self.spec = load_study(path)
        require_folder_path(out, "the study's output folder", StudyError)
        if data:
            require_folder_path(data, "the data folder (--data)", StudyError)
        self.out = out
        self.bin = bin_dir or os.environ.get("LEM_BIN") or os.path.join(ROOT, "build")
        self.hash = study_hash(self.spec)
        self.lattices = lattices(self.spec)
        self.by_tag = {lattice["tag"]: lattice for lattice in self.lattices}
        # the data folder (study_data) that keeps a row per run, if any
        self.data = DataFolder(data, self) if data else None

    # --- layout -----------------------------------------------------------
    def samples(self):
        """Every sample, lattice by lattice: its lattice, rho^m and file stem."""
        return [{"lattice": lattice, "rho_m": rho, "stem": self.sample_stem(lattice, rho)}
                for lattice in self.lattices for rho in self.spec["matrix_fractions"]]

    @staticmethod
    def sample_stem(lattice, rho):
        stem = "rho_%.4f" % rho
        return stem if lattice["tag"] is None else "%s_%s" % (lattice["tag"], stem)

    def sample_file(self, lattice, rho):
        return os.path.join(self.out, "samples", self.sample_stem(lattice, rho) + ".h5")

    def lattice_of(self, item):
        """The lattice of a run (or an elastic pull), from its `lattice` tag."""
        return self.by_tag[item.get("lattice")]

    def runs(self):
        """Every fracture run: id, rho^m, sigma^pm / sigma^p (and the tag of
        its lattice in a study with axes), in a fixed order."""
        out = []
        for lattice in self.lattices:
            if not lattice["fracture"]:
                continue
            for rho in self.spec["matrix_fractions"]:
                for ratio in self.spec["sigma_pm_ratios"]:
                    run = {"id": "%s_spm_%.4f" % (self.sample_stem(lattice, rho), ratio),
                           "rho_m": rho, "sigma_pm_ratio": ratio}
                    if lattice["tag"] is not None:
                        run["lattice"] = lattice["tag"]
                    out.append(run)
        return out

    def run_dir(self, run):
        return os.path.join(self.out, "runs", run["id"])

    def elastic_pulls(self, lattice=None):
        """The elastic pulls (every sample of `lattice`, or of the study, with
        bare and with adhesive contacts) if the study asks for them."""
        if not self.spec.get("elastic"):
            return []
        return [{"id": "%s_%s" % (s["stem"], contacts), "rho_m": s["rho_m"],
                 "lattice": s["lattice"]["tag"], "contacts": contacts}
                for s in self.samples() if lattice is None or s["lattice"] is lattice
                for contacts in ELASTIC_CONTACTS]

    def pull_dir(self, pull):
        return os.path.join(self.out, "elastic", pull["id"])

    def calibration_dir(self, lattice):
        if lattice["tag"] is None:
            return os.path.join(self.out, "calibration")
        return os.path.join(self.out, "calibration", lattice["tag"])

    # --- steps ------------------------------------------------------------
    def plan(self):
        os.makedirs(self.out, exist_ok=True)
        record = os.path.join(self.out, "study.json")
        if os.path.exists(record):
            old = read_json(record)
            if old.get("hash") != self.hash:
                raise StudyError("%s holds the results of a different study (%s, hash %s; this "
                                 "one is %s, hash %s): use another output folder"
                                 % (self.out, old.get("name"), old.get("hash"),
                                    self.spec["name"], self.hash))
        else:
            write_json(record, dict(self.spec, hash=self.hash))
        if self.data:
            self.data.claim()
        runs = self.runs()
        if not has_axes(self.spec):
            print("study %s (hash %s): %d samples x %d sigma^pm = %d runs in %s"
                  % (self.spec["name"], self.hash, len(self.spec["matrix_fractions"]),
                     len(self.spec["sigma_pm_ratios"]), len(runs), self.out))
        else:
            print("study %s (hash %s): %d lattices x %d matrix fractions = %d samples; %d "
                  "fracture runs, %d elastic pulls in %s"
                  % (self.spec["name"], self.hash, len(self.lattices),
                     len(self.spec["matrix_fractions"]), len(self.samples()), len(runs),
                     len(self.elastic_pulls()), self.out))
        return runs

    def make_samples(self, index=None):
        samples = self.samples()
        chosen = samples if index is None else [pick(samples, index, "sample")]
        os.makedirs(os.path.join(self.out, "samples"), exist_ok=True)
        needed = self.needed_samples()
        for sample in chosen:
            stem, lattice = sample["stem"], sample["lattice"]
            path = self.sample_file(lattice, sample["rho_m"])
            done = os.path.join(self.out, "samples", stem + "_summary.json")
            if os.path.exists(done) and os.path.exists(path):
                print("sample %s: complete" % stem)
                continue
            if stem not in needed:
                print("sample %s: not needed (its runs are kept in %s)" % (stem, self.data.path))
                continue
            options = dict(self.spec["sample"], **lattice["sample_options"])
            cmd = [os.path.join(self.bin, "lem_sample")] + options_list(options) + [
                "-matrix_fraction", str(sample["rho_m"]),
                "-output_dir", os.path.join(self.out, "samples"), "-output_stem", stem]
            print("sample %s: %s" % (stem, " ".join(cmd)), flush=True)
            log = os.path.join(self.out, "samples", stem + ".log")
            if execute(cmd, log) != 0:
                raise StudyError("sample %s failed (log: %s): %s" % (stem, log, tail(log)))

    def needed_samples(self):
        """Stems of the samples some step still needs: all of them without
        a data folder; with one, those of the runs it lacks, of the elastic
        pulls, and of the calibration of a lattice neither kept nor made
        whose runs are not all kept."""
        if not self.data:
            return {s["stem"] for s in self.samples()}
        needed = {p["id"].rsplit("_", 1)[0] for p in self.elastic_pulls()}
        for run in self.runs():
            if not self.data.has_row(run):
                lattice = self.lattice_of(run)
                needed.add(self.sample_stem(lattice, run["rho_m"]))
                if not self.calibration(lattice):
                    needed.add(self.sample_stem(lattice, self.spec["matrix_fractions"][0]))
        return needed

    def moduli_options(self, e_pp):
        ph = self.spec["phases"]
        return ["-phase_E_p", str(ph["E_p"]), "-phase_E_m", str(ph["E_m"]),
                "-phase_E_pp", str(e_pp), "-phase_E_pm", str(ph["E_pm"])]

    def fracture_options(self, extra):
        """The options of lem_fracture but its sample and output folder."""
        ph = self.spec["phases"]
        return (self.moduli_options(ph["E_pp"]) + [
            "-phase_sigma_p", str(ph["sigma_p"]), "-phase_sigma_m", str(ph["sigma_p"]),
            "-phase_sigma_pp", str(ph.get("sigma_pp", 0))] + options_list(self.spec["fracture"])
            + options_list(self.spec["solver"]) + extra)

    def fracture_command(self, sample, out_dir, extra):
        return (launcher(self.spec["ranks"]) + [
            os.path.join(self.bin, "lem_fracture"), "-sample_file", sample, "-output_dir", out_dir]
            + self.fracture_options(extra))

    def run_options(self, run, cal):
        """The options of `run` beyond the study's, with the calibration `cal`."""
        sigma_pm = run["sigma_pm_ratio"] * self.spec["phases"]["sigma_p"]
        return ["-phase_sigma_pm", repr(sigma_pm), "-fracture_calibrate", "false",
                "-fracture_sigma_unit", repr(cal["sigma_hom"]),
                "-fracture_modulus_unit", repr(cal["E_hom"])] + self.increment_options(run)

    def increment_options(self, run):
        """-fracture_increment (in bond lengths a) that makes each load step
        of `run` the study's strain_increment: strain_increment times L / a
        of its sample; none without strain_increment."""
        strain = self.spec.get("strain_increment")
        if strain is None:
            return []
        sample = self.sample_file(self.lattice_of(run), run["rho_m"])
        return ["-fracture_increment", repr(strain / bond_length_over_height(sample))]

    def calibration(self, lattice):
        """sigma^[p] and E^[p] of `lattice`: those kept in the data folder
        (so that the rows added later share the units of the kept ones), else
        those of its calibration run, else None."""
        kept = self.data.calibration(lattice["tag"]) if self.data else None
        if kept:
            return kept
        directory = self.calibration_dir(lattice)
        if finished_problem(directory) is not None:
            return None
        return read_json(os.path.join(directory, SUMMARY))

    def calibrate(self, index=None):
        """Each lattice (or the one of --index): its calibration, then the
        elastic pulls of its samples if the study asks for them.  A failed
        pull leaves failed.json (status and gather report it) but does not
        fail the step: the fracture runs need only the calibration."""
        chosen = self.lattices if index is None else [pick(self.lattices, index, "lattice")]
        for lattice in chosen:
            if self.calibrate_lattice(lattice) == EXIT_INTERRUPTED:
                return EXIT_INTERRUPTED
            for pull in self.elastic_pulls(lattice):
                if self.pull_one(pull) == EXIT_INTERRUPTED:
                    return EXIT_INTERRUPTED
        return 0

    def calibrate_lattice(self, lattice):
        """sigma^[p], E^[p]: the same lattice (and so the same homogeneous
        lattice) underlies every sample of a lattice, so one calibration
        serves them all."""
        label = "calibration" if lattice["tag"] is None else "calibration " + lattice["tag"]
        cal = self.calibration(lattice)
        if cal:
            print("%s: complete" % label)
            if self.data:
                self.data.write_calibration(lattice["tag"], cal)
            return 0
        if self.data and all(self.data.has_row(run) for run in self.runs()
                             if self.lattice_of(run) is lattice):
            print("%s: not needed (the runs are kept in %s)" % (label, self.data.path))
            return 0
        rho = self.spec["matrix_fractions"][0]
        out_dir = self.calibration_dir(lattice)
        os.makedirs(out_dir, exist_ok=True)
        cmd = self.fracture_command(self.sample_file(lattice, rho), out_dir,
                                    ["-fracture_max_steps", "1", "-output_fields", "false"])
        print("%s: %s" % (label, " ".join(cmd)), flush=True)
        log = os.path.join(out_dir, "log")
        status = execute(cmd, log)
        if status == EXIT_INTERRUPTED:
            print("%s: interrupted after a checkpoint; run it again to resume" % label)
            return status
        if status != 0:
            raise StudyError("%s failed (log: %s): %s" % (label, log, tail(log)))
        if self.data:
            self.data.write_calibration(lattice["tag"], self.calibration(lattice))
        return 0

    def run_record(self, run):
        return dict(run, study_hash=self.hash, sample=os.path.abspath(
            self.sample_file(self.lattice_of(run), run["rho_m"])))

    def is_complete(self, run):
        """Whether `run` is done: kept in the data folder, or complete in
        its run folder."""
        return bool(self.data and self.data.has_row(run)) or self.folder_complete(run)

    def folder_complete(self, run):
        d = self.run_dir(run)
        try:
            return (read_json(os.path.join(d, "run.json")) == self.run_record(run)
                    and finished_problem(d) is None)
        except ResultsError:
            return False

    def pull_complete(self, pull):
        d = self.pull_dir(pull)
        try:
            return (read_json(os.path.join(d, "run.json")) == self.run_record(pull)
                    and os.path.exists(os.path.join(d, SUMMARY)))
        except ResultsError:
            return False

    def state(self, run):
        """complete, failed (failed.json written) or pending."""
        complete = self.pull_complete(run) if "contacts" in run else self.is_complete(run)
        if complete:
            return "complete"
        d = self.pull_dir(run) if "contacts" in run else self.run_dir(run)
        if os.path.exists(os.path.join(d, "failed.json")):
            return "failed"
        return "pending"

    def launch(self, item, directory, cmd, kind="run"):
        """Record `item` (a run or a pull) in `directory`, run `cmd` there and
        report as `kind`; a failure leaves failed.json.  Returns the exit
        status."""
        os.makedirs(directory, exist_ok=True)
        write_json(os.path.join(directory, "run.json"), self.run_record(item))
        failed = os.path.join(directory, "failed.json")
        if os.path.exists(failed):
            os.remove(failed)
        print("%s %s: %s" % (kind, item["id"], " ".join(cmd)), flush=True)
        log = os.path.join(directory, "log")
        status = execute(cmd, log)
        if status == 0:
            print("%s %s: complete" % (kind, item["id"]))
        elif status == EXIT_INTERRUPTED:
            print("%s %s: interrupted after a checkpoint; run it again to resume"
                  % (kind, item["id"]))
        else:
            write_json(failed, {"exit_status": status, "log_tail": tail(log)})
            print("%s %s: FAILED (exit %d): %s" % (kind, item["id"], status, tail(log)))
        return status

    def pull_one(self, pull):
        """lem_tension on a sample: E_eff and nu with bare contacts (E^pp = 0)
        or adhesive ones (E^pp = E^pm)."""
        if self.pull_complete(pull):
            print("elastic %s: complete" % pull["id"])
            return 0
        d = self.pull_dir(pull)
        e_pp = 0 if pull["contacts"] == "bare" else self.spec["phases"]["E_pm"]
        cmd = launcher(self.spec["ranks"]) + [
            os.path.join(self.bin, "lem_tension"), "-sample_file",
            self.sample_file(self.lattice_of(pull), pull["rho_m"]), "-output_dir", d,
            "-output_fields", "false"] + self.moduli_options(e_pp) + options_list(
                {k: v for k, v in self.spec["fracture"].items() if k in LATTICE_OPTIONS})
        return self.launch(pull, d, cmd, "elastic")

    def run_one(self, run):
        d = self.run_dir(run)
        if self.data and self.data.has_row(run):
            print("run %s: kept in %s" % (run["id"], self.data.path))
            return 0
        if self.folder_complete(run):
            print("run %s: complete" % run["id"])
            self.keep(run)
            return 0
        lattice = self.lattice_of(run)
        cal = self.calibration(lattice)
        if not cal:
            raise StudyError("no calibration in %s: run the calibrate step first"
                             % self.calibration_dir(lattice))
        sample = self.sample_file(lattice, run["rho_m"])
        if not os.path.exists(sample):
            raise StudyError("sample %s missing: run the samples step first" % sample)
        status = self.launch(run, d, self.fracture_command(sample, d, self.run_options(run, cal)))
        if status == 0:
            # their own processes: a failed figure must not fail the run
            for tool in ("plot_stress.py", "plot_crack.py"):
                subprocess.run([sys.executable, os.path.join(TOOLS, tool), d],
                               stdout=subprocess.DEVNULL, check=False)
            self.keep(run)
        return status

    def keep(self, run):
        """The row of a run complete in its folder, into the data folder (if
        the study has one and lacks it)."""
        if not self.data or self.data.has_row(run):
            return
        from .study_table import folder_row  # numpy and the results readers

        lattice = self.lattice_of(run)
        cal = self.calibration(lattice)
        if self.data.calibration(lattice["tag"]) is None:
            self.data.write_calibration(lattice["tag"], cal)
        self.data.write_row(run, folder_row(self, run), self.fracture_options(
            self.run_options(run, cal)), self.run_dir(run),
            self.sample_file(self.lattice_of(run), run["rho_m"]), cal)
        print("run %s: kept in %s" % (run["id"], self.data.run_path(run["id"])))

    def run_all(self, index=None):
        runs = self.runs()
        chosen = runs if index is None else [pick(runs, index, "run")]
        statuses = []
        for r in chosen:
            statuses.append(self.run_one(r))
            if statuses[-1] == EXIT_INTERRUPTED:
                return EXIT_INTERRUPTED  # a stop request: start no other run
        return 0 if all(s == 0 for s in statuses) else 1

    def missing_inputs(self):
        """A line per sample or calibration not made yet: failed (with its
        log's error) if it has a log, else not started."""
        out, needed = [], self.needed_samples()
        for sample in self.samples():
            if sample["stem"] not in needed:
                continue  # its runs are kept in the data folder
            if not os.path.exists(self.sample_file(sample["lattice"], sample["rho_m"])):
                log = os.path.join(self.out, "samples", sample["stem"] + ".log")
                out.append(("sample %s" % sample["stem"], log))
        for lattice in self.lattices:
            if not self.calibration(lattice) and any(
                    not self.is_complete(run) for run in self.runs()
                    if self.lattice_of(run) is lattice):
                name = "calibration" if lattice["tag"] is None else "calibration " + lattice["tag"]
                out.append((name, os.path.join(self.calibration_dir(lattice), "log")))
        return ["%-28s %s" % (name, "failed or interrupted: %s (log: %s)" % (tail(log), log)
                              if os.path.exists(log) else "not started")
                for name, log in out]

    def other_samples(self):
        """Lines for the kept rows whose sample differs from the one here
        (other checksum of its datasets: another build or platform)."""
        out = []
        for run in self.runs():
            sample = self.sample_file(self.lattice_of(run), run["rho_m"])
            if not (self.data and self.data.has_row(run) and os.path.exists(sample)):
                continue
            kept = self.data.row(run["id"])["sample"].get("checksum")
            here = sample_checksum(sample)
            if kept != here:
                out.append("%-28s kept with sample %s, the sample here is %s"
                           % (run["id"], kept, here))
        return out

    def status(self):
        for line in self.missing_inputs() + self.other_samples():
            print(line)
        counts = {"complete": 0, "failed": 0, "pending": 0}
        for run in self.runs() + self.elastic_pulls():
            state = self.state(run)
            counts[state] += 1
            if state != "complete":
                print("%-28s %s" % (run["id"], state))
        print("%d complete, %d failed, %d pending" % (counts["complete"], counts["failed"],
                                                      counts["pending"]))
        return counts


def bond_length_over_height(sample):
    """a / L of a sample file: the mean length of every row of its /bonds,
    void bonds included (lem_fracture's a, the unit of -fracture_increment),
    over the height of its box (the strain of a unit displacement of the
    top face)."""
    import numpy as np

    from .results import read_hdf5

    d = read_hdf5(sample, ("bonds/connectivity", "nodes/coordinates"), ("box_lo", "box_hi"))
    ends, xyz = d["bonds/connectivity"], d["nodes/coordinates"]
    lengths = np.linalg.norm(xyz[ends[:, 0]] - xyz[ends[:, 1]], axis=1)
    height = float(d["box_hi"][2] - d["box_lo"][2])
    if not lengths.size or not height > 0:
        raise StudyError("%s: no bond or an empty box, so no bond length a" % sample)
    return float(lengths.mean()) / height


def pick(items, index, what):
    if not 0 <= index < len(items):
        raise StudyError("--index %d: the study has %d %ss (0 to %d)"
                         % (index, len(items), what, len(items) - 1))
    return items[index]


def launcher(ranks):
    """The MPI launcher of a run on `ranks` ranks: srun inside a Slurm
    allocation, else mpirun, unless LEM_LAUNCHER says which; no flags but
    those of LEM_SRUN / LEM_MPIRUN (a site's or this machine's choice)."""
    kind = os.environ.get("LEM_LAUNCHER") or ("srun" if os.environ.get("SLURM_JOB_ID")
                                              else "mpirun")
    if kind not in LAUNCHERS:
        raise StudyError("LEM_LAUNCHER=%r is not a launcher: use %s"
                         % (kind, " or ".join(LAUNCHERS)))
    variable = "LEM_" + kind.upper()
    try:
        command = shlex.split(os.environ.get(variable) or kind)
    except ValueError as e:
        raise StudyError("%s=%r cannot be split into words: %s"
                         % (variable, os.environ[variable], e))
    return command + ["-n", str(ranks)]


def execute(cmd, log):
    """Run cmd with its output in log.  SIGUSR1 and SIGTERM (Slurm's warning
    before the time limit, a job being stopped) reach it as SIGUSR1, so that
    lem_fracture writes its checkpoint and exits 4: Open MPI's mpirun and
    srun pass SIGUSR1 on to the ranks, but kill them on SIGTERM.  The log
    is appended to, so that a requeued job keeps the interrupted part."""
    with open(log, "a") as f:
        f.write("%sstarted %s on %s: %s\n" % (LOG_MARK, now(), socket.gethostname(),
                                            " ".join(cmd)))
        f.flush()
        try:
            proc = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT)
        except OSError as e:
            f.write(str(e) + "\n")
            return 127
        previous = {s: signal.signal(s, lambda *_: proc.send_signal(signal.SIGUSR1))
                    for s in (signal.SIGUSR1, signal.SIGTERM)}
        try:
            return proc.wait()
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)


def now():
    return datetime.datetime.now().astimezone().isoformat(timespec="seconds")


def tail(path, lines=2):
    """The error lines of a log's last attempt (else its last lines), without
    the launcher's boilerplate."""
    try:
        with open(path, errors="replace") as f:
            attempt = f.read().split("\n" + LOG_MARK)[-1].splitlines()
    except OSError:
        return "(no log)"
    text = [l.strip() for l in attempt if l.strip() and not l.startswith("step ")
            and not l.startswith("---")]
    boilerplate = ("Process name", "Exit code", "Primary job", "mpirun detected", "a non-zero",
                   "the job to be terminated", "Per user-direction", "process returned")
    text = [l for l in text if not l.startswith(boilerplate) and not SRUN_NOISE.match(l)]
    errors = [l for l in text if "error" in l.lower()]
    return " | ".join((errors or text)[-lines:])


def do(args):
    study = Study(args.study_file, args.out, args.bin, args.data)
    if args.ranks is not None:
        check_ranks_option(args.ranks)
        study.spec["ranks"] = args.ranks
    command, index = args.command, args.index
    if index is not None and command not in ("samples", "calibrate", "run", "all"):
        raise StudyError("--index picks a sample, lattice or run; `%s` takes none" % command)
    if command in ("calibrate", "run", "all"):
        launcher(study.spec["ranks"])  # a bad LEM_LAUNCHER stops before any work
    if command == "all" and index is not None:
        pick(study.runs(), index, "run")  # so does a bad --index
    study.plan()
    if command in ("samples", "all"):
        study.make_samples(index if command == "samples" else None)
    status = 0
    if command in ("calibrate", "all"):
        status = study.calibrate(index if command == "calibrate" else None)
        if status == EXIT_INTERRUPTED:
            return status
    if command in ("run", "all"):
        status = study.run_all(index)
    if command == "status":
        counts = study.status()
        status = 0 if counts["complete"] == sum(counts.values()) else 1
    if command in ("gather", "all"):
        status = max(status, gather(study))
    return status


def gather(study):
    """The gather step (study_table), imported here so that the other steps,
    run once per Slurm task, do not load matplotlib; with a data folder,
    the rows of the runs complete here that it lacks are added to it and
    the paper's figures drawn from it (paper_figures) into figures/paper/."""
    from .study_table import gather as write_table_and_figures

    status = write_table_and_figures(study)
    if study.data:
        from .paper_figures import draw_folders

        for run in study.runs():
            if study.folder_complete(run):
                study.keep(run)
        if study.data.rows():
            out = os.path.join(study.out, "figures", "paper")
            draw_folders([study.data.path], out)
            print("gather: the paper's figures from %s -> %s" % (study.data.path, out))
    return status


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("command", choices=COMMANDS, metavar="COMMAND",
                            help="one of: " + ", ".join(COMMANDS) + " (below)")
    arg_parser.add_argument("study_file", metavar="STUDY.yaml", help="the study file")
    arg_parser.add_argument("out", metavar="OUT_DIR", help="the study's output folder")
    arg_parser.add_argument("--index", type=int, metavar="I",
                            help="one sample (samples), one lattice (calibrate) or one run "
                                 "(run, all) by its number")
    arg_parser.add_argument("--ranks", type=int, metavar="N",
                            help="MPI ranks per run (default: the study's `ranks`)")
    arg_parser.add_argument("--bin", metavar="DIR",
                            help="folder of the lem_* programs (default: $LEM_BIN, else "
                                 "build/ of this repository)")
    data_argument(arg_parser)
    return cli.run(arg_parser, do, argv)


def data_argument(arg_parser):
    arg_parser.add_argument("--data", metavar="DATA_DIR",
                            help="keep a row per run in DATA_DIR (e.g. docs/data/<study>), "
                                 "read rows kept there instead of running them, and draw the "
                                 "paper's figures from it (gather)")


GATHER_DOC = """Table and figures of a parametric study (the gather step of study.py).

Reads every complete run of the study (summary.json, curve.csv, stress.json)
and writes, in the study's output folder:
  results.csv         one row per complete run
  fit.json            A and k of the strength scaling (eq. 10) and what they
                      were fitted to, beta per rho^m, the resolution of the
                      figures (particles, bonds per particle, L_n, runs per point)
  figures/strength (.png, .pdf)  sigma_eff against sigma^pm (fig. 9) and the
                              collapse of eq. 10 (fig. 12)
  figures/damage (.png, .pdf)    n_b against strain (fig. 13), n_b after failure
                              against sigma^pm (fig. 14), grey map of n_b over
                              (rho^m, sigma^pm) (fig. 15), n_b against K_c^r
                              of eq. 14 (fig. 16)
  figures/stiffness_stress (.png, .pdf)  E_eff against rho^m (fig. 5) and the
                              tail exponent beta of the node stresses (fig. 8),
                              with the paper's values as stars
Each figure says its resolution in its subtitle.  A study with a bond axis
or replicates (docs/convergence.md) draws these at one size, the
finest whose fracture runs are all complete: each point the mean over its
replicates (the seeds at that size) with ±1 standard deviation as error
bars, eq. 10 fitted to these means (fit.json: figures_lattices), and adds:
  samples.csv         one row per sample: lattice, L_n, calibration, E_eff and
                      nu of the elastic pulls
  convergence.csv     per quantity and grid point: the value extrapolated to
                      L_n -> 0 and its standard error, the finest value, the
                      replicate scatter and where it exceeds the
                      discretisation error
  convergence_levels.csv  per quantity, grid point and size: mean, standard
                      deviation, number of runs
  convergence.md      the same as markdown tables
  figures/convergence_elastic, _strength, _damage (.png, .pdf)
                      every quantity against L_n with the fitted line
Runs that are not complete are listed and left out; the exit status is then 1.
"""


def gather_main(argv=None):
    arg_parser = cli.parser(GATHER_DOC)
    arg_parser.add_argument("study_file", metavar="STUDY.yaml", help="the study file")
    arg_parser.add_argument("out", metavar="OUT_DIR", help="the study's output folder")
    data_argument(arg_parser)
    return cli.run(arg_parser, lambda args: gather(Study(args.study_file, args.out,
                                                         data=args.data)), argv)


if __name__ == "__main__":
    raise SystemExit(main())
