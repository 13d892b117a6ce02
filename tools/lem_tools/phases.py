"""Bond phases of a cemented sample, in the order of the C++ enum lem::Phase
(include/lem/base/phase.hpp), which is also the order of phase ids in files."""

PHASES = ("p", "m", "v", "pp", "pm")

PHASE_NAMES = {
    "p": "particle",
    "m": "matrix",
    "v": "void",
    "pp": "particle-particle",
    "pm": "particle-matrix",
}

# Phases whose bonds can break: void bonds carry no load.
BREAKABLE = tuple(p for p in PHASES if p != "v")


def broken_column(phase):
    """Name of the cumulative count of broken bonds of `phase` in curve.csv
    and summary.json."""
    return "broken_" + phase


def phase_name(phase):
    return PHASE_NAMES.get(phase, "unknown phase")
