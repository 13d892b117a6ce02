#!/bin/bash
# Configure and build (Release) into build/, installing dependencies first.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bash "$root/jobs/install-deps.sh"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release > "$root/build.log" 2>&1 ||
  { tail -30 "$root/build.log" >&2; exit 1; }
cmake --build "$root/build" -j "$(nproc)" >> "$root/build.log" 2>&1 ||
  { grep -E "error|Error" -A5 "$root/build.log" | head -60 >&2; exit 1; }
