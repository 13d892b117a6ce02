#!/bin/bash
# Run a driver that must reject its input: it has to exit non-zero, print a
# message matching PATTERN, and leave no summary in OUTPUT_DIR.
# Usage: expect_failure.sh PATTERN OUTPUT_DIR command [args...]
pattern="$1"; dir="$2"; shift 2
rm -rf "$dir"
output="$("$@" 2>&1)"
status=$?
if [ "$status" -eq 0 ]; then
  echo "FAIL: exit status 0 for bad input: $*"; echo "$output"; exit 1
fi
if ! grep -qE -- "$pattern" <<< "$output"; then
  echo "FAIL: message does not match '$pattern':"; echo "$output"; exit 1
fi
if [ -e "$dir/summary.json" ] || [ -e "$dir/summary.csv" ]; then
  echo "FAIL: a summary was written in $dir despite the error"; exit 1
fi
echo "ok: exit $status, message: $(grep -E -- "$pattern" <<< "$output" | head -1)"
