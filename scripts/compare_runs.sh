#!/usr/bin/env bash
# Runs every example scenario with two builds' swarmcl programs and compares
# the trajectories byte for byte (a change that must not change any result):
#   scripts/compare_runs.sh OLD_BUILD_DIR NEW_BUILD_DIR [STEPS]
# Prints one line per scenario; exits 1 when any differs or fails.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
old=$1 new=$2 steps=${3:-30}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
for f in "$root"/examples/scenarios/*.json; do
  s=$(basename "$f" .json)
  for v in old new; do
    b=$old; [ $v = new ] && b=$new
    if ! "$b/swarmcl" run "$f" --out "$tmp/$v-$s" --format npy --steps "$steps" > "$tmp/$v-$s.log" 2>&1; then
      echo "$s: the $v build failed (see its output below)"; cat "$tmp/$v-$s.log"; status=1; continue 2
    fi
  done
  same=yes
  for g in "$tmp/old-$s"/*.npy; do cmp -s "$g" "$tmp/new-$s/$(basename "$g")" || same=no; done
  echo "$s: $steps steps, positions and velocities bitwise the same: $same"
  [ $same = yes ] || status=1
done
exit $status
