#!/usr/bin/python3
"""Draw the matrix bridge of lem's cemented samples in an axial section.

The command of lem_tools/plot_bridge_geometry.py; --help tells its arguments.
"""
from lem_tools.plot_bridge_geometry import main

if __name__ == "__main__":
    raise SystemExit(main())
