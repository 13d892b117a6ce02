#!/bin/bash
# The results of lem_fracture (2 ranks: parallel, compressed HDF5), lem_sample
# and lem_pack open in csv, numpy, meshio and h5py as they are
# (check_readers.py), and -version answers without running anything.
# Usage: check_results_readers.sh BUILD_DIR WORKDIR MPIEXEC [MPIEXEC_FLAGS...]
set -u
build="$1" work="$2"
shift 2
mpi=("$@")
root="$(cd "$(dirname "$0")/../.." && pwd)"
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work" && mkdir -p "$work"
out="$("$build/lem_fracture" -version 2>&1)" || fail "-version exits $?: $out"
grep -q "^lem_fracture (lem3d) .*, git " <<< "$out" || fail "-version prints: $out"
grep -q "^PETSc " <<< "$out" || fail "-version names no PETSc: $out"
"${mpi[@]}" -n 2 "$build/lem_fracture" -sample_file "$root/meshes/tiny.h5" -fracture_calibrate 0 \
  -fracture_max_steps 30 -output_snapshot_steps 1 -output_dir "$work/fracture" \
  > "$work/fracture.log" 2>&1 || fail "lem_fracture: $(tail -3 "$work/fracture.log")"
"$build/lem_sample" -sample_particles 20 -lattice_bonds 20000 -pack_seed 2 -output_dir "$work/sample" \
  > "$work/sample.log" 2>&1 || fail "lem_sample: $(tail -3 "$work/sample.log")"
"$build/lem_pack" -pack_particles 100 -pack_sample_particles 40 -output_dir "$work/pack" \
  > "$work/pack.log" 2>&1 || fail "lem_pack: $(tail -3 "$work/pack.log")"
/usr/bin/python3 "$root/tests/drivers/check_readers.py" "$work/fracture" "$work/sample" \
  "$work/pack"
