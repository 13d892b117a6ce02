"""The paper's quantities computed from results (Affes et al. 2012): the tail
exponent beta of the node stresses (eq. 2), the strength scaling of eq. 10,
the damage criterion K_c^r (eqs. 13, 14), Hashin-Shtrikman estimates.
numpy and scipy only: the figures are drawn elsewhere."""
import warnings

import numpy as np

from .convergence import fit_line, replicate_stats

RHO_FILLED = 0.28        # rho_f^m of eqs. 6-10 (paper: pores filled at 0.28)
K_WEAKEST_LINK = 0.4     # eq. 13 frontier of fig. 15
K_DAMAGE_LIMIT = 0.7     # eq. 14 frontier of fig. 15
TAIL_START = 1.0         # s = sigma_zz^i / sigma_zz where the exponential tail starts
MIN_TAIL_NODES = 20      # fewer nodes in the tail give no meaningful beta
ZZ = 5                   # Tensor6 order xx, xy, xz, yy, yz, zz
PDF_BINS = 80            # bins of the node-stress pdf (fig. 8)
FACE_TOLERANCE = 1e-9    # a node this close to a box face (relative to the side) lies on it


def tail_exponent(s, start=TAIL_START):
    """beta of P(s) ~ exp(-beta s) above `start`: the maximum-likelihood value
    1 / mean(s - start), and a least-squares fit of the log-histogram as a
    check; None when fewer than MIN_TAIL_NODES values lie above `start`."""
    tail = s[s > start] - start
    if tail.size < MIN_TAIL_NODES:
        return None
    beta_ml = 1.0 / tail.mean()
    hist, edges = np.histogram(tail, bins=30, range=(0, np.quantile(tail, 0.99)), density=True)
    centres = 0.5 * (edges[1:] + edges[:-1])
    ok = hist > 0
    slope = fit_line(centres[ok], np.log(hist[ok]))["slope"] if ok.sum() > 3 else float("nan")
    return {"beta": beta_ml, "beta_histogram_fit": -slope, "tail_nodes": int(tail.size),
            "tail_start": start}


def on_box_faces(coords, lo, hi):
    """The nodes that lie on a face of the box (the lattice puts nodes there).
    Their eq. 1 stress is not the material's: the box halves their Voronoi
    cells, while the random lattice keeps the bonds in the faces whole (the
    FCC block halves them), so the faces are a stiffer skin whose nodes read
    about 2.3 times the applied sigma_zz on the lateral faces of a cemented
    sample (docs/paper-node-stresses.md; tests/system/test_elastic.cpp shows
    both cases on an FCC block)."""
    tolerance = FACE_TOLERANCE * float(np.max(hi - lo))
    return np.any((coords - lo < tolerance) | (hi - coords < tolerance), axis=1)


def node_stress_statistics(elastic):
    """What stress.json records about the node stresses of elastic.h5
    (results.read_elastic); s = sigma_zz^i / sigma_zz of the loaded nodes and
    which of them lie on the box faces.  Nodes without any bond (void) carry
    no stress and are left out of s.  beta ("tail") is fitted to the nodes
    off the faces; "tail_all_nodes" is the fit to every loaded node, as
    beta was measured before the face nodes were left out."""
    zz = elastic["stress"][:, ZZ]
    applied = elastic["applied"]
    loaded = np.any(elastic["stress"] != 0, axis=1)
    s = zz[loaded] / applied
    lo, hi = elastic["coords"].min(axis=0), elastic["coords"].max(axis=0)
    on_face = on_box_faces(elastic["coords"][loaded], lo, hi)
    mean_zz = float(np.sum(elastic["volume"] * zz) / np.prod(hi - lo))
    statistics = {
        "applied_stress": applied, "strain": elastic["strain"],
        "volume_average_stress_zz": mean_zz,
        "volume_average_relative_gap": abs(mean_zz / applied - 1),
        "nodes": int(zz.size), "loaded_nodes": int(loaded.sum()),
        "tensile_share": float(np.mean(s > 0)),
        "s_min": float(s.min()), "s_max": float(s.max()),
        "face_nodes": int(on_face.sum()),
        "face_mean_s": float(s[on_face].mean()) if on_face.any() else None,
        "tail": tail_exponent(s[~on_face]),
        "tail_all_nodes": tail_exponent(s),
    }
    return statistics, s, loaded, on_face


def stress_pdf(s, on_face, bins=PDF_BINS):
    """The pdf of `s` over `bins` common bins, split into the nodes off and
    on the box faces (boolean `on_face`), each per loaded node so that the
    two add up to the pdf of all nodes: (edges, inside, faces)."""
    edges = np.histogram_bin_edges(s, bins=bins)
    width = np.diff(edges) * s.size
    return (edges, np.histogram(s[~on_face], bins=edges)[0] / width,
            np.histogram(s[on_face], bins=edges)[0] / width)


def mid_plane_map(coords, values, box_lo, box_hi, pixels=400):
    """The plane y = mid-height in y cut into pixels (`pixels` along the longer
    side), each taking the value of the node nearest to it in 3D; returns the
    image and its extent (x0, x1, z0, z1)."""
    from scipy.spatial import cKDTree

    lx, lz = box_hi[0] - box_lo[0], box_hi[2] - box_lo[2]
    nx = pixels if lx >= lz else max(1, int(pixels * lx / lz))
    nz = pixels if lz >= lx else max(1, int(pixels * lz / lx))
    x = box_lo[0] + (np.arange(nx) + 0.5) * lx / nx
    z = box_lo[2] + (np.arange(nz) + 0.5) * lz / nz
    gx, gz = np.meshgrid(x, z)
    y = 0.5 * (box_lo[1] + box_hi[1])
    points = np.column_stack([gx.ravel(), np.full(gx.size, y), gz.ravel()])
    _, nearest = cKDTree(coords).query(points)
    return values[nearest].reshape(nz, nx), (box_lo[0], box_hi[0], box_lo[2], box_hi[2])


def eq10_abscissa(rho, k, rho_filled=RHO_FILLED):
    """rho (2 rho_f - rho) / (1 - k rho): eq. 10 makes sigma_eff / sigma^pm
    proportional to it."""
    rho = np.asarray(rho, dtype=float)
    return rho * (2 * rho_filled - rho) / (1 - k * rho)


def fit_eq10(rho, strength, rho_filled=RHO_FILLED, errors=False):
    """A and k of eq. 10, sigma_eff / sigma^pm = A rho (2 rho_f - rho) / (1 - k rho),
    fitted to `strength` = sigma_eff / sigma^pm at matrix fractions `rho`,
    rho_f = `rho_filled` (the paper's 0.28 by default); with `errors` also
    the standard errors A_se and k_se of the fit (None with as many points
    as parameters); None with fewer than two distinct fractions.

    Least squares in k alone (A is linear: its best value for each k is a
    ratio of sums), k in [-20, 0.99 / max rho] so that the denominator stays
    positive over the data: the best of a scan, refined by Brent's bounded
    search.  Only sums and scalar arithmetic, no BLAS or LAPACK call, so the
    fit, and the figures and pages drawn from it, are the same bit for bit
    whichever BLAS numpy and scipy load (OpenBLAS or the reference one)."""
    from scipy.optimize import minimize_scalar

    rho = np.asarray(rho, dtype=float)
    strength = np.asarray(strength, dtype=float)
    if len(set(rho.tolist())) < 2:
        return None
    shape = rho * (2 * rho_filled - rho)

    def best_a(k):
        g = shape / (1 - k * rho)
        return min(max(np.sum(strength * g) / np.sum(g * g), 0.0), 100.0), g

    def squares(k):
        a, g = best_a(k)
        return float(np.sum((strength - a * g) ** 2))
    low, high = -20.0, 0.99 / rho.max()
    scan = np.linspace(low, high, 2001)
    i = int(np.argmin([squares(k) for k in scan]))
    bracket = (scan[max(i - 1, 0)], scan[min(i + 1, len(scan) - 1)])
    k = float(minimize_scalar(squares, bounds=bracket, method="bounded",
                              options={"xatol": 1e-13}).x)
    a, g = best_a(k)
    residual = strength - a * g
    fit = {"A": float(a), "k": float(k), "rho_filled": rho_filled,
           "rms_relative_residual": float(np.sqrt(np.mean((residual / strength) ** 2))),
           "points": int(len(rho))}
    if errors:
        fit.update(A_se=None, k_se=None)
        if len(rho) > 2:
            # the covariance of least squares, s^2 (J^T J)^-1, J the model's
            # derivatives in A and k, s^2 the residuals' variance
            da, dk = g, a * g * rho / (1 - k * rho)
            aa, ak, kk = np.sum(da * da), np.sum(da * dk), np.sum(dk * dk)
            s2 = np.sum(residual ** 2) / (len(rho) - 2)
            det = aa * kk - ak * ak
            fit.update(A_se=float(np.sqrt(s2 * kk / det)), k_se=float(np.sqrt(s2 * aa / det)))
    return fit


def eq10_residuals(rho, strength, fit):
    """{rho^m: mean relative residual} of `strength` (sigma_eff / sigma^pm at
    `rho`) from the eq. 10 of `fit`: negative below the line."""
    rho = np.asarray(rho, dtype=float)
    strength = np.asarray(strength, dtype=float)
    line = fit["A"] * eq10_abscissa(rho, fit["k"], fit["rho_filled"])
    return {float(r): float(np.mean(strength[rho == r] / line[rho == r] - 1))
            for r in sorted(set(rho))}


def crossing(x, y, level):
    """The abscissa where the series y(x) (sorted by x) first reaches `level`,
    linear between the grid points on either side; None if it never does,
    x[0] if it starts there."""
    pairs = sorted(zip(x, y))
    for i, (xi, yi) in enumerate(pairs):
        if yi >= level:
            if i == 0:
                return float(xi)
            x0, y0 = pairs[i - 1]
            return float(x0 + (level - y0) / (yi - y0) * (xi - x0))
    return None


def k_c_r_eq14(e_eff_over_e_unit, sigma_pm_ratio, phases):
    """K_c^r of eq. 14, with the sample's E_eff as the reference medium."""
    return float(np.sqrt(e_eff_over_e_unit * phases["E_p"] / phases["E_pm"] * sigma_pm_ratio))


def eq14_frontier(e_eff_over_e_unit, phases, k_c_r=K_DAMAGE_LIMIT):
    """sigma^pm / sigma^p at which K_c^r of eq. 14 equals `k_c_r`."""
    return k_c_r ** 2 * phases["E_pm"] / phases["E_p"] / e_eff_over_e_unit


def converged_modulus(rho, moduli):
    """E_eff/E^[p] at L_n -> 0 at matrix fraction `rho`: `moduli` {rho^m:
    value} where measured, linear between two measured fractions, None
    outside their range (no extrapolation in rho^m)."""
    known = sorted(moduli)
    if not known or rho < known[0] - 1e-9 or rho > known[-1] + 1e-9:
        return None
    return float(np.interp(rho, known, [moduli[r] for r in known]))


def share_without_bare_contacts(broken_p, broken, broken_pp):
    """Share of broken bonds inside the particles, leaving out the bare
    contacts (sigma^pp = 0) that open at the first step; n_b counts them, as
    the paper defines it."""
    return broken_p / max(1, broken - broken_pp)


def group_by_rho(rows):
    """{rho^m: rows sorted by sigma^pm / sigma^p}, in increasing rho^m."""
    groups = {}
    for r in rows:
        groups.setdefault(r["rho_m"], []).append(r)
    for group in groups.values():
        group.sort(key=lambda r: r["sigma_pm_ratio"])
    return dict(sorted(groups.items()))


def replicate_means(rows, columns):
    """One point per (rho^m, sigma^pm / sigma^p) of the runs `rows`, in
    increasing order: each of `columns` the mean over the point's runs (its
    replicates: the samples of other packing and lattice seeds), std[column]
    their standard deviation (0 for a single run), `replicates` the number of
    runs and `runs` their ids.  With one run per point, the points are the
    runs' values."""
    by_point = {}
    for r in rows:
        by_point.setdefault((r["rho_m"], r["sigma_pm_ratio"]), []).append(r)
    points = []
    for (rho, ratio), runs in sorted(by_point.items()):
        point = {"rho_m": rho, "sigma_pm_ratio": ratio, "replicates": len(runs),
                 "runs": [r["id"] for r in runs], "std": {}}
        for column in columns:
            stats = replicate_stats([r[column] for r in runs])
            point[column] = stats["mean"]
            point["std"][column] = stats["std"] if stats["n"] > 1 else 0.0
        points.append(point)
    return points


def sample_means(rows):
    """One point per rho^m of the runs `rows`, as replicate_means gives
    them (sigma_pm_ratio None, `runs` the samples' lattice tags), over the
    samples of that rho^m (one per lattice, the `lattice` of its runs): a
    sample's first-step modulus is the mean over its runs, its beta that of
    its run at the lowest sigma^pm (both of the first equilibrium, before
    any bond but the bare contacts breaks)."""
    samples = {}
    for r in rows:
        samples.setdefault((r["rho_m"], r.get("lattice")), []).append(r)
    per_sample = [{"id": lattice, "rho_m": rho, "sigma_pm_ratio": None,
                   "E_eff_over_E_unit": float(np.mean([r["E_eff_over_E_unit"] for r in runs])),
                   "beta": min(runs, key=lambda r: r["sigma_pm_ratio"])["beta"]}
                  for (rho, lattice), runs in samples.items()]
    return replicate_means(per_sample, ("E_eff_over_E_unit", "beta"))


def hashin_shtrikman(fraction, ratio, nu=0.25):
    """Young's modulus of a two-phase material, normalised by the matrix's:
    Hashin-Shtrikman with the matrix as reference (lower bound for stiffer
    inclusions, upper bound for pores); inclusions of modulus `ratio` times
    the matrix's fill `fraction` of the volume, both of Poisson ratio nu."""
    k1, m1 = 1.0 / (3 * (1 - 2 * nu)), 1.0 / (2 * (1 + nu))
    k2, m2 = ratio * k1, ratio * m1
    f1, f2 = 1 - fraction, fraction

    def inverse(x):
        return float("inf") if x == 0 else 1.0 / x
    k = k1 + f2 / (inverse(k2 - k1) + 3 * f1 / (3 * k1 + 4 * m1))
    m = m1 + f2 / (inverse(m2 - m1) + 6 * f1 * (k1 + 2 * m1) / (5 * m1 * (3 * k1 + 4 * m1)))
    return 9 * k * m / (3 * k + m)
