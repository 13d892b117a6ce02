#!/usr/bin/python3
"""Crack map of a tensile fracture run (Affes et al. 2012, fig. 4).

The command of lem_tools/plot_crack.py; --help tells its arguments.
"""
from lem_tools.plot_crack import main

if __name__ == "__main__":
    raise SystemExit(main())
