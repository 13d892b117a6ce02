#!/usr/bin/python3
"""Plot E_eff/E^[m] against the mesh density L_n (paper fig. 6).

The command of lem_tools/plot_convergence.py; --help tells its arguments.
"""
from lem_tools.plot_convergence import main

if __name__ == "__main__":
    raise SystemExit(main())
