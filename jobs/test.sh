#!/bin/bash
# Install, build and run every test (unit, 2-rank MPI, driver error paths).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/jobs/build.sh"
cd "$root/build"
ctest --output-on-failure -j 1 "$@"
