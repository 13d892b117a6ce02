#!/bin/bash
# Build and run the tests (docs/testing.md, "Tiers").
#   bash jobs/test.sh          the quick tier: every module and promise in at
#                              least one test (ctest -L quick, pytest -m "not long")
#   bash jobs/test.sh --all    every test, as CI runs them
# Other arguments go to ctest (e.g. -R fracture_ to pick tests by name).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
ctest_args=(-L quick)
pytest_args=(-m "not long")
if [ "${1:-}" = "--all" ]; then
  ctest_args=()
  pytest_args=()
  shift
fi
bash "$root/jobs/build.sh"
cd "$root/build"
# Two tests at a time where the tests' PROCESSORS allow: the 2-rank tests
# run alone, the 1-rank ones in pairs.
ctest --output-on-failure -j 2 "${ctest_args[@]}" "$@"
# The Python tools' own tests (tools/lem_tools), under Debian's Python.
cd "$root"
/usr/bin/python3 -m pytest -q tests/python "${pytest_args[@]}"
