#!/usr/bin/python3
"""The ground springs' energy G of a lem_fracture result, recomputed from its
fields.h5 and summary.json by the rule of docs/model/fracture.md ("Energy
balance"), beside the summary's ground_energy.

Usage: /usr/bin/python3 docs/notes/scripts/ground_energy.py RESULT_DIR
"""
import json
import sys

import h5py
import numpy as np

PHASE_OPTION = {0: "p", 1: "m", 3: "pp", 4: "pm"}  # /bonds/phase codes -> -phase_E_*


def ground_energy(run):
    summary = json.load(open(run + "/summary.json"))
    options = dict(x.split(" ", 1) for x in summary["options"])
    with h5py.File(run + "/fields.h5") as f:
        ends, phase = f["bonds/connectivity"][:], f["bonds/phase"][:]
        u, flags = f["nodes/displacement"][:], f["nodes/dof_flags"][:]
    k = np.array([float(options["-phase_E_" + PHASE_OPTION[p]]) for p in phase])
    k *= summary["mean_bond_length"]
    g = float(options["-lattice_ground_stiffness"]) * 2 * k.sum() / (3 * len(np.unique(ends)))
    free = (flags[:, None] & [1, 2, 4]) == 0
    return 0.5 * g * (u[free] ** 2).sum(), summary["ground_energy"]


if __name__ == "__main__":
    mine, written = ground_energy(sys.argv[1])
    print("recomputed %.10e, summary %.10e, relative difference %.1e"
          % (mine, written, abs(mine - written) / written))
