#!/usr/bin/python3
"""Table and figures of a parametric study (the gather step of study.py).

The command of lem_tools/study.py (gather_main); --help tells its arguments.
"""
from lem_tools.study import gather_main

if __name__ == "__main__":
    raise SystemExit(gather_main())
