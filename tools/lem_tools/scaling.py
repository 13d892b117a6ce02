"""Scaling measurements: lem_bench on one sample file at several rank counts.

  scaling.py run SAMPLE OUT_DIR --ranks N [--bench='OPTION ...']
      lem_bench -sample_file SAMPLE -sample_parallel on N ranks (srun inside a
      Slurm allocation, else mpirun; LEM_LAUNCHER, LEM_SRUN, LEM_MPIRUN and
      LEM_BIN as for study.py), its output in OUT_DIR/np<N>.log.
  scaling.py table OUT_DIR
      every OUT_DIR/np<N>.log as one row of OUT_DIR/scaling.csv and of the
      Markdown table OUT_DIR/scaling.md (printed too): set-up, assembly,
      preconditioner and solve times, CG iterations and milliseconds per
      iteration, peak memory per rank (largest and mean), load balance, edge
      cut, and what one CG iteration sends and reduces per rank; the speed-up
      and efficiency of a CG iteration against the fewest ranks measured.

  scaling.py project OUT_DIR [--bonds M ...] [--ranks P ...] [network options]
      a projection of the time of one CG iteration on P ranks for M bonds,
      from the measured rows of OUT_DIR/scaling.csv: the work per bond and
      iteration of the row with the fewest ranks, and the messages, bytes
      and reductions per rank of the row with the most; a rank's messages
      stay as measured, its bytes scale with its subdomain's surface
      ((M/P)^(2/3)), a reduction costs log2(P) latencies.  Prints a
      Markdown table of milliseconds per iteration and of the parallel
      efficiency against 16 ranks (strong scaling) and at a fixed number of
      bonds per rank (weak scaling).

jobs/slurm/scaling.sh submits one Slurm job per rank count and a last one
that writes the table (docs/scaling.md).
"""
import math
import csv
import glob
import os
import re
import shlex
import subprocess

from . import cli
from .errors import ToolError
from .files import require_folder_path
from .study import check_ranks_option, launcher

# Columns of the table: (name, header of the Markdown table, format).
COLUMNS = (
    ("ranks", "ranks", "%d"),
    ("bonds", "bonds", "%.3g"),
    ("setup_s", "set-up s", "%.2f"),
    ("assembly_s", "assembly s", "%.3f"),
    ("pcsetup_s", "PC set-up s", "%.3f"),
    ("its", "CG its", "%d"),
    ("ms_per_it", "ms / it", "%.2f"),
    ("speedup", "speed-up", "%.2f"),
    ("efficiency", "efficiency", "%.2f"),
    ("memory_max_mb", "peak MB (max)", "%.0f"),
    ("memory_mean_mb", "peak MB (mean)", "%.0f"),
    ("balance_nodes", "nodes max/mean", "%.3f"),
    ("edge_cut", "edge cut", "%d"),
    ("messages", "messages / it / rank", "%.1f"),
    ("bytes", "bytes / it / rank", "%.3g"),
    ("reductions", "reductions / it", "%.1f"),
)


def bench_program():
    """lem_bench of LEM_BIN (default: the build/ of this checkout)."""
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    return os.path.join(os.environ.get("LEM_BIN") or os.path.join(root, "build"), "lem_bench")


def run(args):
    check_ranks_option(args.ranks)
    if not os.path.isfile(args.sample):
        raise ToolError("sample file %s does not exist" % args.sample)
    require_folder_path(args.out_dir, "the output folder")
    os.makedirs(args.out_dir, exist_ok=True)
    log = os.path.join(args.out_dir, "np%d.log" % args.ranks)
    try:
        extra = shlex.split(args.bench)
    except ValueError as e:
        raise ToolError("--bench=%r cannot be split into words: %s" % (args.bench, e))
    cmd = launcher(args.ranks) + [bench_program(), "-sample_file", os.path.abspath(args.sample),
                                  "-sample_parallel"] + extra
    with open(log, "w") as f:
        f.write("# " + " ".join(cmd) + "\n")
        f.flush()
        status = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    if status != 0:
        raise ToolError("lem_bench on %d ranks failed (exit %d): see %s" % (args.ranks, status, log))


def _csv_line(text, tag):
    """The values of the line `TAG,...` whose columns the line `# TAG columns: ...` names."""
    names = re.search(r"^# %s columns: ([^\n]*)$" % tag, text, re.M)
    values = re.search(r"^%s,([^\n]*)$" % tag, text, re.M)
    if not names or not values:
        return None
    keys = names.group(1).split(" (")[0].split(",")
    return dict(zip(keys, (float(v) for v in values.group(1).split(","))))


def parse_log(path):
    """One row of the table from a lem_bench log."""
    with open(path) as f:
        text = f.read()
    bench, messages = _csv_line(text, "BENCH"), _csv_line(text, "MESSAGES")
    balance = re.search(r"^balance:  owned nodes max/mean ([0-9.]+), bonds held max/mean "
                        r"([0-9.]+); set-up ([0-9.]+) s$", text, re.M)
    memory = re.search(r"^peak RSS MB: max [0-9.]+; per rank after set-up \[[^]]*\], "
                       r"at end \[([^]]*)\]$", text, re.M)
    cut = re.search(r"^lattice: .*, edge cut ([0-9]+)$", text, re.M)
    if not (bench and messages and balance and memory and cut):
        raise ToolError("%s is not a complete lem_bench log (the run failed or is going on)"
                        % path)
    per_rank = [float(v) for v in memory.group(1).replace(",", " ").split()]
    return {
        "ranks": int(bench["ranks"]), "bonds": bench["bonds"],
        "setup_s": float(balance.group(3)), "assembly_s": bench["assembly_s"],
        "pcsetup_s": bench["pcsetup_rep_s"], "its": int(bench["its_rep"]),
        "ms_per_it": bench["ms_per_it"], "memory_max_mb": max(per_rank),
        "memory_mean_mb": sum(per_rank) / len(per_rank),
        "balance_nodes": float(balance.group(1)), "edge_cut": int(cut.group(1)),
        "messages": messages["messages_mean"], "bytes": messages["bytes_mean"],
        "reductions": messages["reductions"],
    }


def table(args):
    logs = sorted(glob.glob(os.path.join(args.out_dir, "np*.log")))
    if not logs:
        raise ToolError("no np<N>.log in %s: run `scaling.py run` first" % args.out_dir)
    rows = sorted((parse_log(p) for p in logs), key=lambda r: r["ranks"])
    base = rows[0]
    for r in rows:
        # Speed-up of a CG iteration over the fewest ranks measured, and
        # its efficiency (1: the time falls as the ranks grow).
        r["speedup"] = base["ms_per_it"] / r["ms_per_it"]
        r["efficiency"] = r["speedup"] * base["ranks"] / r["ranks"]
    with open(os.path.join(args.out_dir, "scaling.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([c[0] for c in COLUMNS])
        for r in rows:
            w.writerow([r[c[0]] for c in COLUMNS])
    lines = ["| " + " | ".join(c[1] for c in COLUMNS) + " |",
             "|" + "---|" * len(COLUMNS)]
    for r in rows:
        lines.append("| " + " | ".join(c[2] % r[c[0]] for c in COLUMNS) + " |")
    text = "\n".join(lines) + "\n"
    with open(os.path.join(args.out_dir, "scaling.md"), "w") as f:
        f.write(text)
    print(text, end="")


def projection(rows, bonds, ranks, latency, bandwidth, reduction_latency):
    """Seconds per CG iteration on `ranks` ranks for `bonds` bonds (see the
    module's help); `rows` are rows of scaling.csv."""
    work = min(rows, key=lambda r: r["ranks"])
    talk = max(rows, key=lambda r: r["ranks"])
    per_bond = work["ms_per_it"] * 1e-3 * work["ranks"] / work["bonds"]
    surface = (bonds / ranks / (talk["bonds"] / talk["ranks"])) ** (2.0 / 3.0)
    compute = per_bond * bonds / ranks
    messages = talk["messages"] * latency + talk["bytes"] * surface / bandwidth
    reductions = talk["reductions"] * math.log2(max(ranks, 2)) * reduction_latency
    return compute + messages + reductions


def read_rows(out_dir):
    path = os.path.join(out_dir, "scaling.csv")
    if not os.path.isfile(path):
        raise ToolError("no %s: run `scaling.py table` first" % path)
    with open(path) as f:
        return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(f)]


def project(args):
    rows = read_rows(args.out_dir)
    net = (args.latency, args.bandwidth, args.reduction_latency)
    lines = ["Network: %.1f us per message, %.3g GB/s per rank, %.1f us per reduction stage."
             % (args.latency * 1e6, args.bandwidth / 1e9, args.reduction_latency * 1e6), "",
             "| bonds | " + " | ".join("%d ranks" % p for p in args.ranks) + " |",
             "|---|" + "---|" * len(args.ranks)]
    for m in args.bonds:
        base = projection(rows, m, args.ranks[0], *net) * args.ranks[0]
        cells = []
        for p in args.ranks:
            t = projection(rows, m, p, *net)
            cells.append("%.3g ms (%.0f%%)" % (1e3 * t, 100 * base / (t * p)))
        lines.append("| %.3g | %s |" % (m, " | ".join(cells)))
    per_rank = args.weak_bonds_per_rank
    weak = [projection(rows, per_rank * p, p, *net) for p in args.ranks]
    lines += ["", "Weak scaling, %.3g bonds per rank: " % per_rank +
              ", ".join("%d ranks %.3g ms (%.0f%%)" % (p, 1e3 * t, 100 * weak[0] / t)
                        for p, t in zip(args.ranks, weak))]
    text = "\n".join(lines) + "\n"
    print(text, end="")


def main(argv=None):
    p = cli.parser(__doc__)
    sub = p.add_subparsers(dest="what", required=True)
    q = sub.add_parser("run", help="lem_bench on one rank count")
    q.add_argument("sample", metavar="SAMPLE")
    q.add_argument("out_dir", metavar="OUT_DIR")
    q.add_argument("--ranks", type=int, required=True)
    q.add_argument("--bench", default="", metavar="'OPTION ...'",
                   help="more options of lem_bench, as one word: --bench='-bench_repeat 1'")
    q.set_defaults(func=run)
    q = sub.add_parser("table", help="the table of every np<N>.log")
    q.add_argument("out_dir", metavar="OUT_DIR")
    q.set_defaults(func=table)
    q = sub.add_parser("project", help="a projection of the table to a cluster")
    q.add_argument("out_dir", metavar="OUT_DIR")
    q.add_argument("--bonds", type=float, nargs="+", default=[1.3e6, 1e7, 1e8, 1e9])
    q.add_argument("--ranks", type=int, nargs="+", default=[16, 64, 256, 1024])
    q.add_argument("--weak-bonds-per-rank", type=float, default=1e6)
    q.add_argument("--latency", type=float, default=1.5e-6,
                   help="seconds per point-to-point message (default: an InfiniBand network)")
    q.add_argument("--bandwidth", type=float, default=10e9,
                   help="bytes per second a rank sends (default 10 GB/s)")
    q.add_argument("--reduction-latency", type=float, default=2e-6,
                   help="seconds per stage of a reduction tree (default 2 us)")
    q.set_defaults(func=project)
    return cli.run(p, lambda args: args.func(args), argv)
