"""Convergence in the mesh density L_n and scatter between replicates: the
numbers (numpy only, no files, no figures).

A quantity measured at several resolutions ("levels"), with one or more
replicates (packings x lattices) at each, is summarised level by level
(mean, standard deviation of single runs) and fitted by a straight line in
L_n (paper fig. 6), whose intercept is the value extrapolated to L_n -> 0:

- with replicates, the fit is weighted: each level's mean has the variance
  s_i^2 / n_i, with s_i the standard deviation of its n_i runs, or the pooled
  standard deviation of all replicated levels where a level has a single run
  (or replicates that happen to agree exactly);
- the standard errors are those of the weighted least-squares estimate,
  multiplied by sqrt(chi^2 / dof) when that is above 1 (the line does not
  pass within the scatter: the misfit counts as uncertainty);
- without replicates the fit is ordinary least squares and the standard
  errors come from the residuals (none with two levels only).

The resolution at which the replicate scatter exceeds the discretisation
error is given two ways: the coarsest level from which on every level's
single-run scatter is at least its distance to the extrapolated value, and
L_n* = s / |slope| where the fitted line's distance to its intercept equals
the pooled scatter s.
"""
import math

import numpy as np

NAN = float("nan")


def replicate_stats(values):
    """n, mean, standard deviation (ddof 1; NaN for one value), standard
    error of the mean, min and max of the finite `values`."""
    v = np.asarray([x for x in values if x is not None and math.isfinite(x)], dtype=float)
    n = int(v.size)
    if n == 0:
        return {"n": 0, "mean": NAN, "std": NAN, "sem": NAN, "min": NAN, "max": NAN}
    std = float(v.std(ddof=1)) if n > 1 else NAN
    return {"n": n, "mean": float(v.mean()), "std": std,
            "sem": std / math.sqrt(n) if n > 1 else NAN, "min": float(v.min()),
            "max": float(v.max())}


def pooled_std(stats):
    """sqrt(sum (n_i - 1) s_i^2 / sum (n_i - 1)) over the levels with
    replicates (replicate_stats results); NaN if there are none."""
    dof = sum(s["n"] - 1 for s in stats if s["n"] > 1)
    if dof == 0:
        return NAN
    return math.sqrt(sum((s["n"] - 1) * s["std"] ** 2 for s in stats if s["n"] > 1) / dof)


def fit_line(x, y, sigma=None):
    """y = intercept + slope x by least squares, weighted by 1 / sigma^2 if
    `sigma` is given.  Returns intercept, slope, their standard errors, chi^2
    (weighted residuals) and the degrees of freedom, or None with fewer than
    two distinct x.  Sums and scalar arithmetic only (the 2 x 2 normal
    equations solved by hand): a LAPACK solve would make the last digits
    depend on the BLAS numpy loads, and the figures and pages drawn from the
    fits must redraw the same with any (docs/notes/blas.md)."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    if len(set(x.tolist())) < 2:
        return None
    w = np.ones_like(x) if sigma is None else 1.0 / np.asarray(sigma, dtype=float) ** 2
    sw, sx = np.sum(w), np.sum(w * x)
    mean_x, mean_y = sx / sw, np.sum(w * y) / sw
    sxx = np.sum(w * (x - mean_x) ** 2)
    slope = np.sum(w * (x - mean_x) * (y - mean_y)) / sxx
    intercept = mean_y - slope * mean_x
    # the diagonal of the inverse of [[sw, sx], [sx, sum w x^2]]
    inverse = np.array([1.0 / sw + mean_x ** 2 / sxx, 1.0 / sxx])
    residual = y - intercept - slope * x
    chi2 = float(np.sum(w * residual ** 2))
    dof = len(x) - 2
    if sigma is None:
        # the scatter is only known from the residuals
        scale = chi2 / dof if dof > 0 else NAN
    else:
        scale = max(1.0, chi2 / dof) if dof > 0 else 1.0
    se = np.sqrt(inverse * scale)
    return {"intercept": float(intercept), "slope": float(slope),
            "intercept_se": float(se[0]), "slope_se": float(se[1]), "chi2": chi2, "dof": dof,
            "weighted": sigma is not None}


def extrapolate(levels, labels=None):
    """The convergence of one quantity at one point of the grid.

    `levels`: [(L_n, [value of each replicate]), ...] in any order, `labels`
    a name for each (the bond-axis value).  Returns {"levels": per level
    (label, L_n, replicate_stats, scatter: the single-run standard deviation
    used for it, error: mean - extrapolated value),
    "scatter": the pooled standard deviation, "fit": fit_line's result or
    None, "extrapolated", "extrapolated_se", "scatter_from": index into
    "levels" of the coarsest level from which on the scatter is at least the
    discretisation error (None if no such level), "L_n_scatter_dominates":
    scatter / |slope|}.  The levels come back in decreasing L_n (coarse to
    fine)."""
    labels = labels if labels is not None else [None] * len(levels)
    ordered = sorted(((float(l), replicate_stats(v), label)
                      for (l, v), label in zip(levels, labels)), key=lambda e: -e[0])
    ordered = [(l, s, label) for l, s, label in ordered if s["n"] > 0]
    stats = [s for _, s, _ in ordered]
    pooled = pooled_std(stats)
    scatter = [s["std"] if s["n"] > 1 and s["std"] > 0 else pooled for s in stats]
    weighted = math.isfinite(pooled) and pooled > 0
    fit = None
    if len(ordered) >= 2:
        sigma = [sc / math.sqrt(s["n"]) for sc, s in zip(scatter, stats)] if weighted else None
        fit = fit_line([l for l, _, _ in ordered], [s["mean"] for s in stats], sigma)
    value = fit["intercept"] if fit else NAN
    out_levels = [{"label": label, "L_n": l, **s, "scatter": sc, "error": s["mean"] - value}
                  for (l, s, label), sc in zip(ordered, scatter)]
    scatter_from = None
    if fit and math.isfinite(pooled):
        for i in range(len(out_levels) - 1, -1, -1):
            level = out_levels[i]
            if not level["scatter"] >= abs(level["error"]):
                break
            scatter_from = i
    crossing = NAN
    if fit and math.isfinite(pooled):
        crossing = pooled / abs(fit["slope"]) if fit["slope"] != 0 else math.inf
    return {"levels": out_levels, "scatter": pooled, "fit": fit, "extrapolated": value,
            "extrapolated_se": fit["intercept_se"] if fit else NAN,
            "scatter_from": scatter_from, "L_n_scatter_dominates": crossing}


def bonds_of_mesh_density(l_n):
    """M of L_n = M^(-1/3)."""
    return l_n ** -3 if l_n > 0 else math.inf
