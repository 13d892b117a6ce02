#!/usr/bin/python3
"""Pictures of an elastic tension test written by lem_tension.

The command of lem_tools/plot_tension.py; --help tells its arguments.
"""
from lem_tools.plot_tension import main

if __name__ == "__main__":
    raise SystemExit(main())
