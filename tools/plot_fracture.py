#!/usr/bin/python3
"""Pictures of a tensile fracture run written by lem_fracture.

The command of lem_tools/plot_fracture.py; --help tells its arguments.
"""
from lem_tools.plot_fracture import main

if __name__ == "__main__":
    raise SystemExit(main())
