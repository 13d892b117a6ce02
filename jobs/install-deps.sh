#!/bin/bash
# Install the Debian 12 packages this project needs, if any is missing.
# Runs apt-get as root; as another user it prints the command to run.
set -euo pipefail
if ! command -v dpkg-query > /dev/null; then
  echo "install-deps.sh: no dpkg: this script is for Debian 12; install PETSc, MPI," \
       "parallel HDF5, CGAL and METIS yourself (docs/guide/building.md)" >&2
  exit 1
fi
packages=(build-essential cmake pkg-config git petsc-dev libmetis-dev libcgal-dev
          libhdf5-openmpi-dev openmpi-bin libgtest-dev python3-matplotlib python3-h5py
          python3-numpy python3-scipy python3-yaml python3-pytest python3-meshio
          clang-format-14 libopenblas0-serial)
# libopenblas0-serial: Debian links PETSc, numpy and scipy to the reference
# BLAS unless an optimised one is installed, which then takes its place
# (update-alternatives).  Serial, not pthread: each MPI rank is one core.
# A factorization (-pc_type cholesky -pc_factor_mat_solver_type mumps)
# is several times slower on the reference BLAS (docs/notes/blas.md).
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "error: missing Debian packages: ${missing[*]}" >&2
  echo "install them with: sudo apt-get install ${missing[*]}" >&2
  exit 1
fi
echo "installing: ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" > /tmp/lem-apt.log 2>&1 ||
  { tail -20 /tmp/lem-apt.log >&2; echo "error: apt-get install failed (log: /tmp/lem-apt.log)" >&2; exit 1; }
