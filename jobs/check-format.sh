#!/bin/bash
# The C++ sources follow .clang-format (clang-format 14: other versions lay
# some lines out differently, so the check insists on 14).
#   bash jobs/check-format.sh        names each file that differs; exit 1 if any
#   bash jobs/check-format.sh --fix  formats them in place
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
fmt=
for candidate in "${CLANG_FORMAT:-}" clang-format-14 clang-format; do
  if [ -n "$candidate" ] && command -v "$candidate" > /dev/null &&
     "$candidate" --version | grep -q "version 14\."; then
    fmt=$candidate
    break
  fi
done
if [ -z "$fmt" ]; then
  echo "check-format.sh: clang-format 14 not found (Debian 12: apt-get install clang-format-14;" \
       "or set CLANG_FORMAT to its path)" >&2
  exit 1
fi
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
else
  mapfile -t files < <(find cmake drivers include src tests -name '*.cpp' -o -name '*.hpp' -o -name '*.h' | sort)
fi
if [ "${1:-}" = "--fix" ]; then
  "$fmt" -i --style=file "${files[@]}"
  echo "check-format.sh: ${#files[@]} files formatted with $fmt"
  exit 0
fi
bad=0 lines=0
for f in "${files[@]}"; do
  n=$("$fmt" --style=file "$f" | diff "$f" - | grep -c '^<' || true)
  if [ "$n" -gt 0 ]; then
    echo "not formatted: $f ($n lines)"
    bad=$((bad + 1)) lines=$((lines + n))
  fi
done
if [ "$bad" -gt 0 ]; then
  echo "check-format.sh: $bad of ${#files[@]} files ($lines lines) differ from .clang-format;" \
       "format them with: bash jobs/check-format.sh --fix" >&2
  exit 1
fi
echo "check-format.sh: ${#files[@]} files formatted"
