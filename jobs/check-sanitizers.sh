#!/bin/bash
# Part of the quick tier once more, built with AddressSanitizer and
# UndefinedBehaviorSanitizer (cmake --preset sanitize: -DLEM_SANITIZE=ON at
# -O1 -g1, in build-asan/): the tests labelled `sanitized`, every quick
# GoogleTest program and the driver tests of LEM_SANITIZED_TESTS
# (tests/tiers.cmake; docs/developer/testing.md, "Sanitizers").
#   bash jobs/check-sanitizers.sh            build, then ctest -L sanitized
#   bash jobs/check-sanitizers.sh -R NAME    other arguments go to ctest
#   bash jobs/check-sanitizers.sh --build-only   the build alone (.ci/run
#                                             starts it beside the tiers)
# Any report fails the job, also one from a test that expects its program
# to fail (a bad-input case): the reports go to files, counted at the end.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-asan"
log="$build/build-sanitize.log"
mkdir -p "$build"
# The flags are the preset's, in CMakePresets.json.
(cd "$root" && cmake --preset sanitize) > "$log" 2>&1 || { tail -30 "$log" >&2; exit 1; }
cmake --build "$build" -j "$(nproc)" >> "$log" 2>&1 ||
  { grep -E "error|Error" -A5 "$log" | head -60 >&2; exit 1; }
[ "${1:-}" = "--build-only" ] && { echo "check-sanitizers.sh: built in $build"; exit 0; }
reports="$build/sanitizer-reports"
rm -rf "$reports" && mkdir -p "$reports"
# Leaks are not checked: Open MPI and its plug-ins (PMIx, hwloc, libevent)
# keep allocations to the end of the process by design, so LeakSanitizer
# reports them in every MPI program.  ASan's other checks and all of UBSan's
# stay on; exitcode 86 sets a report apart from the programs' own statuses.
export ASAN_OPTIONS="detect_leaks=0:exitcode=86:log_path=$reports/asan:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=86:log_path=$reports/ubsan"
status=0
# --timeout: a test without a TIMEOUT of its own that hangs (a sanitized MPI
# program stuck in its end) fails after 5 min instead of ctest's 25.
(cd "$build" && ctest --output-on-failure -j 2 --timeout 300 -L sanitized "$@") ||
  status=$?
if compgen -G "$reports/*" > /dev/null; then
  echo "check-sanitizers.sh: sanitizer reports (also from tests that passed):" >&2
  for f in "$reports"/*; do echo "== $f" >&2; head -40 "$f" >&2; done
  exit 1
fi
[ "$status" -eq 0 ] || { echo "check-sanitizers.sh: ctest failed (exit $status)" >&2; exit "$status"; }
echo "check-sanitizers.sh: the sanitized tests passed under ASan and UBSan, no report"
