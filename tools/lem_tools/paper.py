"""The paper's own values (Affes et al. 2012, from its text only) that the
figures mark as reference stars, converted to the units of the figures, and
the values of ours at L_n -> 0 that the figures and pages use in place of
values at one resolution; no plotting (plotting.paper_mark draws them)."""

# (quantity, rho^m): (value, unit, where the paper states it).  Unit "E_m": a
# modulus in units of the matrix modulus E^[m]; None: a pure number.
PAPER_VALUES = {
    # sect. 3, fig. 5: E_eff ~ 1.6 E^[m] with bare contacts, 2.5 E^[m] with
    # adhesive ones, at rho^m = 0.28.
    ("E_bare_over_E_unit", 0.28): (1.6, "E_m", "sect. 3"),
    ("E_adhesive_over_E_unit", 0.28): (2.5, "E_m", "sect. 3"),
    # lem_fracture's first-step modulus: the bare contacts (sigma^pp = 0) in
    # tension have opened, as in the paper's fig. 5.
    ("E_eff_over_E_unit", 0.28): (1.6, "E_m", "sect. 3"),
    # sect. 4, fig. 8: the tail exponent of the node-stress pdf (eq. 2).
    ("beta", 0.06): (0.7, None, "sect. 4, fig. 8"),
    ("beta", 0.28): (2.1, None, "sect. 4, fig. 8"),
}


# The paper's sections (its numbering): where each figure and equation of it
# stands, so that a page citing "sect. N, fig. M" can be checked.
PAPER_SECTIONS = {2: {"figs": (1, 2), "eqs": (1,)},
                  3: {"figs": range(3, 7), "eqs": ()},
                  4: {"figs": range(7, 9), "eqs": (2,)},
                  5: {"figs": range(9, 13), "eqs": range(3, 11)},
                  6: {"figs": range(13, 17), "eqs": range(11, 15)}}

# Ours at L_n -> 0: the bare-contact modulus E_eff/E^[p] of the 516-particle
# sample (pack and lattice seed 1, the paper's phases) extrapolated from five
# sizes, 1 250 to 20 000 bonds per particle (lem_stiffness elastic pulls;
# docs/convergence.md, "Elastic moduli at 516 particles").  Not kept as rows
# yet: these are the page's figures, written here once.
CONVERGED_MODULI = {0.06: 0.283, 0.13: 0.380, 0.28: 0.540}
CONVERGED_MODULI_SOURCE = ("516 p, bare contacts, elastic pulls at 1 250–20 000 b/p "
                           "extrapolated to $L_n \\to 0$ (docs/convergence.md)")
# The same sample's first-step modulus (lem_fracture), extrapolated from three
# sizes (1 250, 2 500, 5 000 b/p; same page, "Strength at 516 particles"): a check.
CONVERGED_FIRST_STEP_MODULI = {0.06: 0.25, 0.13: 0.371, 0.28: 0.535}
# sigma_eff/sigma^[p] of that sample at sigma^pm = sigma^p, stopped just past
# the peak, by bonds per particle, and the line in L_n at L_n -> 0 (0 here;
# at rho^m = 0.06 a lower bound), from the same page.
STRENGTH_516 = {1250: {0.06: 0.0949, 0.13: 0.218, 0.28: 0.537},
                2500: {0.06: 0.1159, 0.13: 0.249, 0.28: 0.540},
                5000: {0.06: 0.1362, 0.13: 0.256, 0.28: 0.543},
                0: {0.06: 0.206, 0.13: 0.324, 0.28: 0.552}}


def paper_values(quantity, phases):
    """[(rho^m, value, source, stated)] of the paper's values of `quantity`:
    the value in the figures' units (moduli in E^[p]: the lattice is linear
    in its bond stiffnesses, so E^[m]/E^[p] is the phases' E_m/E_p, by
    default the paper's 1/3), where the paper states it and what it states
    (mathtext, e.g. "1.6 $E^{[m]}$")."""
    e_m_over_e_p = phases.get("E_m", 1.0) / phases.get("E_p", 3.0)
    return [(rho, value * e_m_over_e_p, source, r"%g $E^{[m]}$" % value) if unit == "E_m"
            else (rho, value, source, "%g" % value)
            for (q, rho), (value, unit, source) in sorted(PAPER_VALUES.items()) if q == quantity]


def paper_marks(quantity, rhos, phases):
    """[(rho, value)] of paper_values at the matrix fractions `rhos` of a
    figure (none where the paper gives no value)."""
    return [(rho, value) for r, value, *_ in paper_values(quantity, phases)
            for rho in rhos if abs(rho - r) < 1e-9]


def paper_source(quantity):
    """Where the paper states its values of `quantity` (None: nowhere)."""
    sources = sorted({source for (q, _), (_, _, source) in PAPER_VALUES.items() if q == quantity})
    return "; ".join(sources) or None
