#!/usr/bin/python3
"""Scaling measurements: lem_bench on one sample file at several rank counts.

The command of lem_tools/scaling.py; --help tells its arguments.
"""
from lem_tools.scaling import main

if __name__ == "__main__":
    raise SystemExit(main())
