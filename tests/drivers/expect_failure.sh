#!/bin/bash
# Run a driver that must reject its input: it has to exit with STATUS (the
# documented exit status: 1 bad input, 2 numerical failure, 3 I/O or other),
# print a message matching PATTERN, and leave no summary in OUTPUT_DIR.
# Usage: expect_failure.sh STATUS PATTERN OUTPUT_DIR command [args...]
expected="$1"; pattern="$2"; dir="$3"; shift 3
rm -rf "$dir"
output="$("$@" 2>&1)"
status=$?
if [ "$status" -ne "$expected" ]; then
  echo "FAIL: exit status $status, expected $expected: $*"; echo "$output"; exit 1
fi
if ! grep -qE -- "$pattern" <<< "$output"; then
  echo "FAIL: message does not match '$pattern':"; echo "$output"; exit 1
fi
if [ -e "$dir/summary.json" ] || [ -e "$dir/summary.csv" ]; then
  echo "FAIL: a summary was written in $dir despite the error"; exit 1
fi
echo "ok: exit $status, message: $(grep -E -- "$pattern" <<< "$output" | head -1)"
