# Sourced by the full-disk checks (check_disk_full.sh, check_outputs.sh).
# mount_tmpfs_at DIR SIZE: a fresh tmpfs of SIZE at DIR, or else
#   - under CI (CI=true): the test fails (exit 1).  CI runs as root, where
#     mounting is allowed, so a skip there would hide a broken test;
#   - elsewhere: the test is skipped (exit 77), for a developer who may not
#     mount (not root).
mount_tmpfs_at() {
  local dir="$1" size="$2" why
  while mountpoint -q "$dir" 2> /dev/null; do umount -l "$dir"; done
  mkdir -p "$dir"
  why=$(mount -t tmpfs -o "size=$size" tmpfs "$dir" 2>&1) && return 0
  if [ "${CI:-}" = true ]; then
    echo "FAIL: cannot mount a tmpfs at $dir: $why"
    echo "  CI=true: the full-disk tests must run there (as root); unset CI to skip them"
    exit 1
  fi
  echo "SKIP: cannot mount a tmpfs at $dir (${why:-no reason given}); the full-disk tests need root"
  exit 77
}
