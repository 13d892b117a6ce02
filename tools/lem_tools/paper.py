"""The paper's own values (Affes et al. 2012, from its text only) that the
figures mark as reference stars, converted to the units of the figures; no
plotting (plotting.paper_mark draws them)."""

# (quantity, rho^m): (value, unit, where the paper states it).  Unit "E_m": a
# modulus in units of the matrix modulus E^[m]; None: a pure number.
PAPER_VALUES = {
    # sect. 5, fig. 5: E_eff ~ 1.6 E^[m] with bare contacts, 2.5 E^[m] with
    # adhesive ones, at rho^m = 0.28.
    ("E_bare_over_E_unit", 0.28): (1.6, "E_m", "sect. 5"),
    ("E_adhesive_over_E_unit", 0.28): (2.5, "E_m", "sect. 5"),
    # lem_fracture's first-step modulus: the bare contacts (sigma^pp = 0) in
    # tension have opened, as in the paper's fig. 5.
    ("E_eff_over_E_unit", 0.28): (1.6, "E_m", "sect. 5"),
    # sect. 4, fig. 8: the tail exponent of the node-stress pdf (eq. 2).
    ("beta", 0.06): (0.7, None, "sect. 4, fig. 8"),
    ("beta", 0.28): (2.1, None, "sect. 4, fig. 8"),
}


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
