#!/usr/bin/python3
"""Node stresses of a cemented sample under tension (Affes et al. 2012, sect. 4).

The command of lem_tools/plot_stress.py; --help tells its arguments.
"""
from lem_tools.plot_stress import main

if __name__ == "__main__":
    raise SystemExit(main())
