#!/usr/bin/python3
"""Convergence tables and figures over several gathered studies.

The command of lem_tools/study_combine.py; --help tells its arguments.
"""
from lem_tools.study_combine import main

if __name__ == "__main__":
    raise SystemExit(main())
