#!/usr/bin/python3
"""Table and figures of a parametric study (tools/study.py gather).

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

Standalone: /usr/bin/python3 tools/study_figures.py STUDY.yaml OUT_DIR
"""
import csv
import json
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

RHO_FILLED = 0.28        # rho_f^m of eqs. 6-10 (paper: pores filled at 0.28)
K_WEAKEST_LINK = 0.4     # eq. 13 frontier of fig. 15
K_DAMAGE_LIMIT = 0.7     # eq. 14 frontier of fig. 15
COLUMNS = ("id", "rho_m", "sigma_pm_ratio", "E_eff_over_E_unit", "sigma_eff_over_sigma_unit",
           "sigma_eff_over_sigma_pm", "strain_at_peak", "n_b", "n_b_without_bare_contacts",
           "broken", "broken_p", "broken_m", "broken_pp", "broken_pm", "K_c_r_eq13",
           "K_c_r_eq14", "beta", "end_reason", "solves", "seconds")


def read_json(path):
    with open(path) as f:
        return json.load(f)


def read_curve(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return (np.array([float(r["strain"]) for r in rows]),
            np.array([float(r["n_b"]) for r in rows]))


def collect(study):
    ph = study.spec["phases"]
    rows, missing = [], []
    for run in study.runs():
        if not study.is_complete(run):
            state = "failed" if os.path.exists(os.path.join(study.run_dir(run), "failed.json")) \
                else "not complete"
            missing.append((run["id"], state))
            continue
        d = study.run_dir(run)
        s = read_json(os.path.join(d, "summary.json"))
        beta = float("nan")
        if os.path.exists(os.path.join(d, "stress.json")):
            tail = read_json(os.path.join(d, "stress.json")).get("tail")
            beta = tail["beta"] if tail else float("nan")
        e_ratio = s["E_eff_over_E_unit"]
        row = dict(id=run["id"], rho_m=run["rho_m"], sigma_pm_ratio=run["sigma_pm_ratio"],
                   E_eff_over_E_unit=e_ratio,
                   sigma_eff_over_sigma_unit=s["sigma_eff_over_sigma_unit"],
                   # eq. 10's left side: both stresses in the units of the phase table.
                   sigma_eff_over_sigma_pm=s["sigma_eff"] / (run["sigma_pm_ratio"] * ph["sigma_p"]),
                   strain_at_peak=s["strain_at_peak"], n_b=s["n_b"],
                   # n_b counts the bare contacts that open at the first step (the
                   # paper's definition); this share leaves them out.
                   n_b_without_bare_contacts=s["broken_p"] / max(1, s["broken"] - s["broken_pp"]),
                   broken=s["broken"],
                   broken_p=s["broken_p"], broken_m=s["broken_m"], broken_pp=s["broken_pp"],
                   broken_pm=s["broken_pm"],
                   # eq. 13: weakest link; eq. 14: reference medium E_eff.
                   K_c_r_eq13=run["sigma_pm_ratio"],
                   K_c_r_eq14=float(np.sqrt(e_ratio * ph["E_p"] / ph["E_pm"]
                                            * run["sigma_pm_ratio"])),
                   beta=beta, end_reason=s["end_reason"], solves=s["solves"],
                   seconds=s["seconds"])
        rows.append(row)
    return rows, missing


def fit_scaling(rows):
    """A, k of eq. 10: sigma_eff / sigma^pm = A rho (2 rho_f - rho) / (1 - k rho)."""
    from scipy.optimize import curve_fit
    rho = np.array([r["rho_m"] for r in rows])
    y = np.array([r["sigma_eff_over_sigma_pm"] for r in rows])
    if len(set(rho)) < 2:
        return None

    def model(r, a, k):
        return a * r * (2 * RHO_FILLED - r) / (1 - k * r)
    try:
        (a, k), _ = curve_fit(model, rho, y, p0=(0.3, 2.5), bounds=([0, -20], [100, 0.99 / rho.max()]))
    except (RuntimeError, ValueError):
        return None
    residual = y - model(rho, a, k)
    return {"A": float(a), "k": float(k), "rho_filled": RHO_FILLED,
            "rms_relative_residual": float(np.sqrt(np.mean((residual / y) ** 2))),
            "points": int(len(rows))}


def by_rho(rows):
    out = {}
    for r in rows:
        out.setdefault(r["rho_m"], []).append(r)
    for v in out.values():
        v.sort(key=lambda r: r["sigma_pm_ratio"])
    return dict(sorted(out.items()))


def save(fig, path):
    tmp = os.path.join(os.path.dirname(path), "." + os.path.basename(path) + ".part")
    fig.savefig(tmp, dpi=100, format="png")
    plt.close(fig)
    os.replace(tmp, path)


def strength_figure(rows, fit, path):
    groups = by_rho(rows)
    colors = plt.cm.viridis(np.linspace(0, 0.9, len(groups)))
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5))
    for c, (rho, rs) in zip(colors, groups.items()):
        x = [r["sigma_pm_ratio"] for r in rs]
        a.plot(x, [r["sigma_eff_over_sigma_unit"] for r in rs], "o-", color=c,
               label=r"$\rho^m$ = %.2f" % rho)
        if fit:
            g = rho * (2 * RHO_FILLED - rho) / (1 - fit["k"] * rho)
            b.plot([g] * len(rs), [r["sigma_eff_over_sigma_pm"] for r in rs], "o", color=c)
    a.set_xlabel(r"$\sigma^{pm} / \sigma^p$")
    a.set_ylabel(r"$\sigma_{\rm eff} / \sigma^{[p]}$")
    a.set_title("(a) tensile strength (paper fig. 9)")
    a.legend(fontsize=8)
    if fit:
        gs = np.linspace(0, b.get_xlim()[1], 10)
        b.plot(gs, fit["A"] * gs, "--", color="black",
               label="eq. 10: A = %.3f, k = %.2f (paper 0.3, 2.5)" % (fit["A"], fit["k"]))
        b.legend(fontsize=8)
    b.set_xlabel(r"$\rho^m (2\rho^m_f - \rho^m) / (1 - k \rho^m)$,  $\rho^m_f$ = %.2f" % RHO_FILLED)
    b.set_ylabel(r"$\sigma_{\rm eff} / \sigma^{pm}$")
    b.set_title("(b) scaling of eq. 10 (paper fig. 12)")
    fig.tight_layout()
    save(fig, path)


def damage_figure(study, rows, path):
    groups = by_rho(rows)
    rhos = list(groups)
    ratios = sorted({r["sigma_pm_ratio"] for r in rows})
    colors = plt.cm.viridis(np.linspace(0, 0.9, len(groups)))
    fig, axes = plt.subplots(2, 2, figsize=(12, 9.5))
    (a, b), (c, d) = axes
    # (a) n_b against strain: the lowest and highest sigma^pm at the largest rho^m,
    # and the highest sigma^pm at the smallest (fig. 13).
    picks = {(rhos[-1], ratios[0]), (rhos[-1], ratios[-1]), (rhos[0], ratios[-1])}
    for r in rows:
        if (r["rho_m"], r["sigma_pm_ratio"]) not in picks:
            continue
        strain, nb = read_curve(os.path.join(study.out, "runs", r["id"], "curve.csv"))
        a.plot(strain * 1e3, nb, label=r"$\rho^m$ = %.2f, $\sigma^{pm}/\sigma^p$ = %.2f"
               % (r["rho_m"], r["sigma_pm_ratio"]))
    a.set_xlabel(r"$\varepsilon_{zz}$ ($\times 10^{-3}$)")
    a.set_ylabel(r"$n_b$")
    a.set_title("(a) particle damage against strain (paper fig. 13)")
    a.legend(fontsize=8)
    for col, (rho, rs) in zip(colors, groups.items()):
        b.plot([r["sigma_pm_ratio"] for r in rs], [r["n_b"] for r in rs], "o-", color=col,
               label=r"$\rho^m$ = %.2f" % rho)
        d.plot([r["K_c_r_eq14"] for r in rs], [r["n_b"] for r in rs], "o", color=col,
               label=r"$\rho^m$ = %.2f" % rho)
    b.set_xlabel(r"$\sigma^{pm} / \sigma^p$")
    b.set_ylabel(r"$n_b$ after failure")
    b.set_title("(b) paper fig. 14")
    b.legend(fontsize=8)
    # (c) grey map over the grid, with the frontiers of eqs. 13 and 14.
    grid = np.full((len(ratios), len(rhos)), np.nan)
    for r in rows:
        grid[ratios.index(r["sigma_pm_ratio"]), rhos.index(r["rho_m"])] = r["n_b"]
    shown = c.pcolormesh(edges(rhos), edges(ratios), grid, cmap="Greys", shading="flat")
    fig.colorbar(shown, ax=c, label=r"$n_b$")
    c.axhline(K_WEAKEST_LINK, ls="--", color="tab:red", label="eq. 13, $K_c^r$ = %.1f"
              % K_WEAKEST_LINK)
    ph = study.spec["phases"]
    e_of_rho = [np.mean([r["E_eff_over_E_unit"] for r in groups[rho]]) for rho in rhos]
    limit = [K_DAMAGE_LIMIT ** 2 * ph["E_pm"] / ph["E_p"] / e for e in e_of_rho]
    c.plot(rhos, limit, ":", color="tab:blue", lw=2, label="eq. 14, $K_c^r$ = %.1f"
           % K_DAMAGE_LIMIT)
    c.set_ylim(edges(ratios)[0], edges(ratios)[-1])
    c.set_xlabel(r"$\rho^m$")
    c.set_ylabel(r"$\sigma^{pm} / \sigma^p$")
    c.set_title("(c) paper fig. 15")
    c.legend(fontsize=8, loc="upper left")
    d.axvline(K_DAMAGE_LIMIT, ls=":", color="tab:blue")
    d.set_xlabel(r"$K_c^r$ (eq. 14)")
    d.set_ylabel(r"$n_b$ after failure")
    d.set_title("(d) paper fig. 16")
    fig.tight_layout()
    save(fig, path)


def edges(values):
    """Cell edges around sorted centres (one cell each)."""
    v = np.asarray(values, dtype=float)
    if len(v) == 1:
        return np.array([v[0] - 0.05, v[0] + 0.05])
    mid = 0.5 * (v[1:] + v[:-1])
    return np.concatenate([[2 * v[0] - mid[0]], mid, [2 * v[-1] - mid[-1]]])


def stiffness_stress_figure(rows, path):
    groups = by_rho(rows)
    rhos = list(groups)
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
    a.plot(rhos, [np.mean([r["E_eff_over_E_unit"] for r in groups[x]]) for x in rhos], "o-")
    a.set_xlabel(r"$\rho^m$")
    a.set_ylabel(r"$E_{\rm eff} / E^{[p]}$")
    a.set_title("(a) effective modulus, bare contacts (paper fig. 5)")
    b.plot(rhos, [groups[x][0]["beta"] for x in rhos], "s-")
    b.set_xlabel(r"$\rho^m$")
    b.set_ylabel(r"tail exponent $\beta$ of eq. 2")
    b.set_title(r"(b) node-stress pdf tail (paper: 0.7 $\to$ 2.1 for 0.06 $\to$ 0.28)")
    fig.tight_layout()
    save(fig, path)


def gather(study):
    rows, missing = collect(study)
    for run_id, state in missing:
        print("gather: %s %s: left out" % (run_id, state))
    if not rows:
        print("gather: no complete run in %s" % study.out)
        return 1
    table = os.path.join(study.out, "results.csv")
    with open(table + ".part", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow(r)
    os.replace(table + ".part", table)
    fit = fit_scaling(rows)
    betas = {"%.4f" % rho: rs[0]["beta"] for rho, rs in by_rho(rows).items()}
    tmp = os.path.join(study.out, "fit.json.part")
    with open(tmp, "w") as f:
        json.dump({"eq10": fit, "beta_by_rho_m": betas, "complete_runs": len(rows),
                   "missing_runs": [m[0] for m in missing]}, f, indent=2)
    os.replace(tmp, os.path.join(study.out, "fit.json"))
    figures = os.path.join(study.out, "figures")
    os.makedirs(figures, exist_ok=True)
    strength_figure(rows, fit, os.path.join(figures, "strength.png"))
    damage_figure(study, rows, os.path.join(figures, "damage.png"))
    stiffness_stress_figure(rows, os.path.join(figures, "stiffness_stress.png"))
    print("gather: %d runs -> %s, fit.json, figures/ (eq. 10: %s)"
          % (len(rows), table, "A = %.3f, k = %.2f" % (fit["A"], fit["k"]) if fit
             else "not fitted: needs two matrix fractions"))
    return 1 if missing else 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import study
    try:
        if len(sys.argv) != 3:
            raise study.StudyError("usage: study_figures.py STUDY.yaml OUT_DIR")
        sys.exit(gather(study.Study(sys.argv[1], sys.argv[2])))
    except study.StudyError as e:
        sys.stderr.write("study_figures.py: error: %s\n" % e)
        sys.exit(1)
