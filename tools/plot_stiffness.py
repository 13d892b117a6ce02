#!/usr/bin/python3
"""Plot E_eff/E^[p] and S^pm/S^p against the matrix fraction (paper figs. 5, 11).

The command of lem_tools/plot_stiffness.py; --help tells its arguments.
"""
from lem_tools.plot_stiffness import main

if __name__ == "__main__":
    raise SystemExit(main())
