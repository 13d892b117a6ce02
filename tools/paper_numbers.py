#!/usr/bin/python3
"""The numbers the paper pages quote, computed from docs/data.

The command of lem_tools/paper_numbers.py; --help tells its arguments.
"""
from lem_tools.paper_numbers import main

if __name__ == "__main__":
    raise SystemExit(main())
