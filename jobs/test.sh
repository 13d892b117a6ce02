#!/bin/bash
# Build and run the tests (docs/developer/testing.md, "Tiers").
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
# The Python tools' own tests (tools/lem_tools, under Debian's Python) run
# beside ctest: the MPI tests leave the cores idle about a third of the time
# (start-up, waits for the other rank), which pytest fills.  Their report
# follows ctest's.
pytest_log="$(mktemp)"
ctest_log="$(mktemp)"
trap 'rm -f "$pytest_log" "$ctest_log"' EXIT
(cd "$root" && exec /usr/bin/python3 -m pytest -q tests/python "${pytest_args[@]}") > "$pytest_log" 2>&1 &
pytest_pid=$!
# Two tests at a time where the tests' PROCESSORS allow: the 2-rank tests
# run alone, the 1-rank ones in pairs.
ctest_status=0
(cd "$root/build" && ctest --output-on-failure -j 2 "${ctest_args[@]}" "$@") 2>&1 |
  tee "$ctest_log" || ctest_status=$?
# Under CI=true a skipped test is a failure: CI runs as root with every
# package, so a skip there means a test that proved nothing.
if [ "${CI:-}" = true ] && [ "$ctest_status" -eq 0 ]; then
  bash "$root/jobs/check-no-skips.sh" "$ctest_log" || ctest_status=1
fi
pytest_status=0
wait "$pytest_pid" || pytest_status=$?
cat "$pytest_log"
[ "$ctest_status" -eq 0 ] || { echo "test.sh: ctest failed (exit $ctest_status)" >&2; exit "$ctest_status"; }
[ "$pytest_status" -eq 0 ] || { echo "test.sh: pytest failed (exit $pytest_status)" >&2; exit "$pytest_status"; }
