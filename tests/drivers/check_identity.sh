#!/bin/bash
# What identifies a result, and what the programs read and delete.
# Usage: check_identity.sh MODE BUILD_DIR MESHES_DIR WORK_DIR MPIEXEC [MPI flags...]
#   inputs       options files that are not regular files (a pipe, a process
#                substitution, a FIFO, /dev/zero), a too large one, a FIFO
#                as the sample file, the checkpoint or the manifest: each
#                refused at once (exit 1) naming it, never read or waited on;
#                lem_tension given two lattice sizes refuses the conflict
#   fingerprint  the shipped tiny sample: -sample_parallel reuses the default
#                set-up's calibration, recognises its result and resumes its
#                checkpoint; -lattice_ground_stiffness, other coordinates (x and
#                y swapped: every bond length the same) or
#                another -ksp_rtol are another result (named) and another
#                calibration (its own key, its warnings kept: an error under
#                -fracture_strict when reused); a checkpoint resumes under
#                other solver options and says so, not under other physics
#   outputs      a run with snapshots killed (-9) after a checkpoint and resumed
#                equals the uninterrupted run, snapshots included (one left
#                from after the checkpoint goes); a user's files whose names
#                look like the program's stay, through a fresh start, a
#                resume and -output_overwrite, and no manifest lists them
set -u
mode="$1"; build="$2"; meshes="$3"; work="$4"; shift 4
mpi=("$@")
py=/usr/bin/python3
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"; mkdir -p "$work"
cd "$work" || exit 1

case "$mode" in
inputs)
  # expect NAME PATTERN command...: exit 1 within 60 s, the pattern in the output.
  expect() {
    local name=$1 pattern=$2
    shift 2
    timeout -s KILL 60 "$@" > "$name.log" 2>&1
    local status=$?
    [ "$status" -eq 1 ] || fail "$name: exit $status (137: killed after 60 s), expected 1: $(tail -2 "$name.log")"
    grep -qE -- "$pattern" "$name.log" || fail "$name: message does not match '$pattern': $(tail -2 "$name.log")"
    echo "ok $name: $(grep -E -- "$pattern" "$name.log" | head -1)"
  }
  tension=("$build/lem_tension" -lattice_nodes 300 -output_fields false)
  mkfifo options.fifo sample.fifo
  expect substitution "-options_file = '/dev/fd/[0-9]+': a pipe \(FIFO\), not a regular file" \
    bash -c '"$@" -options_file <(echo -lattice_seed 5) -output_dir sub' _ "${tension[@]}"
  expect fifo "-options_file = 'options.fifo': a pipe \(FIFO\)" \
    "${tension[@]}" -options_file options.fifo -output_dir fifo
  expect zero "-options_file = '/dev/zero': a character device" \
    "${tension[@]}" -options_file /dev/zero -output_dir zero
  echo "-options_file /dev/urandom" > nested.opts
  expect nested "'/dev/urandom' in 'nested.opts': a character device" \
    "${tension[@]}" -options_file nested.opts -output_dir nested
  head -c 2000000 /dev/zero | tr '\0' '#' > large.opts
  expect large "-options_file = 'large.opts': 2000000 bytes, more than an options file holds" \
    "${tension[@]}" -options_file large.opts -output_dir large
  expect sample "-sample_file = 'sample.fifo': a pipe \(FIFO\), not a sample file" \
    "$build/lem_tension" -sample_file sample.fifo -output_dir sample
  mkdir -p ckpt && mkfifo ckpt/checkpoint.bin
  expect checkpoint "checkpoint 'ckpt/checkpoint.bin' is not a valid lem checkpoint \(a pipe \(FIFO\)" \
    "$build/lem_fracture" -lattice_nodes 300 -output_fields false -output_dir ckpt
  mkdir -p manifest && mkfifo manifest/manifest.txt
  expect manifest "the manifest 'manifest/manifest.txt' is a pipe \(FIFO\)" \
    "${tension[@]}" -output_dir manifest
  expect sizes "-lattice_nodes 300, -lattice_bonds 2000 each set the size of the random lattice" \
    "${tension[@]}" -lattice_bonds 2000 -output_dir sizes
  ;;
fingerprint)
  cp "$meshes/tiny.h5" tiny.h5
  units=(-fracture_calibrate false -fracture_sigma_unit 0.018 -fracture_modulus_unit 7.3)
  run() {  # run NAME RANKS ARGS...: lem_fracture on the tiny sample, log in NAME.log
    local name=$1 n=$2
    shift 2
    "${mpi[@]}" -n "$n" "$build/lem_fracture" -sample_file tiny.h5 -output_fields false \
      -fracture_max_steps 3 "$@" > "$name.log" 2>&1
  }
  keys() { ls tiny.calibration-*.txt 2>/dev/null | wc -l; }
  run a 2 -output_dir a || fail "default set-up: $(tail -2 a.log)"
  grep -q "calibration: the homogeneous lattice" a.log || fail "the first run did not calibrate"
  [ "$(keys)" -eq 1 ] || fail "$(keys) calibration files after the first run"
  # The parallel set-up of the same sample: the same calibration and result.
  run b 2 -sample_parallel -output_dir b || fail "parallel set-up: $(tail -2 b.log)"
  grep -q "calibration: the homogeneous lattice" b.log &&
    fail "-sample_parallel calibrated again instead of reusing the default set-up's calibration"
  grep -q "from tiny.calibration-" b.log || fail "-sample_parallel did not say where sigma^[p] came from"
  run a2 2 -sample_parallel -output_dir a || fail "parallel set-up on a's result: $(tail -3 a2.log)"
  grep -q "is complete (manifest.txt): nothing to do" a2.log ||
    fail "the default set-up's result was not recognised under -sample_parallel: $(tail -3 a2.log)"
  # Physics that changes the result (by 75 % for this one) is another result.
  run ground 2 -lattice_ground_stiffness 1e-3 -output_dir a &&
    fail "a result of -lattice_ground_stiffness 1e-10 was called that of 1e-3"
  grep -q "finished: -lattice_ground_stiffness=1e-10   this run: -lattice_ground_stiffness=0.001" ground.log ||
    fail "the refusal does not name the option: $(tail -3 ground.log)"
  # A sample whose coordinates differ, its bonds, phases and every bond's
  # length (so every stiffness and threshold) the same: x and y swapped.
  $py - tiny.h5 moved.h5 <<'EOF' || fail "cannot write moved.h5"
import shutil, sys, h5py
shutil.copy(sys.argv[1], sys.argv[2])
with h5py.File(sys.argv[2], "r+") as f:
    for name in ("/nodes/coordinates", "/particles/centres"):
        x = f[name][()]
        x[:, [0, 1]] = x[:, [1, 0]]
        f[name][...] = x
EOF
  "${mpi[@]}" -n 2 "$build/lem_fracture" -sample_file moved.h5 -output_fields false \
    -fracture_max_steps 3 -output_dir a > moved.log 2>&1 &&
    fail "a sample with other coordinates was called the same result"
  grep -q "finished: sample_content=" moved.log || fail "the refusal does not name the sample's content: $(tail -3 moved.log)"
  # Other solver options: a calibration of their own, with their warnings.
  run loose 2 -ksp_rtol 1e-2 -output_dir loose || fail "-ksp_rtol 1e-2: $(tail -2 loose.log)"
  grep -q "calibration: the homogeneous lattice" loose.log ||
    fail "-ksp_rtol 1e-2 reused the calibration made with 1e-8"
  [ "$(keys)" -eq 2 ] || fail "$(keys) calibration files: -ksp_rtol 1e-2 did not get a key of its own"
  grep -q "^warning=energy_balance" tiny.calibration-*.txt ||
    fail "the loose calibration did not keep its warning"
  run loose_strict 2 -ksp_rtol 1e-2 -fracture_strict -output_dir loose_strict
  status=$?
  [ "$status" -eq 2 ] || fail "reusing a calibration with warnings under -fracture_strict: exit $status"
  grep -q "was made by a run with warnings (energy_balance" loose_strict.log ||
    fail "unclear message: $(tail -2 loose_strict.log)"
  run loose2 2 -ksp_rtol 1e-2 -output_dir loose2 || fail "reuse of the loose calibration: $(tail -2 loose2.log)"
  grep -q "^warning=calibration_energy_balance" loose2/manifest.txt ||
    fail "the reused calibration's warning is not in the result's manifest"
  # Checkpoints: left by a failed solve on the default set-up (the 6th of
  # the 6 solves of its 3 steps: the first ones hold no step yet).
  LEM_FAULT_SOLVE_FAIL=6 run c 2 "${units[@]}" -output_dir c
  [ -s c/checkpoint.bin ] || fail "no checkpoint: $(tail -2 c.log)"
  run c_ground 2 "${units[@]}" -lattice_ground_stiffness 1e-3 -output_dir c &&
    fail "a checkpoint was resumed under another -lattice_ground_stiffness"
  grep -q "checkpoint: -lattice_ground_stiffness=1e-10   this run: -lattice_ground_stiffness=0.001" c_ground.log ||
    fail "the refusal does not name the option: $(tail -3 c_ground.log)"
  run c_parallel 2 "${units[@]}" -sample_parallel -ksp_rtol 1e-9 -output_dir c ||
    fail "the default set-up's checkpoint under -sample_parallel: $(tail -3 c_parallel.log)"
  grep -q "^resumed from" c_parallel.log || fail "-sample_parallel did not resume the checkpoint"
  grep -q "resuming a checkpoint written with other solver options:" c_parallel.log ||
    fail "the other -ksp_rtol was not said"
  echo "ok: one calibration and one result for both set-ups; ground stiffness, coordinates and -ksp_rtol named"
  ;;
outputs)
  case_args=(-lattice_bonds 6000 -lattice_seed 3 -strength_disorder uniform
             -fracture_stop_fraction 0.3 -output_fields false -output_snapshot_steps 4
             -checkpoint_steps 4 -checkpoint_seconds 0)
  run() {  # run DIR [args]: 1 rank, log in DIR.log
    local dir=$1
    shift
    "$build/lem_fracture" "${case_args[@]}" -output_dir "$dir" "$@" > "$dir.log" 2>&1
  }
  user_files=(notes.tmp data.part fields_mine.h5 snapshot_notes.txt snapshots_old.pdf)
  plant() { mkdir -p "$1"; for f in "${user_files[@]}"; do echo "the user's $f" > "$1/$f"; done; }
  check_user_files() {  # DIR WHEN
    for f in "${user_files[@]}"; do
      [ "$(cat "$1/$f" 2>/dev/null)" = "the user's $f" ] || fail "$2 removed or changed the user's $f"
      grep -q "=$f " "$1/manifest.txt" && fail "$2: the manifest lists the user's $f"
    done
  }
  plant whole
  run whole || fail "uninterrupted run: $(tail -2 whole.log)"
  check_user_files whole "a fresh start"
  # Killed (-9) at the 16th pass of the load-step loop, checkpoints every 4.
  LEM_FAULT_PAUSE=load_step:16 "$build/lem_fracture" "${case_args[@]}" -output_dir cut > cut.log 2>&1 &
  leader=$! paused=""
  for _ in $(seq 1 1200); do
    paused=$(sed -n 's/^test hook: rank 0 (pid \([0-9]*\)).*/\1/p' cut.log)
    [ -n "$paused" ] && break
    kill -0 "$leader" 2> /dev/null || fail "the run ended before the pause: $(tail -2 cut.log)"
    sleep 0.1
  done
  [ -n "$paused" ] || { kill -KILL "$leader"; fail "no pause within 120 s"; }
  kill -KILL "$paused"
  wait "$leader"
  [ -s cut/checkpoint.bin ] || fail "no checkpoint before the kill: $(tail -2 cut.log)"
  ls cut/snapshot_*.h5 > /dev/null 2>&1 || fail "no snapshot before the kill"
  # As if the killed run had written a snapshot after its checkpoint.
  first=$(ls cut/snapshot_*.h5 | head -1)
  cp "$first" cut/snapshot_9999999.h5
  cp "${first%.h5}.xmf" cut/snapshot_9999999.xmf
  plant cut
  run cut || fail "resumed run: $(tail -2 cut.log)"
  grep -q "^resumed from" cut.log || fail "the rerun did not resume"
  check_user_files cut "a resume"
  diff <(cut -d, -f1-21 whole/curve.csv) <(cut -d, -f1-21 cut/curve.csv) > /dev/null ||
    fail "the resumed curve differs"
  cmp -s whole/broken.csv cut/broken.csv || fail "the resumed broken.csv differs"
  snapshots() { (cd "$1" && ls snapshot_* snapshots.xmf 2>/dev/null); }
  [ "$(snapshots whole)" = "$(snapshots cut)" ] ||
    fail "other snapshot files: $(snapshots whole | tr '\n' ' ') / $(snapshots cut | tr '\n' ' ')"
  [ "$(snapshots whole | wc -l)" -ge 6 ] || fail "too few snapshots to test anything"
  manifest_files() { grep '^file=' "$1/manifest.txt" | cut -d' ' -f1; }
  [ "$(manifest_files whole)" = "$(manifest_files cut)" ] || fail "the manifests list other files"
  $py - whole cut <<'EOF' || fail "snapshot fields differ"
import glob, os, sys
import h5py, numpy as np
a, b = sys.argv[1:]
for path in sorted(glob.glob(os.path.join(a, "snapshot_*.h5"))):
    other = os.path.join(b, os.path.basename(path))
    with h5py.File(path, "r") as f, h5py.File(other, "r") as g:
        names = []
        f.visit(lambda n: names.append(n) if isinstance(f[n], h5py.Dataset) else None)
        for n in names:
            if not np.array_equal(f[n][()], g[n][()]):
                sys.exit("%s: %s differs" % (os.path.basename(path), n))
EOF
  cmp -s whole/snapshots.xmf cut/snapshots.xmf || fail "snapshots.xmf differs"
  run whole -output_overwrite || fail "-output_overwrite: $(tail -2 whole.log)"
  check_user_files whole "-output_overwrite"
  echo "ok: the resumed run's curve, ruptures and $(snapshots cut | wc -l) snapshot files equal the uninterrupted run's; the user's files kept"
  ;;
*)
  fail "unknown mode $mode"
  ;;
esac
