#!/bin/bash
# Install, build and run every test (unit, 2-rank MPI, driver error paths).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/jobs/build.sh"
cd "$root/build"
ctest --output-on-failure -j 1 "$@"
# The Python tools' own tests (tools/lem_tools), under Debian's Python.
cd "$root"
/usr/bin/python3 -m pytest -q tests/python
