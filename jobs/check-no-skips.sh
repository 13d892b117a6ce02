#!/bin/bash
# check-no-skips.sh CTEST_OUTPUT: exit 1, naming them, when ctest's output
# (its summary "The following tests did not run") lists skipped tests.
# jobs/test.sh calls it under CI=true, where a skip would hide a test that
# proved nothing (docs/developer/testing.md, "Skips").
set -euo pipefail
[ -r "${1:-}" ] || { echo "check-no-skips.sh: cannot read ctest output '${1:-}'" >&2; exit 2; }
skipped=$(grep -E '^[[:space:]]*[0-9]+ - .* \((Skipped|Not Run|Disabled)\)[[:space:]]*$' "$1" |
  sed -E 's/^[[:space:]]*[0-9]+ - //' || true)
if [ -n "$skipped" ]; then
  echo "CI=true: these tests did not run, which CI counts as a failure:" >&2
  printf '  %s\n' "$skipped" >&2
  exit 1
fi
