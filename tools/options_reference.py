#!/usr/bin/python3
"""Write (or --check) docs/reference/options.md from the programs' -help.

The command of lem_tools/options_reference.py; --help tells its arguments.
"""
from lem_tools.options_reference import main

if __name__ == "__main__":
    raise SystemExit(main())
