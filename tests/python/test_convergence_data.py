"""The convergence tables of the pages (docs/convergence.md, the fig. 6
table of docs/model/theory.md, docs/paper-void-rule.md) against the
measurements kept in docs/data/convergence-*.csv and the lines
tools/convergence_data.py fits through them.  No simulation is run.

- every per-size cell of a table is the kept value (mean, sd and n where
  the table gives them) at the digits the page quotes, and a cell with a
  dash has no kept row;
- every L_n -> 0 cell (value ± its error, or a slope) is the fitted line's
  at the page's digits, widened by how far the fit moves within the
  rounding of the kept values: most lines were fitted to the runs' full
  digits, which the notes do not keep;
- the section on the paper's resolution quotes the matched sizes and the
  interpolated values the tool computes.
"""
import os
import re

import pytest

from lem_tools import convergence_data as cd
from test_docs_figures import NUMBER, figure, matches

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
SIZES_516 = (1250, 2500, 5000, 10000, 20000)


def page_rows(page):
    """{first cells joined by '|': [cells]} of every table row of a page."""
    with open(os.path.join(ROOT, "docs", page), encoding="utf-8") as f:
        text = f.read()
    rows = []
    for line in text.splitlines():
        if line.startswith("|") and not line.startswith("|---"):
            rows.append([c.strip() for c in line.strip().strip("|").split("|")])
    return rows


def find(rows, *first, width=None):
    """The one row beginning with the cells `first` (of `width` cells)."""
    found = [r for r in rows if tuple(r[:len(first)]) == first
             and (width is None or len(r) == width)]
    assert len(found) == 1, "%d rows start with %s" % (len(found), " | ".join(first))
    return found[0]


def numbers_in(cell):
    return [m.group(0) for m in re.finditer(NUMBER, cell.replace("**", ""))]


def near(quoted, value, slack=0.0):
    q, half = figure(quoted)
    return abs(q - value) <= half * (1 + 1e-9) + slack + 1e-12


def check_point(cell, point, problems, where, with_scatter=False):
    """A per-size cell against a kept point (label, L_n, value, sd, n)."""
    quoted = numbers_in(cell)
    if not quoted:
        problems.append("%s: no number in %r, kept %g" % (where, cell, point[2]))
        return
    if not matches(quoted[0], point[2]):
        problems.append("%s: the page says %s, the data %g" % (where, quoted[0], point[2]))
    if with_scatter:
        if len(quoted) < 3 or not matches(quoted[1], point[3]) or figure(quoted[2])[0] != point[4]:
            problems.append("%s: %r against sd %g of %d" % (where, cell, point[3], point[4]))


def check_line(cell, fitted, problems, where, slope=False):
    """An L_n -> 0 cell, 'x ± e' (or '**x** (slope)' with slope=True)."""
    quoted = numbers_in(cell)
    fit, rounding = fitted["fit"], fitted["rounding"]
    if not near(quoted[0], fit["intercept"], rounding["intercept"]):
        problems.append("%s: L_n -> 0 %s on the page, %.5f (± %.5f from rounding) from the data"
                        % (where, quoted[0], fit["intercept"], rounding["intercept"]))
    second = ("slope", fit["slope"], rounding["slope"]) if slope else \
        ("error", fit["intercept_se"], rounding["intercept_se"])
    if len(quoted) > 1 and not near(quoted[1], second[1], second[2]):
        problems.append("%s: %s %s on the page, %.5f (± %.5f) from the data"
                        % (where, second[0], quoted[1], second[1], second[2]))


@pytest.fixture(scope="module")
def lines():
    return cd.lines()


def by_size(fitted):
    return {int(p[0]): p for p in fitted["points"]}


ELASTIC = {"E_bare/E^[p]": "E_bare_over_Ep", "E_adh/E^[p]": "E_adhesive_over_Ep",
           "ν bare": "nu_bare", "ν adhesive": "nu_adhesive"}


def elastic_rows(lines):
    """(quantity, rho^m, page row, kept line) of the elastic table."""
    rows = page_rows("convergence.md")
    for rho in (0.06, 0.13, 0.28):
        for label, quantity in ELASTIC.items():
            yield (quantity, rho, find(rows, "%g" % rho, label, width=10),
                   lines["elastic-516"][(quantity, rho)])


def test_elastic_table(lines):
    problems = []
    for quantity, rho, row, fitted in elastic_rows(lines):
        points = by_size(fitted)
        assert sorted(points) == list(SIZES_516)
        for column, size in enumerate(SIZES_516, start=2):
            check_point(row[column], points[size], problems, "elastic %s %g %d"
                        % (quantity, rho, size))
        check_line(row[7], fitted, problems, "elastic %s %g" % (quantity, rho))
    assert not problems, "\n".join(problems)


STRENGTH = {("σ_eff/σ^[p]", "1.0"): ("sigma_eff_over_sigma_p", 1.0, True),
            ("σ_eff/σ^[p]", "0.6"): ("sigma_eff_over_sigma_p", 0.6, True),
            ("ε_zz at the peak (10⁻³)", "1.0"): ("strain_at_peak_1e-3", 1.0, False),
            ("ε_zz at the peak (10⁻³)", "0.6"): ("strain_at_peak_1e-3", 0.6, False),
            ("β, off the box faces", "any"): ("beta_off_faces", None, True),
            ("E_eff/E^[p], first step", "any"): ("E_first_step_over_Ep", None, True),
            ("n_b where the run stopped", "1.0"): ("n_b_at_stop", 1.0, False),
            ("n_b where the run stopped", "0.6"): ("n_b_at_stop", 0.6, False),
            ("particle bonds among the broken bonds other than bare contacts", "1.0"):
                ("particle_share_of_non_bare_broken", 1.0, False)}


def test_strength_table(lines):
    rows, problems, seen = page_rows("convergence.md"), [], set()
    for key, fitted in lines["strength-516"].items():
        quantity, rho, ratio = key
        (label, ratio_cell), (_, _, quoted_line) = [
            (k, v) for k, v in STRENGTH.items() if v[0] == quantity and v[1] == ratio][0]
        row = find(rows, label, "%g" % rho, ratio_cell)
        seen.add(tuple(row[:3]))
        points = by_size(fitted)
        for column, size in enumerate(SIZES_516[:4], start=3):
            where = "strength %s %g %s %d" % (quantity, rho, ratio, size)
            if size in points:
                check_point(row[column], points[size], problems, where)
            elif numbers_in(row[column]):
                problems.append("%s: %r on the page, no kept row" % (where, row[column]))
        if quoted_line:
            check_line(row[7], fitted, problems, "strength %s %g %s" % key)
    table = [r for r in rows if len(r) == 8 and (r[0], r[2]) in STRENGTH]
    assert {tuple(r[:3]) for r in table} == seen, "page rows without kept data"
    assert not problems, "\n".join(problems)


SCATTER_ELASTIC = {"E_adhesive/E^[p]": "E_adhesive_over_Ep", "E_bare/E^[p]": "E_bare_over_Ep",
                   "ν adhesive": "nu_adhesive", "ν bare": "nu_bare"}


def test_scatter_tables(lines):
    rows, problems = page_rows("convergence.md"), []
    for rho in (0.13, 0.28):
        for label, quantity in SCATTER_ELASTIC.items():
            row = find(rows, "%g" % rho, label, width=9)
            fitted = lines["scatter-64-elastic"][(quantity, rho)]
            for column, size in enumerate((1250, 2500, 5000), start=2):
                check_point(row[column], by_size(fitted)[size], problems,
                            "scatter %s %g %d" % (quantity, rho, size), with_scatter=True)
            check_line(row[5], fitted, problems, "scatter %s %g" % (quantity, rho))
    replicates = cd.replicates_516()
    labels = {"σ_eff/σ^[p]": "sigma_eff_over_sigma_p",
              "ε_zz at the peak (10⁻³)": "strain_at_peak_1e-3",
              "β, off the box faces": "beta_off_faces",
              "E_eff/E^[p], first step": "E_first_step_over_Ep",
              "n_b (64 p: at 60 % of the peak; 516 p: where the run stopped)": "n_b_at_60pc",
              "n_b (as above)": "n_b_at_60pc"}
    for row in rows:
        if len(row) != 9 or row[0] not in labels:
            continue
        quantity, rho = labels[row[0]], float(row[1])
        fitted = lines["scatter-fracture"][(quantity, rho)]
        where = "scatter %s %g" % (quantity, rho)
        for column, size in ((2, 1250), (3, 2500)):
            quoted = numbers_in(row[column])
            point = by_size(fitted)[size]
            if not (matches(quoted[0], point[2]) and matches(quoted[1], point[3])):
                problems.append("%s %d: %r against %g ± %g" % (where, size, row[column],
                                                                point[2], point[3]))
        if numbers_in(row[4]):
            check_line(row[4], fitted, problems, where)
        kept = replicates[("n_b_at_stop" if quantity == "n_b_at_60pc" else quantity, rho)]
        quoted = numbers_in(row[7])
        if not (near(quoted[0], kept["mean"], kept["mean_rounding"])
                and near(quoted[1], kept["sd"], kept["sd_rounding"]) and len(quoted) == 5
                and all(matches(q, v) for q, v in zip(quoted[2:], kept["values"]))):
            problems.append("%s, 516 p: %r against %s" % (where, row[7], kept))
    assert not problems, "\n".join(problems)


def test_fig6_table(lines):
    rows, problems = page_rows("model/theory.md"), []
    data = cd.read("fig6")
    columns = ("E_stiff_over_Em", "E_pores_any_end_over_Em", "E_pores_both_ends_over_Em")
    for kept in data:
        row = find(rows, "%.4f" % kept["L_n"])
        for column, key in enumerate(("bonds", "E_m_k_over_a") + columns, start=1):
            if not matches(row[column], kept[key]):
                problems.append("fig. 6 L_n %g %s: %s against %g" % (kept["L_n"], key,
                                                                     row[column], kept[key]))
    row = find(rows, "fit: E0 (α_E)")
    for column, key in enumerate(columns, start=3):
        check_line(row[column], lines["fig6"][(key,)], problems, "fig. 6 %s" % key, slope=True)
    assert not problems, "\n".join(problems)


def test_void_rule_table(lines):
    rows, problems = page_rows("paper-void-rule.md"), []
    columns = ("E_bare_any_end_over_Ep", "E_bare_both_ends_over_Ep",
               "E_adhesive_any_end_over_Ep", "E_adhesive_both_ends_over_Ep")
    for kept in cd.read("void-rule"):
        size = "%d" % kept["bonds_per_particle"]
        row = [r for r in rows if r[0].split(" ")[0] == size and r[1] == "%g" % kept["rho_m"]]
        assert len(row) == 1, (size, kept["rho_m"])
        quoted = numbers_in(row[0][2])
        cells = [kept["void_bonds_any_end"], kept["void_bonds_both_ends"]]
        for column, key in enumerate(columns, start=3):
            if not matches(row[0][column], kept[key]):
                problems.append("void rule %s %g %s: %s" % (size, kept["rho_m"], key, row[0][column]))
        if [figure(q)[0] for q in quoted] != cells:
            problems.append("void rule %s %g: void bonds %r" % (size, kept["rho_m"], row[0][2]))
    for rho, first in ((0.06, "line through the three, at L_n = 0"), (0.28, "")):
        row = find(rows, first, "%g" % rho)
        for column, key in enumerate(columns, start=3):
            check_line(row[column], lines["void-rule"][(key, rho)], problems,
                       "void rule %s %g" % (key, rho))
    assert not problems, "\n".join(problems)


def test_interpolation_is_linear_in_l_n_and_stays_within_the_kept_sizes(lines):
    fitted = lines["elastic-516"][("E_bare_over_Ep", 0.28)]
    assert cd.interpolate(fitted, 2500) == pytest.approx(0.3567)
    assert cd.interpolate(fitted, 100) is None
    assert cd.interpolate(fitted, 40000) is None
    midpoint = (cd.l_n(1250 * 516) + cd.l_n(2500 * 516)) / 2
    bpp = midpoint ** -3 / 516
    assert cd.interpolate(fitted, bpp) == pytest.approx((0.3105 + 0.3567) / 2)


def test_the_paper_modules_converged_values_are_the_kept_lines(lines):
    """paper.CONVERGED_MODULI, CONVERGED_FIRST_STEP_MODULI and STRENGTH_516
    (used by the paper figures and eq. 14) at the digits they are written
    with, against the kept rows and their lines."""
    from lem_tools import paper
    problems = []
    for rho, value in paper.CONVERGED_MODULI.items():
        fitted = lines["elastic-516"][("E_bare_over_Ep", rho)]
        if not near(repr(value), fitted["fit"]["intercept"], fitted["rounding"]["intercept"]):
            problems.append("CONVERGED_MODULI %g: %r" % (rho, value))
    for rho, value in paper.CONVERGED_FIRST_STEP_MODULI.items():
        fitted = lines["strength-516"][("E_first_step_over_Ep", rho, None)]
        if not near(repr(value), fitted["fit"]["intercept"], fitted["rounding"]["intercept"]):
            problems.append("CONVERGED_FIRST_STEP_MODULI %g: %r" % (rho, value))
    for size, values in paper.STRENGTH_516.items():
        for rho, value in values.items():
            fitted = lines["strength-516"][("sigma_eff_over_sigma_p", rho, 1.0)]
            if size == 0:
                ok = near(repr(value), fitted["fit"]["intercept"], fitted["rounding"]["intercept"])
            else:
                ok = matches(repr(value), by_size(fitted)[size][2])
            if not ok:
                problems.append("STRENGTH_516 %d %g: %r" % (size, rho, value))
    assert not problems, "\n".join(problems)


def test_the_committed_figures_redraw_byte_for_byte(tmp_path):
    for drawn in cd.draw(str(tmp_path)):
        committed = os.path.join(ROOT, "docs", "figures", os.path.basename(drawn))
        with open(drawn, "rb") as a, open(committed, "rb") as b:
            assert a.read() == b.read(), "%s: run tools/convergence_data.py --figures docs/figures" \
                % os.path.basename(drawn)


def test_elastic_finest_error(lines):
    """The elastic table's "finest error": the finest size against the line at L_n -> 0."""
    problems = []
    for quantity, rho, row, fitted in elastic_rows(lines):
        fit = fitted["fit"]
        error = fitted["points"][-1][2] / fit["intercept"] - 1
        slack = fitted["rounding"]["intercept"] / fit["intercept"]
        if not near(numbers_in(row[8])[0], error, slack):
            problems.append("%s %g: finest error %s, data %.4f" % (quantity, rho, row[8], error))
    assert not problems, "\n".join(problems)


# "Results at a glance": each cell "at 2 500 → at the finest size → at L_n -> 0".
GLANCE = {"E_eff/E^[p], bare contacts": ("elastic-516", "E_bare_over_Ep", ()),
          "E_eff/E^[p], adhesive contacts": ("elastic-516", "E_adhesive_over_Ep", ()),
          "σ_eff/σ^[p]": ("strength-516", "sigma_eff_over_sigma_p", (1.0,)),
          "σ_eff/σ^[p], σ^pm = 0.6 σ^p": ("strength-516", "sigma_eff_over_sigma_p", (0.6,)),
          "β, node-stress tail off the box faces": ("strength-516", "beta_off_faces", (None,))}


def test_results_at_a_glance(lines):
    rows, problems = page_rows("convergence.md"), []
    for label, (table, quantity, rest) in GLANCE.items():
        row = find(rows, label, width=5)
        for column, rho in enumerate((0.06, 0.13, 0.28), start=1):
            key = (quantity, rho) + rest
            if key not in lines[table]:
                assert not numbers_in(row[column]), (label, rho)
                continue
            fitted = lines[table][key]
            quoted = numbers_in(row[column])
            expected = (by_size(fitted)[2500][2], fitted["points"][-1][2])
            if not (matches(quoted[0], expected[0]) and matches(quoted[1], expected[1])):
                problems.append("%s %g: %r against %s" % (label, rho, row[column], expected))
            check_line(quoted[2], fitted, problems, "glance %s %g" % (label, rho))
    assert not problems, "\n".join(problems)
