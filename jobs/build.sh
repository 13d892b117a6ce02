#!/bin/bash
# Configure and build (Release) into build/, installing dependencies first
# on Debian.  Without dpkg (another Linux, a cluster) nothing is installed:
# load your PETSc, MPI, HDF5, CGAL and METIS (docs/guide/building.md) and the
# build, or an existing build/, is used as it is.
#   bash jobs/build.sh                 every target: drivers and tests
#   bash jobs/build.sh lem_fracture    only the named targets (and what they need)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if command -v dpkg-query > /dev/null; then
  bash "$root/jobs/install-deps.sh"
else
  echo "build.sh: no dpkg on this host: jobs/install-deps.sh skipped (docs/guide/building.md)" >&2
fi
targets=()
for t in "$@"; do targets+=(--target "$t"); done
# Under CI (CI=true) a compiler warning in lem3d's own code fails the build.
werror=OFF
[ "${CI:-}" = true ] && werror=ON
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DLEM_WERROR=$werror > "$root/build.log" 2>&1 ||
  { tail -30 "$root/build.log" >&2; exit 1; }
cmake --build "$root/build" -j "$(nproc)" "${targets[@]}" >> "$root/build.log" 2>&1 ||
  { grep -E "error|Error" -A5 "$root/build.log" | head -60 >&2; exit 1; }
