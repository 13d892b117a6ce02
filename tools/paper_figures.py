#!/usr/bin/python3
"""The paper's figures from study data folders (docs/data/<study>/).

The command of lem_tools/paper_figures.py; --help tells its arguments.
"""
from lem_tools.paper_figures import main

if __name__ == "__main__":
    raise SystemExit(main())
