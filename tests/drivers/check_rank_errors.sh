#!/bin/bash
# A job whose ranks fail must end within seconds with STATUS and one line
# of stderr matching PATTERN (the error is reported once, whichever ranks
# saw it); with STATUS 0, a short job that must succeed and say PATTERN once.
# Usage: check_rank_errors.sh STATUS PATTERN command [args...]
status="$1"; pattern="$2"; shift 2
limit=10  # seconds: the 3 s grace of a rank failing alone, MPI start and teardown
start=$(date +%s.%N)
output="$("$@" 2>&1)"
got=$?
seconds=$(echo "$(date +%s.%N) - $start" | bc)
fail() { echo "FAIL: $*"; echo "$output"; exit 1; }
[ "$got" -eq "$status" ] || fail "exit status $got, expected $status"
count=$(grep -cE -- "$pattern" <<< "$output")
[ "$count" -eq 1 ] || fail "$count lines match '$pattern', expected 1"
! grep -q "exiting improperly" <<< "$output" || fail "a rank exited without finalising MPI"
(( $(echo "$seconds < $limit" | bc) )) || fail "took $seconds s (limit $limit s)"
echo "ok: exit $got in $seconds s: $(grep -E -- "$pattern" <<< "$output")"
