"""Parametric study of Affes et al. (2012): grid of rho^m x sigma^pm tension runs.

Commands (each skips what is already complete, so any can be rerun):
  plan       check the study file, record it in OUT_DIR/study.json, list the runs
  samples    build the shared samples, one per matrix fraction (lem_sample)
  calibrate  sigma^[p] and E^[p] on the homogeneous lattice (lem_fracture)
  run        the tension runs (lem_fracture under mpirun); --index I for one
  gather     one table (results.csv) and the paper's figures from complete runs
  status     complete / failed / pending runs
  all        plan, samples, calibrate, run and gather on this machine

Study file keys (YAML; anything else is an error):
  name               label of the study
  ranks              MPI ranks per run (default 2)
  sample             lem_sample options shared by every sample, without the
                     dash (e.g. sample_particles: 64); -matrix_fraction is set
                     per sample
  matrix_fractions   list of rho^m (one sample each)
  sigma_pm_ratios    list of sigma^pm / sigma^p (one run per sample and value)
  phases             E_p, E_m, E_pp, E_pm, sigma_p (defaults: the paper's
                     3, 1, 1, 1 and 0.01; sigma^m = sigma^p, sigma^pp = 0)
  fracture           lem_fracture / PETSc options of every run, without the dash

Layout of OUT_DIR: study.json, samples/rho_<r>.h5, calibration/, runs/<id>/
(run.json, the lem_fracture results, log, failed.json after a failure),
results.csv, figures/*.png, fit.json.  A run is complete when its
manifest.txt agrees with its files and its run.json matches the study; an
interrupted run (exit 4, checkpoint written) resumes from its checkpoint when
run again.
"""
import hashlib
import json
import math
import os
import re
import signal
import subprocess
import sys

import yaml

from . import cli
from .errors import ToolError
from .files import write_json
from .results import ResultsError, finished_problem, read_json

TOOLS = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ROOT = os.path.dirname(TOOLS)
KEYS = {"name", "ranks", "sample", "matrix_fractions", "sigma_pm_ratios", "phases", "fracture"}
PHASE_KEYS = {"E_p": 3.0, "E_m": 1.0, "E_pp": 1.0, "E_pm": 1.0, "sigma_p": 0.01}
GRID_RANGES = {"matrix_fractions": (0.0, 0.5), "sigma_pm_ratios": (0.0, 100.0)}
OPTION_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
RESERVED_OPTIONS = {"matrix_fraction", "output_dir", "output_stem", "sample_file"}
COMMANDS = ("plan", "samples", "calibrate", "run", "gather", "status", "all")
EXIT_INTERRUPTED = 4  # lem_fracture: checkpoint written after SIGTERM / SIGUSR1


class StudyError(ToolError):
    pass


def is_number(value):
    """A finite int or float; YAML's true/false are bools, which Python would
    otherwise take for 1 and 0."""
    return (isinstance(value, (int, float)) and not isinstance(value, bool)
            and math.isfinite(value))


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
            s = yaml.safe_load(f)
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
             "fracture": mapping("fracture")}
    ranks = study["ranks"]
    if not isinstance(ranks, int) or isinstance(ranks, bool) or ranks < 1:
        raise bad("ranks must be a positive integer, not %r", ranks)
    for key in ("sample", "fracture"):
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
        study[key] = [float(v) for v in values]
    phases = dict(PHASE_KEYS)
    given = mapping("phases")
    if set(given) - set(PHASE_KEYS):
        raise bad("phases accepts only %s", ", ".join(sorted(PHASE_KEYS)))
    for k, v in given.items():
        if not is_number(v) or v <= 0:
            raise bad("phases.%s must be a number > 0, not %r", k, v)
        phases[k] = float(v)
    study["phases"] = phases
    clash = RESERVED_OPTIONS & (set(study["sample"]) | set(study["fracture"]))
    if clash:
        raise bad("%s are set by the study itself", ", ".join(sorted(clash)))
    return study


def study_hash(study):
    """Identity of a study's results: everything but the rank count, which
    changes how runs are made, not what they give."""
    text = json.dumps({k: v for k, v in study.items() if k != "ranks"}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class Study:
    def __init__(self, path, out, bin_dir=None):
        self.spec = load_study(path)
        self.out = out
        self.bin = bin_dir or os.environ.get("LEM_BIN") or os.path.join(ROOT, "build")
        self.hash = study_hash(self.spec)

    # --- layout -----------------------------------------------------------
    def sample_stem(self, rho):
        return "rho_%.4f" % rho

    def sample_file(self, rho):
        return os.path.join(self.out, "samples", self.sample_stem(rho) + ".h5")

    def runs(self):
        """Every run: id, rho^m, sigma^pm / sigma^p, in a fixed order."""
        out = []
        for rho in self.spec["matrix_fractions"]:
            for ratio in self.spec["sigma_pm_ratios"]:
                out.append({"id": "rho_%.4f_spm_%.4f" % (rho, ratio), "rho_m": rho,
                            "sigma_pm_ratio": ratio})
        return out

    def run_dir(self, run):
        return os.path.join(self.out, "runs", run["id"])

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
        runs = self.runs()
        print("study %s (hash %s): %d samples x %d sigma^pm = %d runs in %s"
              % (self.spec["name"], self.hash, len(self.spec["matrix_fractions"]),
                 len(self.spec["sigma_pm_ratios"]), len(runs), self.out))
        return runs

    def make_samples(self, index=None):
        rhos = self.spec["matrix_fractions"]
        chosen = rhos if index is None else [pick(rhos, index, "sample")]
        os.makedirs(os.path.join(self.out, "samples"), exist_ok=True)
        for rho in chosen:
            stem = self.sample_stem(rho)
            done = os.path.join(self.out, "samples", stem + "_summary.json")
            if os.path.exists(done) and os.path.exists(self.sample_file(rho)):
                print("sample %s: complete" % stem)
                continue
            cmd = [os.path.join(self.bin, "lem_sample")] + options_list(self.spec["sample"]) + [
                "-matrix_fraction", str(rho), "-output_dir", os.path.join(self.out, "samples"),
                "-output_stem", stem]
            print("sample %s: %s" % (stem, " ".join(cmd)), flush=True)
            log = os.path.join(self.out, "samples", stem + ".log")
            if execute(cmd, log) != 0:
                raise StudyError("sample %s failed (log: %s): %s" % (stem, log, tail(log)))

    def fracture_command(self, sample, out_dir, extra):
        ph = self.spec["phases"]
        return (mpirun(self.spec["ranks"]) + [
            os.path.join(self.bin, "lem_fracture"), "-sample_file", sample, "-output_dir", out_dir,
            "-phase_E_p", str(ph["E_p"]), "-phase_E_m", str(ph["E_m"]),
            "-phase_E_pp", str(ph["E_pp"]), "-phase_E_pm", str(ph["E_pm"]),
            "-phase_sigma_p", str(ph["sigma_p"]), "-phase_sigma_m", str(ph["sigma_p"]),
            "-phase_sigma_pp", "0"] + options_list(self.spec["fracture"]) + extra)

    def calibration(self):
        directory = os.path.join(self.out, "calibration")
        if finished_problem(directory) is not None:
            return None
        return read_json(os.path.join(directory, "summary.json"))

    def calibrate(self):
        """sigma^[p], E^[p]: the same lattice (and so the same homogeneous
        lattice) underlies every sample, so one calibration serves them all."""
        if self.calibration():
            print("calibration: complete")
            return 0
        rho = self.spec["matrix_fractions"][0]
        out_dir = os.path.join(self.out, "calibration")
        os.makedirs(out_dir, exist_ok=True)
        cmd = self.fracture_command(self.sample_file(rho), out_dir,
                                    ["-fracture_max_steps", "1", "-output_fields", "false"])
        print("calibration: " + " ".join(cmd), flush=True)
        log = os.path.join(out_dir, "log")
        status = execute(cmd, log)
        if status == EXIT_INTERRUPTED:
            print("calibration: interrupted after a checkpoint; run it again to resume")
            return status
        if status != 0:
            raise StudyError("calibration failed (log: %s): %s" % (log, tail(log)))
        return 0

    def run_record(self, run):
        return dict(run, study_hash=self.hash, sample=os.path.abspath(
            self.sample_file(run["rho_m"])))

    def is_complete(self, run):
        d = self.run_dir(run)
        try:
            return (read_json(os.path.join(d, "run.json")) == self.run_record(run)
                    and finished_problem(d) is None)
        except ResultsError:
            return False

    def state(self, run):
        """complete, failed (failed.json written) or pending."""
        if self.is_complete(run):
            return "complete"
        if os.path.exists(os.path.join(self.run_dir(run), "failed.json")):
            return "failed"
        return "pending"

    def run_one(self, run):
        d = self.run_dir(run)
        if self.is_complete(run):
            print("run %s: complete" % run["id"])
            return 0
        cal = self.calibration()
        if not cal:
            raise StudyError("no calibration in %s/calibration: run the calibrate step first"
                             % self.out)
        if not os.path.exists(self.sample_file(run["rho_m"])):
            raise StudyError("sample %s missing: run the samples step first"
                             % self.sample_file(run["rho_m"]))
        os.makedirs(d, exist_ok=True)
        write_json(os.path.join(d, "run.json"), self.run_record(run))
        failed = os.path.join(d, "failed.json")
        if os.path.exists(failed):
            os.remove(failed)
        sigma_pm = run["sigma_pm_ratio"] * self.spec["phases"]["sigma_p"]
        cmd = self.fracture_command(self.sample_file(run["rho_m"]), d, [
            "-phase_sigma_pm", repr(sigma_pm), "-fracture_calibrate", "false",
            "-fracture_sigma_unit", repr(cal["sigma_hom"]),
            "-fracture_modulus_unit", repr(cal["E_hom"])])
        print("run %s: %s" % (run["id"], " ".join(cmd)), flush=True)
        status = execute(cmd, os.path.join(d, "log"))
        if status == 0:
            # its own process: a failed stress figure must not fail the run
            subprocess.run([sys.executable, os.path.join(TOOLS, "plot_stress.py"), d],
                           stdout=subprocess.DEVNULL, check=False)
            print("run %s: complete" % run["id"])
        elif status == EXIT_INTERRUPTED:
            print("run %s: interrupted after a checkpoint; run it again to resume" % run["id"])
        else:
            write_json(failed, {"exit_status": status, "log_tail": tail(os.path.join(d, "log"))})
            print("run %s: FAILED (exit %d): %s" % (run["id"], status,
                                                     tail(os.path.join(d, "log"))))
        return status

    def run_all(self, index=None):
        runs = self.runs()
        chosen = runs if index is None else [pick(runs, index, "run")]
        statuses = []
        for r in chosen:
            statuses.append(self.run_one(r))
            if statuses[-1] == EXIT_INTERRUPTED:
                return EXIT_INTERRUPTED  # a stop request: start no other run
        return 0 if all(s == 0 for s in statuses) else 1

    def status(self):
        counts = {"complete": 0, "failed": 0, "pending": 0}
        for run in self.runs():
            state = self.state(run)
            counts[state] += 1
            if state != "complete":
                print("%-28s %s" % (run["id"], state))
        print("%d complete, %d failed, %d pending" % (counts["complete"], counts["failed"],
                                                      counts["pending"]))
        return counts


def pick(items, index, what):
    if not 0 <= index < len(items):
        raise StudyError("--index %d: the study has %d %ss (0 to %d)"
                         % (index, len(items), what, len(items) - 1))
    return items[index]


def mpirun(ranks):
    launcher = os.environ.get("LEM_MPIRUN", "mpirun --allow-run-as-root --oversubscribe")
    return launcher.split() + ["-n", str(ranks)]


def execute(cmd, log):
    """Run cmd with its output in log.  SIGUSR1 and SIGTERM (Slurm's warning
    before the time limit, a job being stopped) reach it as SIGUSR1, so that
    lem_fracture writes its checkpoint and exits 4: Open MPI's mpirun passes
    SIGUSR1 on to the ranks, but kills them on SIGTERM and exits 1."""
    with open(log, "w") as f:
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


def tail(path, lines=2):
    """The error lines of a log (else its last lines), without mpirun's boilerplate."""
    try:
        with open(path, errors="replace") as f:
            text = [l.strip() for l in f if l.strip() and not l.startswith("step ")
                    and not l.startswith("---")]
    except OSError:
        return "(no log)"
    boilerplate = ("Process name", "Exit code", "Primary job", "mpirun detected", "a non-zero",
                   "the job to be terminated", "Per user-direction", "process returned")
    text = [l for l in text if not l.startswith(boilerplate)]
    errors = [l for l in text if "error" in l.lower()]
    return " | ".join((errors or text)[-lines:])


def do(args):
    study = Study(args.study_file, args.out, args.bin)
    if args.ranks is not None:
        if args.ranks < 1:
            raise StudyError("--ranks %d is not a positive integer" % args.ranks)
        study.spec["ranks"] = args.ranks
    command, index = args.command, args.index
    study.plan()
    if command in ("samples", "all"):
        study.make_samples(index if command == "samples" else None)
    status = 0
    if command in ("calibrate", "all"):
        status = study.calibrate()
        if status == EXIT_INTERRUPTED:
            return status
    if command in ("run", "all"):
        status = study.run_all(index if command == "run" else None)
    if command == "status":
        counts = study.status()
        status = 0 if counts["complete"] == sum(counts.values()) else 1
    if command in ("gather", "all"):
        status = max(status, gather(study))
    return status


def gather(study):
    """The gather step (study_table), imported here so that the other steps,
    run once per Slurm task, do not load matplotlib."""
    from .study_table import gather as write_table_and_figures

    return write_table_and_figures(study)


def main(argv=None):
    arg_parser = cli.parser(__doc__)
    arg_parser.add_argument("command", choices=COMMANDS, metavar="COMMAND",
                            help="one of: " + ", ".join(COMMANDS) + " (below)")
    arg_parser.add_argument("study_file", metavar="STUDY.yaml", help="the study file")
    arg_parser.add_argument("out", metavar="OUT_DIR", help="the study's output folder")
    arg_parser.add_argument("--index", type=int, metavar="I",
                            help="one sample (samples) or one run (run) by its number")
    arg_parser.add_argument("--ranks", type=int, metavar="N",
                            help="MPI ranks per run (default: the study's `ranks`)")
    arg_parser.add_argument("--bin", metavar="DIR",
                            help="folder of the lem_* programs (default: $LEM_BIN, else "
                                 "build/ of this repository)")
    return cli.run(arg_parser, do, argv)


GATHER_DOC = """Table and figures of a parametric study (the gather step of study.py).

Reads every complete run of the study (summary.json, curve.csv, stress.json)
and writes, in the study's output folder:
  results.csv         one row per complete run
  fit.json            A and k of the strength scaling (eq. 10), beta per rho^m
  figures/strength.png        sigma_eff against sigma^pm (fig. 9) and the
                              collapse of eq. 10 (fig. 12)
  figures/damage.png          n_b against strain (fig. 13), n_b after failure
                              against sigma^pm (fig. 14), grey map of n_b over
                              (rho^m, sigma^pm) (fig. 15), n_b against K_c^r
                              of eq. 14 (fig. 16)
  figures/stiffness_stress.png  E_eff against rho^m (fig. 5) and the tail
                              exponent beta of the node stresses (fig. 8)
Runs that are not complete are listed and left out; the exit status is then 1.
"""


def gather_main(argv=None):
    arg_parser = cli.parser(GATHER_DOC)
    arg_parser.add_argument("study_file", metavar="STUDY.yaml", help="the study file")
    arg_parser.add_argument("out", metavar="OUT_DIR", help="the study's output folder")
    return cli.run(arg_parser, lambda args: gather(Study(args.study_file, args.out)), argv)


if __name__ == "__main__":
    raise SystemExit(main())
