#!/usr/bin/python3
"""Where a lem_fracture run spent its solver work (up to the peak, after it).

The command of lem_tools/work_split.py; --help tells its arguments.
"""
from lem_tools.work_split import main

if __name__ == "__main__":
    raise SystemExit(main())
