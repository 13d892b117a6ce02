#!/bin/bash
# Stands in for a driver in the tests of the checkers: writes a result folder
# whose summary.json is a copy of the given file (with a crafted bad value),
# so that a checker can be shown to refuse it.
#   fake_result.sh SUMMARY.json [driver options...] -output_dir DIR
# Every other option is ignored; the other result files are written empty.
set -euo pipefail
summary=$1
shift
dir=
while [ $# -gt 0 ]; do
  if [ "$1" = "-output_dir" ]; then dir=$2; shift; fi
  shift
done
[ -n "$dir" ] || { echo "fake_result.sh: no -output_dir" >&2; exit 1; }
mkdir -p "$dir"
cp "$summary" "$dir/summary.json"
for f in summary.csv fields.h5 fields.xmf sample.h5 sample.xmf; do : > "$dir/$f"; done
