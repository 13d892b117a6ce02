#!/bin/bash
# The programs other than lem_fracture keep the same contract for their result
# folder (docs/reference/result-folder.md, "manifest.txt and the commit"): a finished
# result is recognised and not computed again, another run's result is refused
# rather than replaced, a manifest missing the checksum of one of its files is
# refused as damaged, -output_overwrite computes it again in place of the
# old one and keeps files that are not the program's (a study's run.json).
# Usage: check_result_contract.sh BIN_DIR WORKDIR
set -u
bin="$1"; work="$2"
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }
check() {  # check NAME PROGRAM OPTION_A OPTION_B -- ARGS...: the contract for one program
  local name="$1" prog="$2" a="$3" b="$4"; shift 5
  local d="$work/$name"
  "$bin/$prog" "$@" $a -output_dir "$d" > "$d.log" 2>&1 || fail "$name: $(tail -3 "$d.log")"
  grep -qx "program=$prog" "$d/manifest.txt" || fail "$name: no manifest of $prog"
  echo '{"study": 1}' > "$d/run.json"
  local old; old=$(cd "$d" && md5sum manifest.txt)
  "$bin/$prog" "$@" $a -output_dir "$d" > "$d.log" 2>&1 || fail "$name rerun: $(tail -3 "$d.log")"
  grep -q "is complete (manifest.txt): nothing to do" "$d.log" || fail "$name: computed again"
  # A manifest with checksums has one for every file it lists: without one
  # a changed file would pass as committed.
  local first; first=$(sed -n 's/^file=\([^ ]*\) .*/\1/p' "$d/manifest.txt" | head -1)
  cp "$d/manifest.txt" "$d.manifest"
  grep -v "^checksum=$first " "$d.manifest" > "$d/manifest.txt"
  "$bin/$prog" "$@" $a -output_dir "$d" > "$d.log" 2>&1
  [ $? -eq 1 ] || fail "$name: a manifest without the checksum of $first was accepted"
  grep -q "manifest '$d/manifest.txt' is damaged (no checksum of $first, though it has those of the other files)" "$d.log" ||
    fail "$name: manifest without a checksum: $(tail -2 "$d.log")"
  cp "$d.manifest" "$d/manifest.txt"
  "$bin/$prog" "$@" $b -output_dir "$d" > "$d.log" 2>&1
  [ $? -eq 1 ] || fail "$name: another run's result was replaced without -output_overwrite"
  grep -q "holds the finished result of another run" "$d.log" || fail "$name: $(tail -2 "$d.log")"
  [ "$(cd "$d" && md5sum manifest.txt)" = "$old" ] || fail "$name: the refused run changed the result"
  "$bin/$prog" "$@" $b -output_dir "$d" -output_overwrite > "$d.log" 2>&1 ||
    fail "$name overwrite: $(tail -3 "$d.log")"
  [ "$(cd "$d" && md5sum manifest.txt)" != "$old" ] || fail "$name: -output_overwrite kept the old result"
  grep -q study "$d/run.json" || fail "$name: run.json was lost"
  [ ! -e "$d.overwrite" ] || fail "$name: the staging folder is left"
  echo "ok: $prog: finished result recognised, another run refused, -output_overwrite replaced it"
}
check tension lem_tension "-load_displacement 3e-4" "-load_displacement 2e-4" -- -lattice_nodes 400
check packing lem_pack "-pack_seed 1" "-pack_seed 2" -- -pack_particles 100 -pack_sample_particles 20
