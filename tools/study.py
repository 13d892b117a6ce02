#!/usr/bin/python3
"""Parametric study of Affes et al. (2012): grid of rho^m x sigma^pm tension runs.

Usage: /usr/bin/python3 tools/study.py COMMAND STUDY.yaml OUT_DIR [options]

Commands (each skips what is already complete, so any can be rerun):
  plan       check the study file, record it in OUT_DIR/study.json, list the runs
  samples    build the shared samples, one per matrix fraction (lem_sample)
  calibrate  sigma^[p] and E^[p] on the homogeneous lattice (lem_fracture)
  run        the tension runs (lem_fracture under mpirun); --index I for one
  gather     one table (results.csv) and the paper's figures from complete runs
  status     complete / failed / pending runs
  all        plan, samples, calibrate, run and gather on this machine
Options: --index I (one sample, or one run, by its number), --ranks N (MPI
ranks per run; default: the study's `ranks`), --bin DIR (the lem_* programs;
default build/ next to this script).

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
summary.json exists and its run.json matches the study; an interrupted run
(exit 4, checkpoint written) resumes from its checkpoint when run again.
"""
import hashlib
import json
import os
import signal
import subprocess
import sys

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
KEYS = {"name", "ranks", "sample", "matrix_fractions", "sigma_pm_ratios", "phases", "fracture"}
PHASE_KEYS = {"E_p": 3.0, "E_m": 1.0, "E_pp": 1.0, "E_pm": 1.0, "sigma_p": 0.01}
EXIT_INTERRUPTED = 4  # lem_fracture: checkpoint written after SIGTERM / SIGUSR1


class StudyError(Exception):
    pass


def options_list(d):
    """{name: value} -> ['-name', 'value', ...] (booleans as true/false)."""
    out = []
    for k, v in d.items():
        out += ["-" + k, ("true" if v else "false") if isinstance(v, bool) else str(v)]
    return out


def load_study(path):
    try:
        with open(path) as f:
            s = yaml.safe_load(f)
    except OSError as e:
        raise StudyError("cannot read the study file %s: %s" % (path, e))
    except yaml.YAMLError as e:
        raise StudyError("study file %s is not valid YAML: %s" % (path, e))
    if not isinstance(s, dict):
        raise StudyError("study file %s: expected a mapping of keys" % path)
    unknown = sorted(set(s) - KEYS)
    if unknown:
        raise StudyError("study file %s: unknown key(s) %s (allowed: %s)"
                         % (path, ", ".join(unknown), ", ".join(sorted(KEYS))))
    study = {"name": str(s.get("name", os.path.splitext(os.path.basename(path))[0])),
             "ranks": s.get("ranks", 2), "sample": s.get("sample") or {},
             "fracture": s.get("fracture") or {}}
    if not isinstance(study["ranks"], int) or study["ranks"] < 1:
        raise StudyError("study file %s: ranks must be a positive integer" % path)
    for key in ("sample", "fracture"):
        if not isinstance(study[key], dict):
            raise StudyError("study file %s: %s must be a mapping of options" % (path, key))
    for key, low, high in (("matrix_fractions", 0.0, 0.5), ("sigma_pm_ratios", 0.0, 100.0)):
        values = s.get(key)
        if not isinstance(values, list) or not values:
            raise StudyError("study file %s: %s must be a non-empty list (the grid is empty)"
                             % (path, key))
        for v in values:
            if not isinstance(v, (int, float)) or not low < v <= high:
                raise StudyError("study file %s: %s value %r outside (%g, %g]"
                                 % (path, key, v, low, high))
        if len(set(values)) != len(values):
            raise StudyError("study file %s: %s has repeated values" % (path, key))
        study[key] = [float(v) for v in values]
    phases = dict(PHASE_KEYS)
    given = s.get("phases") or {}
    if not isinstance(given, dict) or set(given) - set(PHASE_KEYS):
        raise StudyError("study file %s: phases accepts only %s"
                         % (path, ", ".join(sorted(PHASE_KEYS))))
    for k, v in given.items():
        if not isinstance(v, (int, float)) or v <= 0:
            raise StudyError("study file %s: phases.%s must be > 0" % (path, k))
        phases[k] = float(v)
    study["phases"] = phases
    reserved = {"matrix_fraction", "output_dir", "output_stem", "sample_file"}
    clash = reserved & (set(study["sample"]) | set(study["fracture"]))
    if clash:
        raise StudyError("study file %s: %s are set by the study itself"
                         % (path, ", ".join(sorted(clash))))
    return study


def study_hash(study):
    text = json.dumps({k: v for k, v in study.items() if k != "ranks"}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


class Study:
    def __init__(self, path, out, bin_dir=None):
        self.spec = load_study(path)
        self.out = out
        self.bin = bin_dir or os.path.join(ROOT, "build")
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
            with open(record) as f:
                old = json.load(f)
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
        path = os.path.join(self.out, "calibration", "summary.json")
        if not os.path.exists(path):
            return None
        with open(path) as f:
            return json.load(f)

    def calibrate(self):
        """sigma^[p], E^[p]: the same lattice (and so the same homogeneous
        lattice) underlies every sample, so one calibration serves them all."""
        if self.calibration():
            print("calibration: complete")
            return
        rho = self.spec["matrix_fractions"][0]
        out_dir = os.path.join(self.out, "calibration")
        os.makedirs(out_dir, exist_ok=True)
        cmd = self.fracture_command(self.sample_file(rho), out_dir,
                                    ["-fracture_max_steps", "1", "-output_fields", "false"])
        print("calibration: " + " ".join(cmd), flush=True)
        log = os.path.join(out_dir, "log")
        if execute(cmd, log) != 0:
            raise StudyError("calibration failed (log: %s): %s" % (log, tail(log)))

    def run_record(self, run):
        return dict(run, study_hash=self.hash, sample=os.path.abspath(
            self.sample_file(run["rho_m"])))

    def is_complete(self, run):
        d = self.run_dir(run)
        try:
            with open(os.path.join(d, "run.json")) as f:
                return (json.load(f) == self.run_record(run)
                        and os.path.exists(os.path.join(d, "summary.json")))
        except (OSError, ValueError):
            return False

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
            subprocess.run([sys.executable, os.path.join(HERE, "plot_stress.py"), d],
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
        statuses = [self.run_one(r) for r in chosen]
        if any(s == EXIT_INTERRUPTED for s in statuses):
            return EXIT_INTERRUPTED
        return 0 if all(s == 0 for s in statuses) else 1

    def status(self):
        counts = {"complete": 0, "failed": 0, "pending": 0}
        for run in self.runs():
            if self.is_complete(run):
                state = "complete"
            elif os.path.exists(os.path.join(self.run_dir(run), "failed.json")):
                state = "failed"
            else:
                state = "pending"
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
    """Run cmd with its output in log; SIGUSR1 / SIGTERM (Slurm's warning
    before the time limit) are passed on to it, so that lem_fracture writes
    its checkpoint."""
    with open(log, "w") as f:
        try:
            proc = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT)
        except OSError as e:
            f.write(str(e) + "\n")
            return 127
        previous = {s: signal.signal(s, lambda number, _: proc.send_signal(number))
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


def write_json(path, data):
    tmp = path + ".part"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=2)
    os.replace(tmp, path)


def main(argv):
    args = argv[1:]
    opts = {"--index": None, "--ranks": None, "--bin": None}
    positional = []
    i = 0
    while i < len(args):
        if args[i] in opts:
            if i + 1 >= len(args):
                raise StudyError("%s needs a value" % args[i])
            opts[args[i]] = args[i + 1]
            i += 2
        elif args[i].startswith("--"):
            raise StudyError("unknown option %s (allowed: %s)" % (args[i], ", ".join(opts)))
        else:
            positional.append(args[i])
            i += 1
    commands = ("plan", "samples", "calibrate", "run", "gather", "status", "all")
    if len(positional) != 3 or positional[0] not in commands:
        raise StudyError("usage: study.py {%s} STUDY.yaml OUT_DIR [--index I] [--ranks N] "
                         "[--bin DIR]" % "|".join(commands))
    command, path, out = positional
    study = Study(path, out, opts["--bin"])
    if opts["--ranks"] is not None:
        try:
            study.spec["ranks"] = int(opts["--ranks"])
        except ValueError:
            study.spec["ranks"] = 0
        if study.spec["ranks"] < 1:
            raise StudyError("--ranks %s is not a positive integer" % opts["--ranks"])
    index = None
    if opts["--index"] is not None:
        try:
            index = int(opts["--index"])
        except ValueError:
            raise StudyError("--index %s is not an integer" % opts["--index"])
    study.plan()
    if command in ("samples", "all"):
        study.make_samples(index if command == "samples" else None)
    if command in ("calibrate", "all"):
        study.calibrate()
    status = 0
    if command in ("run", "all"):
        status = study.run_all(index if command == "run" else None)
    if command == "status":
        counts = study.status()
        status = 0 if counts["complete"] == sum(counts.values()) else 1
    if command in ("gather", "all"):
        import study_figures
        status = max(status, study_figures.gather(study))
    return status


if __name__ == "__main__":
    sys.path.insert(0, HERE)
    try:
        sys.exit(main(sys.argv))
    except StudyError as e:
        sys.stderr.write("study.py: error: %s\n" % e)
        sys.exit(1)
