"""The resolution and replicate axes of a study file, and the lattices they
expand into.

A study without these keys has one lattice (the one its `sample` options
give) and keeps the layout, run ids and results it always had.  With them,
every matrix fraction is built on every lattice of

  lattice_bonds: [M, ...]                  or  lattice_bonds_per_particle: [m, ...]
                                              (-lattice_bonds = m x sample_particles)
  pack_seeds: [s, ...]                     -pack_seed of lem_sample
  lattice_seeds: [s, ...]                  -lattice_seed of lem_sample
  replicates_up_to: v                      a value of the bond axis: every
                                           pack x lattice seed pair up to it,
                                           the first pair only above it
  fracture_up_to: v                        a value of the bond axis: the
                                           fracture runs up to it only (the
                                           larger lattices get the elastic pulls)
  elastic: true                            pull every sample elastically too
                                           (lem_tension: E_eff and nu, bare and
                                           adhesive contacts)

The mesh density of a lattice is the paper's L_n = M^(-1/3), M its number of
bonds (as lem_sample reports it; docs/model/theory.md).
"""
import math

BOND_AXES = ("lattice_bonds", "lattice_bonds_per_particle")
SEED_AXES = {"pack_seeds": "pack_seed", "lattice_seeds": "lattice_seed"}
LEVEL_KEYS = ("replicates_up_to", "fracture_up_to")
AXIS_KEYS = set(BOND_AXES) | set(SEED_AXES) | set(LEVEL_KEYS) | {"elastic"}
# Keys that choose which lattices and runs of the grid are made, not what a
# run gives: left out of the study's hash, so that raising them extends a
# study in its folder.
SUBSET_KEYS = ("replicates_up_to", "fracture_up_to")
# The sample options each axis sets (given both ways, the study would be ambiguous).
SIZE_OPTIONS = ("lattice_bonds", "lattice_nodes", "lattice_Ln")
DEFAULT_SAMPLE_PARTICLES = 516       # lem_sample's -sample_particles default
MAX_BONDS = 200_000_000              # what a lattice of the code may have, about
MAX_SEED = 2147483647                # -pack_seed and -lattice_seed


def is_number(value):
    """A finite int or float; YAML's true/false are bools, which Python would
    otherwise take for 1 and 0."""
    return (isinstance(value, (int, float)) and not isinstance(value, bool)
            and math.isfinite(value))


def is_integer(value):
    return isinstance(value, int) and not isinstance(value, bool)


def read_list(s, key, good, kind, bad):
    """s[key] checked: a non-empty list without repeats whose values all pass
    `good` (else the error names the first bad one and `kind`)."""
    values = s[key]
    if not isinstance(values, list) or not values:
        raise bad("%s must be a non-empty list", key)
    for v in values:
        if not good(v):
            raise bad("%s value %r is not %s", key, v, kind)
    if len(set(values)) != len(values):
        raise bad("%s has repeated values", key)
    return list(values)


def read_axes(s, sample, bad):
    """The axis keys of study file `s` checked, as a dict to merge into the
    study (only the keys that are given: a study without them stays as it
    was); `sample` is the study's sample mapping, `bad(message, *args)`
    makes the error to raise."""
    axes = {}
    bond_keys = [k for k in BOND_AXES if k in s]
    if len(bond_keys) > 1:
        raise bad("give lattice_bonds or lattice_bonds_per_particle, not both")
    if "lattice_bonds" in s:
        axes["lattice_bonds"] = read_list(
            s, "lattice_bonds", lambda v: is_integer(v) and 1000 <= v <= MAX_BONDS,
            "an integer in [1000, %d]" % MAX_BONDS, bad)
    if "lattice_bonds_per_particle" in s:
        key = "lattice_bonds_per_particle"
        axes[key] = read_list(s, key, lambda v: is_number(v) and v > 0, "a number > 0", bad)
        particles = sample.get("sample_particles", DEFAULT_SAMPLE_PARTICLES)
        if not is_integer(particles):
            raise bad("%s needs an integer sample.sample_particles, not %r", key, particles)
        for v in axes[key]:
            if not 1000 <= round(v * particles) <= MAX_BONDS:
                raise bad("%s value %r gives %d bonds, outside [1000, %d]", key, v,
                          round(v * particles), MAX_BONDS)
    clash = [o for o in SIZE_OPTIONS if o in sample]
    if bond_keys and clash:
        raise bad("%s sets the lattice size: remove sample.%s", bond_keys[0], clash[0])
    for key, option in SEED_AXES.items():
        if key not in s:
            continue
        axes[key] = read_list(s, key, lambda v: is_integer(v) and 0 <= v <= MAX_SEED,
                              "an integer in [0, %d]" % MAX_SEED, bad)
        if option in sample:
            raise bad("%s sets the seed: remove sample.%s", key, option)
    for key in LEVEL_KEYS:
        if key not in s:
            continue
        if not bond_keys:
            raise bad("%s needs a bond axis (lattice_bonds or lattice_bonds_per_particle)", key)
        if isinstance(s[key], bool) or s[key] not in axes[bond_keys[0]]:
            raise bad("%s value %r is not one of %s %s", key, s[key], bond_keys[0],
                      axes[bond_keys[0]])
        axes[key] = s[key]
    if "elastic" in s:
        if not isinstance(s["elastic"], bool):
            raise bad("elastic must be true or false, not %r", s["elastic"])
        axes["elastic"] = s["elastic"]
    if "fracture_up_to" in axes and not axes.get("elastic"):
        raise bad("fracture_up_to leaves the larger lattices without any run: set elastic: true")
    return axes


def bond_axis(spec):
    """(key, values) of the study's bond axis, or (None, [None])."""
    for key in BOND_AXES:
        if key in spec:
            return key, spec[key]
    return None, [None]


def lattices(spec):
    """The lattices of a study in run order (bond-axis value, pack seed,
    lattice seed, as the file lists them), each a dict: tag (None for a study
    without axes), level (the bond-axis value or None), sample_options (what
    the axes add to the sample options), pack_seed, lattice_seed, fracture
    (whether the fracture runs are made on it)."""
    key, levels = bond_axis(spec)
    packs = spec.get("pack_seeds", [None])
    seeds = spec.get("lattice_seeds", [None])
    out = []
    for level in levels:
        replicated = "replicates_up_to" not in spec or level <= spec["replicates_up_to"]
        for pack in packs if replicated else packs[:1]:
            for seed in seeds if replicated else seeds[:1]:
                options, parts = {}, []
                if key == "lattice_bonds":
                    options["lattice_bonds"] = level
                    parts.append("b%d" % level)
                elif key == "lattice_bonds_per_particle":
                    particles = spec["sample"].get("sample_particles", DEFAULT_SAMPLE_PARTICLES)
                    options["lattice_bonds"] = int(round(level * particles))
                    parts.append("bpp%g" % level)
                if pack is not None:
                    options["pack_seed"] = pack
                    parts.append("p%d" % pack)
                if seed is not None:
                    options["lattice_seed"] = seed
                    parts.append("l%d" % seed)
                out.append({"tag": "_".join(parts) or None, "level": level,
                            "sample_options": options,
                            "pack_seed": pack if pack is not None
                            else spec["sample"].get("pack_seed", 1),
                            "lattice_seed": seed if seed is not None
                            else spec["sample"].get("lattice_seed", 1),
                            "fracture": "fracture_up_to" not in spec
                            or level <= spec["fracture_up_to"]})
    return out


def has_axes(spec):
    return any(k in spec for k in AXIS_KEYS)
