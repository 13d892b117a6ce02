"""The figures the fracture pages (docs/model/fracture.md and the pages split
from it, docs/model/fracture-*.md) quote for the main job and the tiny
sample are those of the runs kept as gold (tests/gold/main, tests/gold/tiny:
their summary.json and curve.csv).  A page left behind by a change of the
code, or a gold remade without the pages, fails here; no simulation is run.

Two kinds of quotes are read:
- the table "The figures of the shipped samples" (between its begin and end
  comments): one row per figure, its source in backticks, a cell for the
  main job's reference run and one for tiny ("—": not quoted);
- figures in the prose, found by the phrases in PROSE below.  A phrase that
  is no longer on the pages fails too: reword the pages and this list together.

A quoted figure matches when the gold value rounds to it at the digits quoted
(1 855 is exact, 1.5·10⁻⁷ means 1.45·10⁻⁷ to 1.55·10⁻⁷, 35 % of 0.35)."""
import csv
import glob
import json
import os
import re

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
# The protocol's page and the pages split from it by purpose (decisions,
# solves, the calibration, the load increment): a figure may sit on any.
PAGES = sorted(glob.glob(os.path.join(ROOT, "docs", "model", "fracture*.md")))
GOLD = os.path.join(ROOT, "tests", "gold")
SAMPLES = ("main", "tiny")

# ---------------------------------------------------------------- numbers
SPACES = "  \u2009\u202f\u00a0"  # a space, thin, narrow no-break, no-break
SUPERSCRIPT = str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")
NUMBER = (r"[−-]?(?:\d{1,3}(?:[" + SPACES + r"]\d{3})+|\d+)(?:\.\d+)?"
          r"(?:\s*[·×x]\s*10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+|[eE][−+-]?\d+)?(?:\s*%)?")


def figure(text):
    """(value, half a unit of its last digit) of a figure as the docs write
    it: 1 855 (any space between groups of three), 0.3142785, 1.5·10⁻⁷,
    4·10⁻³, 5.8e-8, 35 %."""
    t = text.strip()
    percent = t.endswith("%")
    t = t.rstrip("%").strip().replace("−", "-")
    exponent = 0
    m = re.match(r"(.*?)\s*[·×x]\s*10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)$", t)
    if m:
        t, exponent = m.group(1), int(m.group(2).translate(SUPERSCRIPT))
    else:
        m = re.match(r"(.*?)[eE]([−+-]?\d+)$", t)
        if m:
            t, exponent = m.group(1), int(m.group(2).replace("−", "-"))
    t = re.sub("[" + SPACES + "]", "", t)
    if not re.fullmatch(r"-?\d+(\.\d+)?", t):
        raise ValueError("not a figure: %r" % text)
    decimals = len(t.partition(".")[2])
    scale = 10.0 ** (exponent - (2 if percent else 0))
    return float(t) * scale, 0.5 * 10.0 ** -decimals * scale


def matches(quoted, value):
    """The figure `quoted` (text) is `value` at the digits it shows."""
    q, half = figure(quoted)
    return abs(q - value) <= half * (1 + 1e-9) + 1e-300


# ---------------------------------------------------------------- the gold
def gold(sample):
    folder = os.path.join(GOLD, sample)
    with open(os.path.join(folder, "summary.json")) as f:
        summary = json.load(f)
    with open(os.path.join(folder, "curve.csv")) as f:
        rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
    return summary, rows


def peak_row(rows):
    return max(rows, key=lambda r: float(r["stress_norm"]))


# Sources a figure can name (the table's "from" column, the prose list):
# each gives the value of one gold run.
SOURCES = {
    "rows of curve.csv": lambda s, c: len(c),
    "steps": lambda s, c: s["steps"],
    "peak step": lambda s, c: int(peak_row(c)["step"]),
    "broken": lambda s, c: s["broken"],
    "broken_p": lambda s, c: s["broken_p"],
    "broken_m": lambda s, c: s["broken_m"],
    "broken_pp": lambda s, c: s["broken_pp"],
    "broken_pm": lambda s, c: s["broken_pm"],
    "n_b": lambda s, c: s["n_b"],
    "active_bonds": lambda s, c: s["active_bonds"],
    "nodes": lambda s, c: s["nodes"],
    "mean_bond_length": lambda s, c: s["mean_bond_length"],
    "sigma_hom": lambda s, c: s["sigma_hom"],
    "E_hom": lambda s, c: s["E_hom"],
    "E_eff": lambda s, c: s["E_eff"],
    "sigma_eff": lambda s, c: s["sigma_eff"],
    "strain_at_peak": lambda s, c: s["strain_at_peak"],
    "final_strain / strain_at_peak": lambda s, c: s["final_strain"] / s["strain_at_peak"],
    "stress_norm at the peak": lambda s, c: float(peak_row(c)["stress_norm"]),
    "stress_norm of the last row / peak":
        lambda s, c: float(c[-1]["stress_norm"]) / float(peak_row(c)["stress_norm"]),
    "work": lambda s, c: s["work"],
    "ground_energy": lambda s, c: s["ground_energy"],
    "ground_energy / work": lambda s, c: s["ground_energy"] / s["work"],
    "energy_balance_error": lambda s, c: s["energy_balance_error"],
}


# ---------------------------------------------------------------- the pages
TABLE_BEGIN = "<!-- begin: figures of the shipped samples"
TABLE_END = "<!-- end -->"

# (id, sample, source, phrase): the phrase's group `v` is a figure of that
# gold run.  Every phrase must be on the pages at least once (whitespace in
# the pages counts as one space).
N = "(?P<v>" + NUMBER + ")"
PROSE = [
    ("a of mini", "main", "mean_bond_length",
     r"`mean_bond_length` prints it \(" + N + r" on `meshes/mini\.h5`"),
    ("bonds in the system", "main", "active_bonds", N + r" of them in the system"),
    ("balance, reference", "main", "energy_balance_error",
     r"with every solve to `-ksp_rtol` \(`-fracture_decision_safety 0`[^)]*\), " + N),
    ("ground share", "main", "ground_energy / work", r"G is " + N + r" of W"),
    ("ranks, ruptures", "main", "broken", r"1 and 2 ranks break the same " + N + r" bonds"),
    ("rtol, ruptures", "main", "broken", r"the main job breaks the same " + N + r" bonds"),
    ("ranks, rows", "main", "rows of curve.csv", N + r" rows of `curve\.csv` on 2 ranks"),
    ("main tail", "main", "final_strain / strain_at_peak",
     r"below 5 % of the peak only at " + N + r" times the strain at the peak"),
    ("tiny tail", "tiny", "stress_norm of the last row / peak",
     r"the tiny sample's is still " + N + r" of the peak at 1\.5 times"),
    ("tiny peak step", "tiny", "peak step",
     r"the pre-peak part needs \S+ solves for " + N + r" increments"),
    ("tiny ruptures", "tiny", "broken", r"\(" + N + r" up to 1\.5 times the peak strain\)"),
    ("tiny balance", "tiny", "energy_balance_error",
     N + r" on the tiny sample to 1\.5 times its peak strain"),
    ("balance, largest", "main", "energy_balance_error",
     r"on the shipped samples at most " + N + r", the main job"),
]


def page_text():
    texts = []
    for page in PAGES:
        with open(page, encoding="utf-8") as f:
            texts.append(f.read())
    return "\n\n".join(texts)


def table_rows(text):
    """(figure, source, {sample: cell}) of the figures table."""
    begin = text.find(TABLE_BEGIN)
    if begin < 0:
        return []
    end = text.find(TABLE_END, begin)
    lines = [ln.strip() for ln in text[begin:end].splitlines() if ln.strip().startswith("|")]
    rows = []
    for line in lines[2:]:  # the header and its rule
        cells = [c.strip() for c in line.strip("|").split("|")]
        name, source, main, tiny = cells[:4]
        rows.append((name, source.strip("`"), {"main": main, "tiny": tiny}))
    return rows


def check(sample, source, quoted, where):
    """Problems (a list) of one quoted figure or list of figures."""
    if source not in SOURCES:
        return ["%s: no gold source %r (known: %s)" % (where, source, ", ".join(SOURCES))]
    summary, curve = gold(sample)
    try:
        value = SOURCES[source](summary, curve)
    except KeyError as e:
        return ["%s: tests/gold/%s has no %s" % (where, sample, e)]
    if not matches(quoted, value):
        return ["%s: the page says %s, tests/gold/%s has %.10g" % (where, quoted, sample, value)]
    return []


# ---------------------------------------------------------------- tests
def test_the_page_has_the_figures_table():
    rows = table_rows(page_text())
    assert rows, "docs/model/fracture*.md have no table starting with %r" % TABLE_BEGIN
    quoted = {(sample, source) for _, source, cells in rows for sample in SAMPLES
              if cells[sample] not in ("—", "-", "")}
    for must in ("rows of curve.csv", "broken", "steps", "energy_balance_error"):
        for sample in SAMPLES:
            assert (sample, must) in quoted, "the table quotes no %s for %s" % (must, sample)


def test_table_figures_are_the_gold():
    problems = []
    for name, source, cells in table_rows(page_text()):
        sources = [s.strip().strip("`") for s in source.split(",")]
        for sample in SAMPLES:
            cell = cells[sample]
            if cell in ("—", "-", ""):
                continue
            values = [v.strip() for v in cell.split(",")]
            if len(values) != len(sources):
                problems.append("%s, %s: %d figures for %d sources" % (name, sample, len(values),
                                                                       len(sources)))
                continue
            for src, v in zip(sources, values):
                problems += check(sample, src, v, "table row %r, %s" % (name, sample))
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("name,sample,source,phrase", PROSE, ids=[p[0] for p in PROSE])
def test_prose_figures_are_the_gold(name, sample, source, phrase):
    text = re.sub(r"\s+", " ", page_text())
    found = list(re.finditer(phrase, text))
    assert found, ("docs/model/fracture*.md no longer quote %r (%s of tests/gold/%s): "
                   "update the pages or PROSE" % (name, source, sample))
    problems = []
    for m in found:
        problems += check(sample, source, m.group("v"), "prose %r" % m.group(0))
    assert not problems, "\n".join(problems)


def test_every_source_reads_the_gold():
    for sample in SAMPLES:
        summary, curve = gold(sample)
        for name, get in SOURCES.items():
            if name in ("sigma_hom", "E_hom") and sample == "tiny":
                continue  # tiny's gold is uncalibrated (0)
            assert get(summary, curve) is not None


def test_figure_rule():
    assert figure("1 855") == (1855.0, 0.5)
    assert figure("1\u2009855")[0] == figure("1\u202f855")[0] == figure("1\u00a0855")[0] == 1855
    v, half = figure("1.5·10⁻⁷")
    assert abs(v - 1.5e-7) < 1e-20 and abs(half - 0.05e-7) < 1e-20
    assert abs(figure("5.8e-8")[0] - 5.8e-8) < 1e-20
    assert abs(figure("35 %")[0] - 0.35) < 1e-12
    assert matches("1.5·10⁻⁷", 1.526e-7) and not matches("2.2·10⁻⁷", 1.526e-7)
    assert matches("0.3142785", 0.3142784659) and not matches("0.3142784", 0.3142784659)
    assert matches("1 855", 1855) and not matches("1 855", 1856)
    assert matches("4·10⁻³", 0.0042) and not matches("4·10⁻³", 0.0046)
    with pytest.raises(ValueError):
        figure("about 3")


# The calibration's step limit, worded once: the same sentence in both pages
# (src/run/fracture_run.cpp gives the calibration FractureOptions{}.max_steps).
CALIBRATION_STEPS = ("The calibration's run is bounded by 10⁶ load steps (the default of "
                     "`-fracture_max_steps`), whatever `-fracture_max_steps` the command "
                     "gives: that option bounds the sample's run only.")


@pytest.mark.parametrize("page", ["model/fracture-calibration.md", "reference/exit-status.md"])
def test_calibration_step_limit_worded_once(page):
    with open(os.path.join(ROOT, "docs", page), encoding="utf-8") as f:
        text = re.sub(r"\s+", " ", f.read())
    assert CALIBRATION_STEPS in text, "docs/%s does not say: %s" % (page, CALIBRATION_STEPS)
