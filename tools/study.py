#!/usr/bin/python3
"""Parametric study of Affes et al. (2012): grid of rho^m x sigma^pm tension runs.

The command of lem_tools/study.py; --help tells its arguments.
"""
from lem_tools.study import main

if __name__ == "__main__":
    raise SystemExit(main())
