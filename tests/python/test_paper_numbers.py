"""The paper pages (docs/paper.md and the pages split from it) quote the
numbers of the kept studies (docs/data/) as tools/paper_numbers.py computes
them: a page left behind by new rows, or a number written by hand that the
rows do not give, fails here.  No simulation is run.

- QUOTES: phrases of the pages, each with the numbers it quotes; every
  phrase must be on the pages, and each of its numbers must round to the
  computed value at the digits quoted (0.51 means 0.505 to 0.515, 8 % means
  7.5 % to 8.5 %).  Reword a page and its phrase here together.
- The census: on the pages drawn wholly from the kept rows (paper-grid.md,
  paper-analysis.md) and in the cells of paper.md's comparison table that
  quote them (the 64-particle column and the 516-particle line's cells),
  every number must be one a phrase checks, a reference (fig. 5, sect. 3,
  Note 11), a grid coordinate or protocol setting, or one of the paper's
  own values (CENSUS_ALLOWED) - so that a number added by hand without a
  check fails too.
- The generated tables (the 516-particle line, k, eq. 14) are those
  `tools/paper_numbers.py --write` writes from the rows.
- The sections cited beside the paper's figures and equations are the
  paper's (paper.PAPER_SECTIONS)."""
import json
import os
import re

import numpy as np
import pytest

from lem_tools import analysis, convergence_data, paper, paper_numbers
from test_docs_figures import NUMBER, figure, matches

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
PAGES = ("paper.md", "paper-grid.md", "paper-analysis.md", "paper-node-stresses.md",
         "paper-void-rule.md")
FENCE = re.compile(r"^(```|~~~)")


def one_minus(key):
    return lambda n: n[key] - 1


# (id, phrase, {placeholder: number}): `{a}` in a phrase is a figure
# checked against the number named (paper_numbers.numbers), a pair
# (name, scale) compares the figure with the number times scale, a callable
# computes the value from all numbers; `{_}` is a figure left unchecked (a
# value of a study not kept as rows).  Whitespace in the pages counts as
# one space.
QUOTES = [
    # ---- paper-grid.md: the grid at 516 particles
    ("g516 cap", "each to 30 % of its peak with a strain cap of {a} times the peak strain",
     dict(a="g516_strain_cap")),
    ("g516 corner 8 scatter", "the strength lies {a} standard deviations below the mean of the "
     "three 64-particle packings and n_b as the paper counts it {b} above; n_b without the bare "
     "contacts is {c} standard deviations above. The peak comes earlier, at {d} of their peak "
     "strain", dict(a=("g516_sigma_sd_028_140", -1), b="g516_nb_sd_028_140",
                    c="g516_nbw_sd_028_140", d="g516_peak_strain_over_64_028_140")),
    ("g516 corner 8 gain", "{a} more adhesion gives {b} more strength there",
     dict(a="g516_adhesion_step_028_140", b="g516_gain_028_140")),
    ("g516 low rows", "A row at ρ^m = 0.06 takes {a} to {b} minutes on 2 ranks",
     dict(a="g516_006_minutes_min", b="g516_006_minutes_max")),
    ("g516 corner 0", "the strength is {a} above the mean of the 64-particle packings ({b} of "
     "their standard deviations), and the peak comes at {c} of their peak strain",
     dict(a="g516_sigma_over_64_006_020", b="g516_sigma_sd_006_020",
          c="g516_peak_strain_over_64_006_020")),
    ("g516 resolution gain", "the paper's resolution gives +{a} there, +{b} at 0.6 σ^p, +{c} at "
     "ρ^m = 0.13, 1.4 σ^p and {d} at 0.28, 1.4 σ^p; the line gives +{e} at ρ^m = 0.06",
     dict(a="g516_sigma_over_64_006_020", b="g516_sigma_over_64_006_060",
          c="g516_sigma_over_64_013_140", d="g516_sigma_over_64_028_140",
          e="g516_line_over_64_006")),
    # ---- paper-grid.md: the grid
    ("grid lattice", "on a lattice of {a} bonds ({b} bonds per particle, L_n = {c},",
     dict(a="grid_bonds", b="grid_bpp", c="grid_L_n")),
    ("grid particles", "The samples have {a} particles on a lattice", dict(a="grid_particles")),
    ("grid points", "one packing for the {a} grid points", dict(a="grid_points")),
    ("packing runs", "(`jobs/studies/paper-64-packings.yaml`, {a} runs)", dict(a="packings_runs")),
    ("replicated points", "The {a} points with three packings are drawn as their mean with ± one "
     "standard deviation, the other {b} as their one run",
     dict(a="grid_replicated", b="grid_single")),
    ("stop fraction", "until its stress falls below {a} of its peak",
     dict(a="grid_stop_fraction")),
    ("strain cap", "but not beyond {a} times the strain at its peak", dict(a="grid_strain_cap")),
    ("capped runs", "{a} of the {b} runs stop at {c} of their peak; the other {d} stop at the "
     "strain cap with their stress still {e}–{f} of the peak",
     dict(a="grid_stopped", b="grid_runs", c="grid_stop_fraction", d="grid_capped",
          e=("grid_capped_end_min", 100), f="grid_capped_end_max")),
    ("fig 3 peaks", "a peak between {a} and {b} (the paper",
     dict(a=("fig03_peak_min", 1e3), b="fig03_peak_max")),
    ("fig 5 fit", "E_eff/E^[p] = {a} + {b} ρ^m, with the ρ^m = 0.06 point {c} below the line "
     "through the other seven", dict(a="fig05_intercept", b="fig05_slope",
                                     c=("grid_E_gap_006", -1))),
    ("fig 5 at 0.28", "{a} E^[p] = {b} E^[m] at ρ^m = 0.28 against", dict(a="E_028", b="E_m_028")),
    ("fig 8 beta", "β rises with ρ^m from {a} (ρ^m = 0.06) to {b} (0.28)",
     dict(a="beta_006", b="beta_028")),
    ("fig 8 line", "on the 516-particle line below, {a} and {b}.",
     dict(a="line_beta_006", b="line_beta_028")),
    ("fig 9 coating", "reaches {a} σ^[p] at 1.4 σ^p", dict(a="sigma_028_140")),
    ("fig 11", "{a} at ρ^m = 0.06 to {b} at 0.28, below eq. 6", dict(a="Spm_006", b="Spm_028")),
    ("fig 12 points", "Fitted to the {a} grid points", dict(a="grid_points")),
    ("fig 12 fit", "k = {a} (the paper: ≈ 2.5) and A = {b}, relative rms residual {c}.",
     dict(a="eq10_k", b="eq10_A", c="eq10_rms")),
    ("fig 12 lattice units", "the same fit gives A = {a} ± {b}, which",
     dict(a="eq10_lattice_A", b="eq10_lattice_A_se")),
    ("paper's A", "implies ({a}–{b};", dict(a="paper_A_low", b="paper_A_high")),
    ("fig 12 low points", "The ρ^m = 0.06 points lie {a} below the line on average, the other "
     "matrix fractions {b} to +{c};", dict(a=("eq10_low", -1), b=("eq10_others_min", 100),
                                          c="eq10_others_max")),
    ("n_b ratio", "which makes it {a} to {b} times larger",
     dict(a="nb_ratio_min", b="nb_ratio_max")),
    ("figs 13 14", "at 0.8 σ^p from {a} (ρ^m = 0.06) to {b} (0.28), at 1.4 σ^p from {c} to {d};",
     dict(a="nb_006_080", b="nb_028_080", c="nb_006_140", d="nb_028_140")),
    ("onsets", "first broken particle bonds appear at σ^pm/σ^p = {a} for ρ^m ≥ 0.22 ({b} bond "
     "already at 0.2 in one of the three packings at 0.28), {c} for 0.17–0.2 and {d} for "
     "ρ^m ≤ 0.13", dict(a="onset_first_022", b="onset_low_bonds", c="onset_first_017",
                        d="onset_first_006")),
    ("fig 15 low", "(n_b = {a} and {b} at 1.25 and 1.4 σ^p, ρ^m = 0.06;",
     dict(a="nb_006_125", b="nb_006_140")),
    ("fig 15 converged frontier", "frontier falls from σ^pm/σ^p = {a} at ρ^m = 0.06 to {b} at 0.28",
     dict(a="eq14c_frontier_006", b="eq14c_frontier_028")),
    ("fig 16 own", "n_b passes 0.01 at K_c^r = {a} for ρ^m = 0.06 but only at {b} for ρ^m = 0.28",
     dict(a="k14_nb_006", b="k14_nb_028")),
    ("fig 16 own onset", "bonds appear from K_c^r = {a} to {b}.",
     dict(a="onset_k_own_min", b="onset_k_own_max")),
    ("fig 16 converged", "n_b passes 0.01 between K_c^r = {a} (0.06) and {b} (0.28)",
     dict(a="k14c_nb_006", b="k14c_nb_028")),
    ("fig 16 converged onset", "the first particle bonds break between K_c^r = {a} and {b} ({c} "
     "bond of one packing at {d} aside)", dict(a="onset_k_conv_min", b="onset_k_conv_max",
                                              c="onset_low_bonds", d="onset_low_k_conv")),
    ("eq 13 onset", "the onset moves from {a} to {b} as ρ^m grows",
     dict(a="onset_first_006", b="onset_first_028")),
    ("grid run time", "{a} runs of paper-64 took {b} h of run time, {c} s to {d} min a run but "
     "one of {e} min", dict(a=lambda n: n["grid_runs"] - n["packings_runs"], b="grid_hours",
                            c="grid_run_min_s", d="grid_run_max_min", e="grid_run_longest_min")),
    ("packings run time", "the {a} rows of paper-64-packings {b} h",
     dict(a="packings_runs", b="packings_hours")),
    # ---- paper-grid.md: the 516-particle line
    ("line lattice", "line: {a} runs on {b} bonds ({c} bonds per particle, L_n = {d})",
     dict(a="line_runs", b="line_bonds", c="line_bpp", d="line_L_n")),
    ("line stop", "each to {a} of its peak with the same strain cap of {b} times the peak strain",
     dict(a="line_stop_fraction", b="line_strain_cap")),
    ("line run time", "the run's cost ({a} min to {b} h a row on 2 ranks)",
     dict(a="line_run_min_min", b="line_run_max_h")),
    ("increment runs", "σ_eff = {a} σ^[p] at ε_zz = {b} for ρ^m = 0.13 and {c} σ^[p] at {d} for "
     "0.28, where the sample fails in one load step at {e}.",
     dict(a="inc_sigma_013", b="inc_peak_013", c="inc_sigma_028", d="inc_peak_028",
          e="inc_end_strain_028")),
    ("line moduli", "E_eff/E^[p] = {a}, {b}, {c}, {d}, {e}, {f}, {g} and {h} from ρ^m = 0.06 to "
     "0.28 (linear within {i} from 0.1 up, slope {j}; the 0.06 point {k} below that line;",
     dict(a="line_E_006", b="line_E_010", c="line_E_013", d="line_E_017", e="line_E_020",
          f="line_E_022", g="line_E_024", h="line_E_028", i="line_E_gap_max", j="line_E_slope",
          k=("line_E_gap_006", -1))),
    ("line beta n_b k", "β = {a} → {b} (the paper: 0.7 → 2.1), n_b = {c} → {d} as the paper "
     "counts it ({e} → {f} without the bare contacts), and eq. 10 through the eight points "
     "gives k = {g}", dict(a="line_beta_006", b="line_beta_028", c="line_nb_006",
                           d="line_nb_028", e="line_nbw_006", f="line_nbw_028", g="line_k")),
    # ---- paper-analysis.md
    ("bare contacts", "On the 516-particle line they are {a} to {b} of the bonds broken when a "
     "run stops, {c}–{d} of them.", dict(a="line_bare_min", b="line_bare_max",
                                          c=("line_bare_share_min", 100),
                                          d="line_bare_share_max")),
    ("n_b ratio, analysis", "The second is {a} to {b} times the first",
     dict(a="nb_ratio_min", b="nb_ratio_max")),
    ("n_b both ways", "at 1.4 σ^p, n_b is {a} at ρ^m = 0.06 and {b} at 0.28 as the paper counts "
     "it, but {c} and {d} without the bare contacts", dict(a="nb_006_140", b="nb_028_140",
                                                          c="nbw_006_140", d="nbw_028_140")),
    ("vanishing", "{a} at most as the paper counts it",
     dict(a=lambda n: max(v for k, v in n.items() if re.fullmatch(r"nb_006_\d+", k)))),
    ("bare spread", "their number moves by {a} over the line's eight matrix fractions",
     dict(a="line_bare_spread")),
    ("eq 10 units", "A = {a}, k = {b} on the {c} grid points",
     dict(a="eq10_A", b="eq10_k", c="grid_points")),
    ("strength units", "that is {a} times larger at 64 particles ({b} at 516",
     dict(a="grid_strength_unit", b="line_strength_unit")),
    ("eq 10 lattice units", "the same fit gives A = {a} ± {b} and k = {c} ± {d}",
     dict(a="eq10_lattice_A", b="eq10_lattice_A_se", c="eq10_lattice_k", d="eq10_lattice_k_se")),
    ("eq 10 at 0.95", "at σ^pm = 0.95 σ^p alone, A = {a}.", dict(a="eq10_095_lattice_A")),
    ("paper's A derived", "eq. 10's abscissa there is {a} and A = σ_eff/σ^[p] / (1.4 × {b}) = "
     "{c} to {d} for", dict(a="paper_abscissa_028", b="paper_abscissa_028", c="paper_A_low",
                            d="paper_A_high")),
    ("our A inside", "Our {a} is inside that range.", dict(a="eq10_lattice_A")),
    ("A at k = 2.5", "ours is A = {a} (the 64-particle grid) and {b} (the 516-particle line), "
     "{c}–{d} lower", dict(a="grid_fixed_k_A", b="line_fixed_k_A", c=("fixed_k_gap_min", 100),
                           d="fixed_k_gap_max")),
    ("coating strength", "and 1.4 σ^p is {a} σ^[p]", dict(a="sigma_028_140")),
    ("A = 0.3", "A = 0.3 is {a} to {b} times smaller",
     dict(a="paper_A_times_min", b="paper_A_times_max")),
    ("k both", "k is {a} on the 64-particle grid ({b} bonds per particle) and {c} on the "
     "516-particle line ({d}).", dict(a="eq10_k", b="grid_bpp", c="line_k", d="line_bpp")),
    ("k by resolution", "eight times the particles leave k where it is ({a} and {b}); doubling "
     "the bonds per particle lowers it ({c} → {d} → {e} on one sample)",
     dict(a="k_064_1250_three", b="k_516_1250", c="k_516_1250", d="k_516_2500", e="k_516_5000")),
    ("line over grid", "ρ^m: +{a} at 0.06, +{b} at 0.1, +{c} at 0.13, +{d} at 0.17, +{e} at 0.2, "
     "+{f} at 0.22, {g} at 0.24 and {h} at 0.28.",
     {k: one_minus("line_over_grid_%s" % t) for k, t in
      zip("abcdefgh", ("006", "010", "013", "017", "020", "022", "024", "028"))}),
    ("k at L_n 0", "eq. 10 gives k = {a} with a relative rms residual of {b}",
     dict(a="k_516_0", b="k_516_0_rms")),
    ("line hours", "The line at {a} bonds per particle took {b} h",
     dict(a="line_bpp", b="line_hours")),
    ("modulus factors", "the moduli at L_n → 0 are {a} (ρ^m = 0.06), {b} (0.13) and {c} (0.28) "
     "times the grid's", dict(a="E_factor_006", b="E_factor_013", c="E_factor_028")),
    ("converged moduli", "{a}, {b} and {c} E^[p] at ρ^m = 0.06, 0.13 and 0.28, linear",
     dict(a="E_conv_006", b="E_conv_013", c="E_conv_028")),
    ("first-step moduli", "(`CONVERGED_FIRST_STEP_MODULI`): {a}, {b} and {c} E^[p]",
     dict(a="E_first_006", b="E_first_013", c="E_first_028")),
    ("collapse", "over {a}–{b} with the grid's own moduli, and over {c}–{d} with the converged "
     "ones", dict(a="k14_nb_min", b="k14_nb_max", c="k14c_nb_min", d="k14c_nb_max")),
    ("onset, analysis", "between K_c^r = {a} and {b} at every ρ^m, and no point below {c} breaks "
     "one but a single bond of one packing at {d}; with the grid's moduli the onset spreads over "
     "{e}–{f}", dict(a="onset_k_conv_min", b="onset_k_conv_max", c="onset_k_conv_min",
                     d="onset_low_k_conv", e="onset_k_own_min", f="onset_k_own_max")),
    ("onset line", "(σ^pm/σ^p = {a} at ρ^m = 0.06 to {b} at 0.28)",
     dict(a="eq14c_frontier_006", b="eq14c_frontier_028")),
    ("onset step", "{a}–{b} in K_c^r", dict(a="onset_step_min", b="onset_step_max")),
    ("looser", "the collapse is looser ({a}–{b})", dict(a="k14c_nbw_min", b="k14c_nbw_max")),
    # ---- paper.md: the comparison table
    ("line sample", "the kept line's at {a} b/p ({b} bonds,",
     dict(a="line_bpp", b="line_bonds")),
    ("two samples", "σ_eff = {_} and {a} σ^[p] at ρ^m = 0.13, {_} and {b} at 0.28; β = {_} and "
     "{c} at 0.28; the first-step E_eff at 0.28, {_} and {d} E^[p]",
     dict(a="line_sigma_013", b="line_sigma_028", c="line_beta_028", d="line_E_028")),
    ("table beta 0.28", "β ≈ 2.1 at ρ^m = 0.28 (sect. 4, fig. 8) | {a} ± {b} | {_}; {c} (line)",
     dict(a="beta_028", b="beta_sd_028", c="line_beta_028")),
    ("table beta 0.06", "β ≈ 0.7 at ρ^m = 0.06 (sect. 4, fig. 8) | {a} ± {b} | {_}; {c} (line)",
     dict(a="beta_006", b="beta_sd_006", c="line_beta_006")),
    ("table fig 5", "linear: E_eff/E^[p] = {a} + {b} ρ^m; the 0.06 point {c} below the line of "
     "the others | linear from 0.1 up, the 0.06 point {d} below (line)",
     dict(a="fig05_intercept", b="fig05_slope", c=("grid_E_gap_006", -1),
          d=("line_E_gap_006", -1))),
    ("table modulus", "bare contacts, ρ^m = 0.28 (sect. 3, fig. 5) | {a} ± {b} E^[m] | {_} E^[m] | "
     "{c} E^[m]", dict(a="E_m_028", b="E_m_sd_028", c="E_conv_m_028")),
    ("table grows", "(sect. 5, fig. 9) | at all {a} points", dict(a="grid_points")),
    ("table coating", "| {a} ± {b} σ^[p] at 1.4 σ^p |",
     dict(a="sigma_028_140", b="sigma_sd_028_140")),
    ("table peak", "| {a}–{b} at σ^pm = 0.95 σ^p |",
     dict(a=("fig03_peak_min", 1e3), b="fig03_peak_max")),
    ("table eq 10", "| k = {a}; A = {b} with σ^pm a bond threshold, {c} ± {d} in σ^[p] units "
     "(rms residual {e}) (Note 11) | k = {f}, A = {g} in σ^[p] units (line)",
     dict(a="eq10_k", b="eq10_A", c="eq10_lattice_A", d="eq10_lattice_A_se", e="eq10_rms",
          f="line_k", g="line_lattice_A")),
    ("paper's A, table", "the paper's fig. 9 gives {a}–{b})",
     dict(a="paper_A_low", b="paper_A_high")),
    ("table low points", "| {a} below it on average, the other ρ^m {b} to +{c}; the paper's {d} "
     "below (Note 12) | {e} above the line through the other seven ρ^m (line)",
     dict(a=("eq10_low", -1), b=("eq10_others_min", 100), c="eq10_others_max",
          d="paper_low_gap", e="line_low_gap")),
    ("table onsets", "first particle bonds broken at σ^pm/σ^p = {a} (ρ^m ≥ 0.22; {b} bond at 0.2 "
     "in one packing at 0.28), {c} (0.17, 0.2), {d} (≤ 0.13)",
     dict(a="onset_first_022", b="onset_low_bonds", c="onset_first_017", d="onset_first_006")),
    ("table n_b grows", "| {a} ± {b} at ρ^m = 0.28, 1.4 σ^p (Note 14) | {c} → {d} → {e} → {f} → "
     "{g} → {h} → {i} → {j} from ρ^m = 0.06 to 0.28",
     dict(a="nb_028_140", b="nb_sd_028_140", c="line_nb_006", d="line_nb_010",
          e="line_nb_013", f="line_nb_017", g="line_nb_020", h="line_nb_022", i="line_nb_024",
          j="line_nb_028")),
    ("table n_b 0.06", "| {a}, {b} ± {c}, {d} ± {e} at σ^pm = 0.2, 0.8, 1.4 σ^p (Note 15) | {_}; "
     "{f} (line)", dict(a="nb_006_020", b="nb_006_080", c="nb_sd_006_080", d="nb_006_140",
                        e="nb_sd_006_140", f="line_nb_006")),
    ("table eq 14", "n_b passes 0.01 at K_c^r = {a} (ρ^m = 0.06) to {b} (0.28) with the grid's "
     "E_eff (Note 16) | — | with E_eff at L_n → 0 (derived): onset at K_c^r = {c}–{d}, n_b "
     "passes 0.01 at {e}–{f}", dict(a="k14_nb_006", b="k14_nb_028", c="onset_k_conv_min",
                                     d="onset_k_conv_max", e="k14c_nb_min", f="k14c_nb_max")),
    # ---- paper.md: the notes
    ("note 1", "On the grid's ρ^m = 0.13 sample σ_zz^i ranges from {a} to +{b} times",
     dict(a="pdf_min_013", b="pdf_max_013")),
    ("note 3 first packing", "{a} (64 p, the grid's first packing)", dict(a="beta_first_006")),
    ("note 3 grid", "The 64-particle grid (1 250 b/p): {a} ± {b} → {c} → {d} → {e} ± {f} → {g} → "
     "{h} → {i} → {j} ± {k} for ρ^m", dict(
         a="beta_006", b="beta_sd_006", c="beta_010", d="beta_013", e="beta_017",
         f="beta_sd_017", g="beta_020", h="beta_022", i="beta_024", j="beta_028",
         k="beta_sd_028")),
    ("note 3 line", "the 516-particle line (2 521 b/p): {a} → {b} from 0.06 to 0.28",
     dict(a="line_beta_006", b="line_beta_028")),
    ("note 4 converged", "At L_n → 0: {a}, {b} and {c} E^[p]",
     dict(a="E_conv_006", b="E_conv_013", c="E_conv_028")),
    ("note 5", "{a} E^[m] = {b} ± {_} E^[p] at L_n → 0. The paper's value",
     dict(a="E_conv_m_028", b="E_conv_028")),
    ("note 8 at 516", "At 516 particles ({b} b/p) the point itself gives {a} σ^[p]",
     dict(a="g516_sigma_028_140", b="line_bpp")),
    ("note 8 full pores", "was run where they are full: ρ^m = {a} on the same three packings",
     dict(a="coating_rho")),
    ("note 8 coating", "σ_eff = {a} ± {b} σ^[p] at 0.95 σ^p rises to {c} ± {d} σ^[p] at 1.4 σ^p, "
     "still {e} below σ^[p]", dict(a="coating_sigma_095", b="coating_sigma_sd_095",
                                  c="coating_sigma_140", d="coating_sigma_sd_140",
                                  e="coating_below_140")),
    ("table coating 516", "| {a} σ^[p] at 1.4 σ^p (the grid) |", dict(a="g516_sigma_028_140")),
    ("table coating full pores", "{a} ± {b} σ^[p] at full pores, {c} σ^[p] at 516 p (Note 8)",
     dict(a="coating_sigma_140", b="coating_sigma_sd_140", c="coating516_sigma_140")),
    ("note 8 coating 516", "one run on the 516-particle sample at ρ^m = {a}",
     dict(a="coating516_rho")),
    ("note 8 coating 516 voids", "with our bridges is 0.358; ρ^v = {a})",
     dict(a="coating516_rho_v")),
    ("note 8 coating 516 strength", "peaks at {a} σ^[p] at ε = {b}·10⁻³, {c} standard deviations "
     "of the 64-particle packings above their mean, still {d} below σ^[p]",
     dict(a="coating516_sigma_140", b=("coating516_strain_140", 1e3), c="coating516_sd_from_64",
          d="coating516_below_140")),
    ("fig 3 at 0.3", "the eight curves peak at {a}–{b}·10⁻³ with σ_eff = {c}–{d} σ^[p]",
     dict(a=("fig3_030_peak_min", 1e3), b=("fig3_030_peak_max", 1e3), c="fig3_030_sigma_min",
          d="fig3_030_sigma_max")),
    ("fig 3 with contacts", "the peaks lie at {a}–{b}·10⁻³, σ_eff = {c}–{d} σ^[p], {e}–{f} above "
     "the same sample's with bare contacts",
     dict(a=("fig3_pp_peak_min", 1e3), b=("fig3_pp_peak_max", 1e3), c="fig3_pp_sigma_min",
          d="fig3_pp_sigma_max", e=("fig3_pp_gain_min", 100), f="fig3_pp_gain_max")),
    ("note 8", "(1 250 b/p): {a} ± {b} σ^[p] at σ^pm = 1.4 σ^p (three packings)",
     dict(a="sigma_028_140", b="sigma_sd_028_140")),
    ("note 9", "the peak strain grows with σ^pm: {a}–{b} for σ^pm ≥ 0.8 σ^p, {c}–{d} at 0.2.",
     dict(a=("peak_high_min", 1e3), b="peak_high_max", c=("peak_low_min", 1e3),
          d="peak_low_max")),
    ("note 11 grid", "k = {a}, A = {b} with σ^pm the bond threshold σ^φ of the paper's sect. 2.2, "
     "relative rms residual {c}; k = {d}, A = {e} with our fill point",
     dict(a="eq10_k", b="eq10_A", c="eq10_rms", d="eq10_fill_k", e="eq10_fill_A")),
    ("note 11 units", "In σ^[p] units for both stresses, A = {a} ± {b}: the A that the paper's own "
     "statements at ρ^m = 0.28 imply is {c}–{d},", dict(a="eq10_lattice_A", b="eq10_lattice_A_se",
                                                      c="paper_A_low", d="paper_A_high")),
    ("note 11 line", "k = {a} ± {b} (the fit's standard error), A = {c}, relative rms residual "
     "{d} (without 0.06: {e} ± {f}, A = {g}), against k = {h} ± {i}, A = {j} for",
     dict(a="line_k", b="line_k_se", c="line_A", d="line_rms", e="line_k_without_006",
          f="line_k_se_without_006", g="line_A_without_006", h="eq10_095_k",
          i="eq10_095_k_se", j="eq10_095_A")),
    ("note 11 resolution", "particle count ({a} at 516 p and {b} at 64 p, both at 1 250 b/p; {c} "
     "and {d} at 2 500 and 5 000 b/p)", dict(a="k_516_1250", b="k_064_1250_three",
                                              c="k_516_2500", d="k_516_5000")),
    ("note 12", "Ours lie {a} below the fitted line on average, the other matrix fractions {b} to "
     "+{c}", dict(a=("eq10_low", -1), b=("eq10_others_min", 100), c="eq10_others_max")),
    ("note 12 line", "σ_eff/σ^pm = {a}, lies {b} above the eq. 10 line through the seven other "
     "matrix fractions ({c})", dict(a="line_strength_pm_006", b="line_low_gap",
                                    c="line_low_line")),
    ("note 12 grid at 0.95", "put ρ^m = 0.06 {a} below theirs", dict(a=("eq10_095_low", -1))),
    ("note 12 fig 5", "our ρ^m = 0.06 modulus lies {a} (64 p) and {b} (516 p) below the line",
     dict(a=("grid_E_gap_006", -1), b=("line_E_gap_006", -1))),
    ("note 13 one bond", "(one particle bond, n_b = {a})", dict(a="onset_low_nb")),
    ("note 13 onsets", "first broken particle bonds at σ^pm/σ^p = {a} (ρ^m = 0.22, 0.24, 0.28), "
     "{b} (ρ^m = 0.17, 0.2), {c} (ρ^m = 0.06, 0.1, 0.13).",
     dict(a="onset_first_022", b="onset_first_017", c="onset_first_006")),
    ("note 13 in K", "these onsets are {a}–{b} with the grid's E_eff and {c}–{d} with E_eff at",
     dict(a="onset_k_own_min", b="onset_k_own_max", c="onset_k_conv_min",
          d="onset_k_conv_max")),
    ("note 14 grid", "σ^pm = 0.2, 0.8, 1.4 σ^p: {a} → {b} ± {c} → {d} ± {e} (ρ^m = 0.17) and {f} "
     "→ {g} ± {h} → {i} ± {j} (0.28)", dict(
         a="nb_017_020", b="nb_017_080", c="nb_sd_017_080", d="nb_017_140", e="nb_sd_017_140",
         f="nb_028_020", g="nb_028_080", h="nb_sd_028_080", i="nb_028_140", j="nb_sd_028_140")),
    ("note 14 line", "peak): {a}, {b}, {c}, {d}, {e}, {f}, {g} and {h} at ρ^m = 0.06, 0.1,",
     {k: "line_nb_%s" % t for k, t in
      zip("abcdefgh", ("006", "010", "013", "017", "020", "022", "024", "028"))}),
    ("note 14 without", "grid's value at ρ^m = 0.28 and 1.4 σ^p is {a} ± {b}",
     dict(a="nbw_028_140", b="nbw_sd_028_140")),
    ("note 15 grid", "{a} → {b} ± {c} → {d} ± {e} at σ^pm = 0.2, 0.8 and 1.4 σ^p",
     dict(a="nb_006_020", b="nb_006_080", c="nb_sd_006_080", d="nb_006_140",
          e="nb_sd_006_140")),
    ("note 15 line", "{a} at 30 % of the peak, {b} particle bonds of {c} broken",
     dict(a="line_nb_006", b="line_broken_p_006", c="line_broken_006")),
    ("note 15 without", "the grid's value at 1.4 σ^p is {a} ± {b}, and the line's {c}",
     dict(a="nbw_006_140", b="nbw_sd_006_140", c="line_nbw_006")),
    ("note 16 own", "n_b passes 0.01 at K_c^r = {a} at ρ^m = 0.06 and {b} at 0.28",
     dict(a="k14_nb_006", b="k14_nb_028")),
    ("note 16 factors", "That E_eff is {a} (ρ^m = 0.06) to {b} (0.28) times below its value",
     dict(a="E_factor_006", b="E_factor_028")),
    ("note 16 moduli", "({a}, {b}, {c} E^[p] at ρ^m = 0.06, 0.13, 0.28; linear between them)",
     dict(a="E_conv_006", b="E_conv_013", c="E_conv_028")),
    ("note 16 collapse", "n_b passes 0.01 between K_c^r = {a} and {b}, and the first particle "
     "bonds break between {c} and {d},", dict(a="k14c_nb_min", b="k14c_nb_max",
                                              c="onset_k_conv_min", d="onset_k_conv_max")),
    ("separates", "(2.7–2.9, where ours is)", dict()),
    # ---- paper-analysis.md: the paper's resolution matched by node count
    ("res paper", "M ≈ {_} elements with about {a} inside each particle and a roughness "
     "2a/d̄ ≈ {b} (sect. 2.3), and N ≈ {c} nodes (appendix A)",
     dict(a=lambda n: convergence_data.PAPER_P_BONDS_PER_PARTICLE,
          b=lambda n: convergence_data.PAPER_ROUGHNESS, c=lambda n: convergence_data.PAPER_NODES)),
    ("res M/N", "(M/N ≈ {a} there)",
     dict(a=lambda n: convergence_data.PAPER_BONDS / convergence_data.PAPER_NODES)),
    ("res nodes", "({a} nodes per bond at the paper's M, {b} fewer at 10 000 bonds per "
     "particle), so N ≈ {_} is {c} bonds per particle ({d} bonds); the bonds inside a particle "
     "scale with M, so {e} of them is {f}; a scales as L_n, so the paper's roughness is {g} "
     "bonds per particle ({h} bonds; ours at the paper's M is {i})",
     dict(a="res_nodes_per_bond", b="res_node_spread", c="res_nodes", d="res_nodes_bonds",
          e=lambda n: convergence_data.PAPER_P_BONDS_PER_PARTICLE, f="res_particle_bonds",
          g="res_roughness", h="res_roughness_bonds", i="res_our_roughness")),
    ("res beta 0.06", "matched by node count it is {a}, {b} above the paper's {_} where at "
     "2 500 bonds per particle it was {c} below; the paper's value is still one of its "
     "resolution, between our M-matched and N-matched sizes, and {d} at L_n → 0",
     dict(a="res_beta_006_nodes", b=lambda n: n["res_beta_006_nodes"] / 0.7 - 1,
          c=lambda n: 1 - n["res_beta_006_elements"] / 0.7,
          d=lambda n: convergence_data.lines()["strength-516"][
              ("beta_off_faces", 0.06, None)]["fit"]["intercept"])),
    ("res beta 0.28", "{a} by node count, {b} below {_} as at 2 500",
     dict(a="res_beta_028_nodes", b=lambda n: 1 - n["res_beta_028_nodes"] / 2.1)),
    ("res strain", "by node count {a}·10⁻³ at ρ^m = 0.13 and {b}·10⁻³ at 0.28, {c} and {d} "
     "below the paper's ≈ {_}", dict(a="res_strain_013_nodes", b="res_strain_028_nodes",
                                     c=lambda n: 1 - n["res_strain_013_nodes"] / 4,
                                     d=lambda n: 1 - n["res_strain_028_nodes"] / 4)),
    ("res modulus", "(the paper's {_} E^[m] is our converged {a}): by node count {b} E^[m], "
     "by roughness {c}", dict(a=lambda n: 3 * convergence_data.lines()["elastic-516"][
         ("E_bare_over_Ep", 0.28)]["fit"]["intercept"], b="res_E_bare_028_nodes",
         c="res_E_bare_028_roughness")),
]

# The census: what a number on the pages drawn from the rows may be besides
# a checked one.  Grid coordinates and protocol settings; the paper's own
# values; for paper-analysis.md, the figures it quotes from
# docs/convergence.md (runs not kept as rows: named there).
COORDINATES = {"0.06", "0.1", "0.13", "0.17", "0.2", "0.22", "0.24", "0.28", "0.35", "0.5",
               "0.65", "0.8", "0.95", "1.1", "1.25", "1.4", "0.15", "64", "516", "0", "1", "2",
               "3", "1.0"}
THE_PAPERS = {"0.7", "2.1", "1.6", "2.5", "0.3", "0.4", "4·10⁻³", "1.3·10⁶", "2 520", "0.357",
              "0.01", "30 %", "10 %", "1.05", "0.009", "0.023"}
CENSUS_ALLOWED = {
    "paper-grid.md": COORDINATES | THE_PAPERS | {"3 × 3", "0.6", "30 %", "0..8"},
    "paper-analysis.md": COORDINATES | THE_PAPERS | {
        "1 250", "2 500", "5 000", "10 000", "20 000", "22 %", "18 %", "0.5 %", "5", "7 %",
        "3.5 %"},
    "paper.md": COORDINATES | THE_PAPERS | {"92 %", "10⁻⁸", "6·10⁻⁸"},
}
POWER = r"(?<![\d.·])10[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+"    # 10⁻⁸ on its own
REFERENCE = re.compile(r"\b(?:figs?\.|sects?\.|eqs?\.|Notes?|figures|appendix|panel)\s+"
                       r"(?:(?:[A-D]\.)?\d+(?:\.\d+)?(?:–\d+)?(?:\s*\([a-f]\))?"
                       r"(?:,\s*|\s+and\s+|\s+of\s+)?)+", re.IGNORECASE)


# ---------------------------------------------------------------- helpers
@pytest.fixture(scope="module")
def numbers():
    return paper_numbers.numbers()


def read(page):
    with open(os.path.join(ROOT, "docs", page), encoding="utf-8") as f:
        return f.read()


def prose(text):
    """The text outside fenced code blocks and generated blocks, image lines
    and link targets removed, whitespace as single spaces."""
    out, fenced = [], False
    for line in text.splitlines():
        if FENCE.match(line.strip()):
            fenced = not fenced
            continue
        if not fenced and not line.startswith("!["):
            out.append(line)
    text = "\n".join(out)
    text = re.sub(r"<!-- begin: (\w+);.*?<!-- end: \1 -->", " ", text, flags=re.S)
    text = re.sub(r"\]\([^)]*\)", "]", text)          # link targets
    return re.sub(r"\s+", " ", text)


def pattern(phrase):
    """The regular expression of a phrase: its text literal, each {x} a figure."""
    parts = re.split(r"(\{\w+\})", re.sub(r"\s+", " ", phrase))
    out = []
    for part in parts:
        m = re.fullmatch(r"\{(\w+)\}", part)
        if m:
            out.append(NUMBER if m.group(1) == "_" else "(?P<%s>%s)" % (m.group(1), NUMBER))
        else:
            out.append(re.escape(part))
    return "".join(out)


def value(numbers, spec):
    if callable(spec):
        return spec(numbers)
    if isinstance(spec, tuple):
        key, scale = spec
        return numbers[key] * scale
    return numbers[spec]


def quote_problems(numbers, text, where):
    """(problems, the spans of text each phrase covers)."""
    problems, spans = [], []
    for name, phrase, groups in QUOTES:
        for m in re.finditer(pattern(phrase), text):
            spans.append(m.span())
            for group, spec in groups.items():
                quoted = m.group(group)
                expected = value(numbers, spec)
                if expected is None or not matches(quoted, expected):
                    problems.append("%s, %r: the page says %s, the rows give %s"
                                    % (where, name, quoted, expected))
    return problems, spans


def census(text, spans, allowed, where):
    """Numbers of `text` outside `spans`, references and `allowed`."""
    blank = REFERENCE.sub(lambda m: " " * len(m.group(0)), text)
    # code spans (file names, options) hold no quoted figure
    blank = re.sub(r"`[^`]*`", lambda m: " " * len(m.group(0)), blank)
    # dates (of a Measured block) and digits inside names (fig03.png)
    blank = re.sub(r"\b\d{4}-\d{2}-\d{2}\b|\w*[A-Za-z_]\d+\w*",
                   lambda m: " " * len(m.group(0)), blank)
    left = []
    for m in re.finditer(POWER + "|" + NUMBER, blank):
        if any(a <= m.start() and m.end() <= b for a, b in spans):
            continue
        token = m.group(0).strip()
        if token.lstrip("−-") in allowed or token in allowed:
            continue
        # a range a–b: each end on its own
        left.append("%s: %r (…%s…)" % (where, token, text[max(0, m.start() - 40):m.end() + 20]))
    return left


def table_cells(text):
    """The cells of paper.md's comparison table that quote the kept rows:
    the 64-particle column, and the cells of the 516-particle line."""
    cells = []
    for line in text.splitlines():
        if not line.startswith("| ") or line.startswith("| paper (") or line.startswith("|---"):
            continue
        row = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(row) != 5:
            continue
        cells.append((row[0], row[1]))
        cells += [(row[0], c) for c in row[2:] if "(line" in c]
    return cells


# ---------------------------------------------------------------- tests
def test_every_phrase_is_on_the_pages_and_quotes_the_rows(numbers):
    texts = {page: prose(read(page)) for page in PAGES}
    problems, found = [], set()
    for page, text in texts.items():
        bad, _ = quote_problems(numbers, text, page)
        problems += bad
        found |= {name for name, phrase, _ in QUOTES if re.search(pattern(phrase), text)}
    missing = [name for name, _, _ in QUOTES if name not in found]
    assert not missing, "no longer on the paper pages (reword QUOTES with the page): %s" % missing
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("page", ["paper-grid.md", "paper-analysis.md"])
def test_census_of_the_pages_drawn_from_the_rows(numbers, page):
    text = prose(read(page))
    _, spans = quote_problems(numbers, text, page)
    left = census(text, spans, CENSUS_ALLOWED[page], page)
    assert not left, "numbers no phrase of QUOTES checks:\n" + "\n".join(left)


def test_census_of_the_comparison_table(numbers):
    text = read("paper.md")
    table = prose(text)
    _, spans = quote_problems(numbers, table, "paper.md")
    left = []
    for statement, cell in table_cells(text):
        cell_text = re.sub(r"\s+", " ", re.sub(r"\]\([^)]*\)", "]", cell))
        start = table.find(cell_text)
        assert start >= 0, cell_text
        # the cell's numbers, at their place in the page's text
        shifted = [(a - start, b - start) for a, b in spans]
        left += census(cell_text, shifted, CENSUS_ALLOWED["paper.md"], statement[:40])
    assert not left, "numbers of the table no phrase of QUOTES checks:\n" + "\n".join(left)


def test_the_generated_tables_are_those_of_the_rows():
    assert paper_numbers.main(["--check"]) == 0


def test_the_cited_sections_are_the_papers():
    """"(sect. N, fig. M)" and "(sect. N, eq. K)" beside a statement of the
    paper: the figure or equation stands in that section of the paper."""
    problems = []
    for page in PAGES:
        text = prose(read(page))
        for m in re.finditer(r"sect\. (\d)(?:\.\d)?,? (figs?\.|eq\.) (\d+)(?: and (\d+))?", text):
            section, what = int(m.group(1)), "figs" if m.group(2).startswith("fig") else "eqs"
            for n in filter(None, (m.group(3), m.group(4))):
                if int(n) not in paper.PAPER_SECTIONS[section][what]:
                    problems.append("%s: %r: %s %s is not in sect. %d of the paper"
                                    % (page, m.group(0), what[:-1], n, section))
    assert not problems, "\n".join(problems)


def test_the_stated_equalities_hold(numbers):
    """What the pages say in words rather than figures."""
    # "first broken particle bonds at 0.35 for rho^m >= 0.22, 0.5 for 0.17-0.2, 0.65 below"
    assert numbers["onset_first_022"] == numbers["onset_first_024"] == numbers["onset_first_028"]
    assert numbers["onset_first_017"] == numbers["onset_first_020"]
    assert numbers["onset_first_006"] == numbers["onset_first_010"] == numbers["onset_first_013"]
    assert numbers["onset_low_runs"] == 1                  # "in one of the three packings"
    assert numbers["line_capped"] == 0                     # "which no run reached"
    assert numbers["inc_end_strain_028"] - numbers["inc_peak_028"] < 0.05e-3  # "in one load step"


# ---------------------------------------------------------------- the arithmetic
def test_crossing_is_linear_between_grid_points():
    assert analysis.crossing([0.2, 0.4, 0.6], [0.0, 0.005, 0.015], 0.01) == pytest.approx(0.5)
    assert analysis.crossing([0.2, 0.4], [0.02, 0.03], 0.01) == 0.2
    assert analysis.crossing([0.2, 0.4], [0.0, 0.005], 0.01) is None


def test_eq14_thresholds_scale_as_the_root_of_the_modulus():
    """K_c^r of eq. 14 grows as sqrt(E_eff): with every modulus four times
    larger the threshold doubles."""
    phases = {"E_p": 3.0, "E_pm": 1.0}

    class Grid:
        pass
    grid = Grid()
    grid.phases = phases
    grid.points = []
    for ratio, n_b in ((0.5, 0.0), (1.0, 0.02)):
        grid.points.append({"rho_m": 0.1, "sigma_pm_ratio": ratio, "n_b": n_b,
                            "K_c_r_eq14": analysis.k_c_r_eq14(0.05, ratio, phases)})
    own, converged = paper_numbers.eq14_thresholds(grid, moduli={0.0: 0.2, 0.2: 0.2})[0.1]
    # n_b reaches 0.01 halfway between the points, linear in K_c^r
    assert own == pytest.approx(np.mean([p["K_c_r_eq14"] for p in grid.points]))
    assert converged == pytest.approx(2 * own)


def test_converged_moduli_are_interpolated_not_extrapolated():
    moduli = {0.06: 0.283, 0.28: 0.540}
    assert analysis.converged_modulus(0.17, moduli) == pytest.approx((0.283 + 0.540) / 2)
    assert analysis.converged_modulus(0.06, moduli) == 0.283
    assert analysis.converged_modulus(0.3, moduli) is None


def test_the_papers_a_from_its_own_statements():
    """Eq. 10 at rho^m = 0.28, k = 2.5: the abscissa 0.28 * 0.28 / 0.3, and
    sigma_eff = sigma^[p] at sigma^pm = 1.4 sigma^p gives A = 1 / (1.4 x)."""
    (a,) = paper_numbers.paper_a_in_lattice_units(strength=(1.0,))
    assert a == pytest.approx(1 / (1.4 * 0.28 * 0.28 / 0.3))


def test_a_in_lattice_units_is_a_times_the_threshold_over_the_strength():
    """With one calibration, A in sigma^[p] units is the bond-unit A times
    sigma^p / sigma^[p], and k is unchanged."""
    rho = np.repeat([0.06, 0.13, 0.2, 0.28], 2)
    ratio = np.tile([0.5, 1.0], 4)
    unit, sigma_p = 1.8, 0.01
    strength_pm = 5.0 * analysis.eq10_abscissa(rho, 2.0) * (1 + 0.01 * ratio)
    points = [{"rho_m": r, "sigma_pm_ratio": q, "sigma_eff_over_sigma_pm": s,
               "sigma_eff_over_sigma_unit": s * q * sigma_p / (unit * sigma_p)}
              for r, q, s in zip(rho, ratio, strength_pm)]
    bond = analysis.fit_eq10(rho, strength_pm)
    lattice = paper_numbers.eq10_in_lattice_units(points)
    assert lattice["A"] == pytest.approx(bond["A"] / unit, rel=1e-6)
    assert lattice["k"] == pytest.approx(bond["k"], rel=1e-6)


def test_falls_name_the_steps_they_cover():
    curve = {"strain": np.array([1, 2, 3, 4, 6, 7]) * 1e-4,
             "stress_before_norm": np.array([0.1, 0.2, 0.3, 0.29, 0.28, 0.1]),
             "stress_norm": np.array([0.1, 0.2, 0.3, 0.2, 0.27, 0.09]),
             "broken": np.array([0, 0, 10, 40, 60, 100])}
    falls = paper_numbers.falls(curve)
    assert [(f["before"], f["after"], f["bonds"], f["steps"]) for f in falls] == [
        (0.29, 0.2, 30, 1)]
    curve["strain"][3] = 5e-4          # the fall's row two steps after the previous one
    assert paper_numbers.falls(curve)[0]["steps"] == 2
    assert paper_numbers.run_end(curve) == (pytest.approx(0.3), pytest.approx(7 / 3))


@pytest.mark.long  # draws both studies' figures: 10-20 s
@pytest.mark.parametrize("folders, out, beside", [
    (("paper-64", "paper-64-packings"), "paper-64", ()),
    (("paper-516-line",), "paper-516-line", ()),
    (("paper-516-grid", "paper-516-line"), "paper-516-grid", ("paper-64", "paper-64-packings")),
    (("coating-64",), "coating-64", ()), (("fig3-64",), "fig3-64", ()),
    (("fig3-pp-64",), "fig3-pp-64", ())])
def test_the_committed_figures_redraw_byte_for_byte(tmp_path, folders, out, beside):
    """docs/figures/<study>/ is what tools/paper_figures.py draws from the
    committed rows, to the byte (the same packages: matplotlib writes its
    version into the PNGs)."""
    from lem_tools import paper_figures

    def data(names):
        return [os.path.join(ROOT, "docs", "data", f) for f in names]
    drawn = str(tmp_path / out)
    paper_figures.draw_folders(data(folders), drawn, data(beside))
    committed = os.path.join(ROOT, "docs", "figures", out)
    assert sorted(os.listdir(drawn)) == sorted(os.listdir(committed))
    differ = []
    for name in sorted(os.listdir(drawn)):
        with open(os.path.join(drawn, name), "rb") as a, open(os.path.join(committed, name),
                                                              "rb") as b:
            mine, theirs = a.read(), b.read()
        if name == "fit.json":   # the folders as given on the command line aside
            mine, theirs = ({k: v for k, v in json.loads(t).items()
                             if k not in ("folders", "beside")} for t in (mine, theirs))
        if mine != theirs:
            differ.append(name)
    assert not differ, "redraw docs/figures/%s: %s differ" % (out, ", ".join(differ))
