#!/usr/bin/python3
"""The rows of studies that differ only in the load increment, side by side.

The command of lem_tools/increment_table.py; --help tells its arguments.
"""
from lem_tools.increment_table import main

if __name__ == "__main__":
    raise SystemExit(main())
