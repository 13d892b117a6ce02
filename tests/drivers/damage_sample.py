"""Copy a sample file and damage one dataset, for the bad-input tests.

Usage: damage_sample.py SOURCE.h5 TARGET.h5 CASE
       damage_sample.py SOURCE.h5 --all DIR     (DIR/<case>.h5 for every case)

Each case changes one value of a valid sample so that exactly one check of
the reader fails; --list prints the cases.  Indices are chosen away from 0
so that a reader that reports the wrong index is caught.
"""
import argparse
import os
import shutil
import sys

import h5py
import numpy as np

NODE = 17  # the node or bond that is damaged
BOND = 23


def coordinate(value):
    def damage(f):
        f["nodes/coordinates"][NODE, 1] = value
    return damage


def outside_box(f):
    hi = f.attrs["box_hi"]
    f["nodes/coordinates"][NODE, 2] = hi[2] + 1e6


def bond_end_out_of_range(f):
    n = f["nodes/coordinates"].shape[0]
    f["bonds/connectivity"][BOND, 1] = n


def zero_length_bond(f):
    i, j = f["bonds/connectivity"][BOND]
    f["nodes/coordinates"][j] = f["nodes/coordinates"][i]


def duplicate_bond(f):
    f["bonds/connectivity"][BOND] = f["bonds/connectivity"][BOND - 1]


def volume(value):
    def damage(f):
        f["nodes/volume"][NODE] = value
    return damage


def volumes_off(f):
    f["nodes/volume"][NODE] *= 1000  # positive, but the cells no longer tile the box


def bond_phase(f):
    f["bonds/phase"][BOND] = 9


def node_phase(f):
    f["nodes/phase"][NODE] = 7


def stiffness(value):
    def damage(f):
        f["bonds/stiffness"][BOND] = value
    return damage


def swapped_stiffness(f):
    """Bond BOND's stiffness and the node volume table swapped in: values
    that are finite and positive, but not the lattice's stiffness."""
    f["bonds/stiffness"][BOND] = f["nodes/volume"][NODE]


def single_precision_coordinates(f):
    """The coordinates stored as float32, as a careless conversion does."""
    values = f["nodes/coordinates"][...].astype(np.float32)
    del f["nodes/coordinates"]
    f.create_dataset("nodes/coordinates", data=values)


def taller_box(f):
    """The box 1e-9 taller than its nodes: no node lies on the top face."""
    hi = f.attrs["box_hi"].copy()
    hi[2] += 1e-9 * (hi[2] - f.attrs["box_lo"][2]) * 10
    f.attrs["box_hi"] = hi


def resize(f, group, rows):
    """Every dataset of `group` with `rows` rows, chunked and never written:
    the file stays small whatever the count."""
    for name in list(f[group]):
        old = f[group][name]
        shape, dtype = (rows,) + old.shape[1:], old.dtype
        del f[group][name]
        f[group].create_dataset(name, shape=shape, dtype=dtype,
                                chunks=(min(rows, 65536),) + old.shape[1:])


def huge_node_count(f):
    """2**31 + 1 nodes: more displacements than 32-bit PETSc indices number."""
    f.attrs["nodes"] = 2 ** 31 + 1
    resize(f, "nodes", 2 ** 31 + 1)


def huge_bond_count(f):
    """4e9 bonds: more memory than a machine has."""
    f.attrs["bonds"] = 4 * 10 ** 9
    resize(f, "bonds", 4 * 10 ** 9)


CASES = {
    "nan_coordinate": coordinate(np.nan),
    "inf_coordinate": coordinate(np.inf),
    "outside_box": outside_box,
    "bond_end_out_of_range": bond_end_out_of_range,
    "zero_length_bond": zero_length_bond,
    "duplicate_bond": duplicate_bond,
    "nan_volume": volume(np.nan),
    "negative_volume": volume(-0.01),
    "zero_volume": volume(0.0),
    "volumes_off": volumes_off,
    "bad_bond_phase": bond_phase,
    "bad_node_phase": node_phase,
    "nan_stiffness": stiffness(np.nan),
    "negative_stiffness": stiffness(-1.0),
    "swapped_stiffness": swapped_stiffness,
    "single_precision_coordinates": single_precision_coordinates,
    "taller_box": taller_box,
    "huge_node_count": huge_node_count,
    "huge_bond_count": huge_bond_count,
}


def damage(source, target, case):
    shutil.copyfile(source, target)
    with h5py.File(target, "r+") as f:
        CASES[case](f)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source", nargs="?")
    parser.add_argument("target", nargs="?")
    parser.add_argument("case", nargs="?", choices=sorted(CASES))
    parser.add_argument("--all", metavar="DIR", help="write DIR/<case>.h5 for every case")
    parser.add_argument("--list", action="store_true", help="print the cases and stop")
    args = parser.parse_args(argv)
    if args.list:
        print("\n".join(sorted(CASES)))
        return 0
    if args.source and args.all:
        os.makedirs(args.all, exist_ok=True)
        for case in CASES:
            damage(args.source, os.path.join(args.all, case + ".h5"), case)
        return 0
    if not (args.source and args.target and args.case):
        parser.error("SOURCE, TARGET and CASE (or SOURCE --all DIR) are required")
    damage(args.source, args.target, args.case)
    return 0


if __name__ == "__main__":
    sys.exit(main())
