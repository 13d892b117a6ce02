#!/bin/bash
# CI proof of the CMake package (docs/guide/building.md): lem3d built a second
# time, with the `cluster` preset, against a PETSc found only through
# PETSC_DIR/PETSC_ARCH (Debian's PETSc tree, pkg-config's own search hidden),
# without the tests; installed into a prefix; a project outside lem3d built
# against the installed package (tests/install_consumer); the main job run
# by the installed programs, which must break the same bonds at the same
# strains as the build tree's programs; jobs/build.sh on a host without dpkg.
# Usage: jobs/check-install.sh [--build-only] [WORK_DIR]   (needs build/ from
# jobs/build.sh).  --build-only stops after the second build (.ci/run starts
# it beside the test tiers); a later run reuses that build and redoes the rest.
# LEM_CHECK_PETSC_DIR, LEM_CHECK_PETSC_ARCH: the PETSc tree (Debian's).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build_only=false
if [ "${1:-}" = "--build-only" ]; then build_only=true; shift; fi
work="$(realpath -m "${1:-$root/build/install-check}")"
petsc_dir="${LEM_CHECK_PETSC_DIR:-/usr/lib/petscdir/petsc3.18}"
petsc_arch="${LEM_CHECK_PETSC_ARCH:-x86_64-linux-gnu-real}"
prefix="$work/prefix"
fail() { echo "install-check: FAIL: $*" >&2; exit 1; }
step() { echo "install-check: [${SECONDS} s] $*"; }
# Everything but the second build is redone; the build is incremental.
if [ -d "$work" ]; then
  find "$work" -mindepth 1 -maxdepth 1 ! -name build -exec rm -rf {} +
fi
mkdir -p "$work/no-pkgconfig" "$work/run"

# PETSc only through PETSC_DIR/PETSC_ARCH: pkg-config searches an empty
# folder instead of the system's.
export PETSC_DIR="$petsc_dir" PETSC_ARCH="$petsc_arch"
export PKG_CONFIG_LIBDIR="$work/no-pkgconfig" PKG_CONFIG_PATH=
! pkg-config --exists PETSc petsc || fail "pkg-config still finds PETSc"

step "configure (preset cluster, PETSC_DIR=$PETSC_DIR PETSC_ARCH=$PETSC_ARCH)"
(cd "$root" && cmake --preset cluster -B "$work/build") > "$work/configure.log" 2>&1 ||
  { tail -30 "$work/configure.log" >&2; fail "configure"; }
grep -F "lem3d: PETSc" "$work/configure.log"
grep -F "lem3d: HDF5" "$work/configure.log"
grep -qF "found through PETSC_DIR=$PETSC_DIR PETSC_ARCH=$PETSC_ARCH" "$work/configure.log" ||
  fail "PETSc was not found through PETSC_DIR"
grep -q "lem3d: HDF5 .*(parallel) from .*/hdf5/openmpi" "$work/configure.log" ||
  fail "the HDF5 found is not Debian's openmpi flavour"
grep -q "GTest" "$work/configure.log" && fail "GoogleTest looked for with LEM_BUILD_TESTS=OFF"

step "build"
cmake --build "$work/build" -j "$(nproc)" > "$work/build.log" 2>&1 ||
  { grep -E "error|Error" -A5 "$work/build.log" | head -60 >&2; fail "build"; }
[ ! -e "$work/build/tests" ] || fail "tests built with LEM_BUILD_TESTS=OFF"
$build_only && { step "built (--build-only)"; exit 0; }

step "install into $prefix"
cmake --install "$work/build" --prefix "$prefix" > "$work/install.log" 2>&1 ||
  { tail -20 "$work/install.log" >&2; fail "install"; }
for f in bin/lem_fracture bin/lem_sample bin/lem_tension lib/liblem_base.a lib/liblem_report.a \
         include/lem/lattice/lattice.hpp include/lem/protocol/options.hpp \
         lib/cmake/lem3d/lem3dConfig.cmake lib/cmake/lem3d/lem3dConfigVersion.cmake \
         lib/cmake/lem3d/lem3dTargets.cmake share/lem3d/tools/lem_tools/__init__.py \
         share/lem3d/tools/plot_fracture.py share/lem3d/meshes/mini.h5 \
         share/lem3d/jobs/main.sh share/lem3d/jobs/main.opts; do
  [ -e "$prefix/$f" ] || fail "not installed: $f"
done
! ldd "$prefix/bin/lem_fracture" | grep "not found" || fail "installed lem_fracture misses libraries"
# The BLAS behind PETSc is the optimised one jobs/install-deps.sh installs.
blas="$(ldd "$prefix/bin/lem_fracture" | awk '$1 == "libblas.so.3" {print $3}')"
[ -n "$blas" ] || fail "lem_fracture loads no libblas.so.3"
realpath "$blas" | grep -q openblas || fail "lem_fracture's BLAS is $(realpath "$blas"), not OpenBLAS"
PYTHONPATH="$prefix/share/lem3d/tools" /usr/bin/python3 -c \
  "import lem_tools.study as s, sys; sys.exit(not s.__file__.startswith('$prefix/'))" ||
  fail "lem_tools is not imported from the install"

step "a project using the installed package (tests/install_consumer)"
# PETSC_DIR unset: the package brings the PETSc lem3d was built with.
env -u PETSC_DIR -u PETSC_ARCH cmake -S "$root/tests/install_consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$prefix" \
  > "$work/consumer.log" 2>&1 && cmake --build "$work/consumer" >> "$work/consumer.log" 2>&1 ||
  { tail -30 "$work/consumer.log" >&2; fail "consumer project"; }
"$work/consumer/consumer" || fail "consumer program"

step "main job, build tree's programs"
LEM_BIN="$root/build" bash "$root/jobs/main.sh" -output_dir "$work/main-build" > "$work/main-build.log" 2>&1 ||
  { tail -20 "$work/main-build.log" >&2; fail "main job of the build tree"; }
step "main job, installed programs ($prefix/share/lem3d/jobs/main.sh in $work/run)"
(cd "$work/run" && bash "$prefix/share/lem3d/jobs/main.sh") > "$work/main-install.log" 2>&1 ||
  { tail -20 "$work/main-install.log" >&2; fail "installed main job"; }
installed="$work/run/results/main"
for f in summary.json broken.csv curve.csv fields.xmf fracture.png stress.png; do
  [ -s "$installed/$f" ] || fail "installed main job wrote no $f"
done
cmp "$work/main-build/broken.csv" "$installed/broken.csv" ||
  fail "the installed programs broke other bonds than the build tree's"
# curve.csv but its last column (elapsed_s)
diff <(sed 's/,[^,]*$//' "$work/main-build/curve.csv") <(sed 's/,[^,]*$//' "$installed/curve.csv") ||
  fail "the installed programs gave another curve"
step "same broken.csv ($(($(wc -l < "$installed/broken.csv") - 1)) ruptures) and curve.csv"

step "jobs/build.sh on a host without dpkg (PATH without dpkg-query), build/ existing"
mkdir -p "$work/no-dpkg"
for f in /usr/bin/*; do
  case "${f##*/}" in dpkg*) ;; *) ln -s "$f" "$work/no-dpkg/${f##*/}" ;; esac
done
env -u PETSC_DIR -u PETSC_ARCH -u PKG_CONFIG_LIBDIR PATH="$work/no-dpkg" \
  bash "$root/jobs/build.sh" 2> "$work/no-dpkg.log" || { cat "$work/no-dpkg.log" >&2; fail "build.sh without dpkg"; }
grep -q "no dpkg on this host" "$work/no-dpkg.log" || fail "build.sh did not say that dpkg is missing"
step "done"
