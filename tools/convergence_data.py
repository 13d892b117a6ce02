#!/usr/bin/python3
"""The L_n -> 0 lines of the convergence pages, from docs/data/convergence-*.csv.

The command of lem_tools/convergence_data.py; --help tells its arguments.
"""
from lem_tools.convergence_data import main

if __name__ == "__main__":
    raise SystemExit(main())
