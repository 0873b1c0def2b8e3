#!/usr/bin/env bash
# Runs the model benchmarks of two builds alternately (old, new, new, old),
# so a change that must not slow anything is measured on one machine at one
# time (docs/benchmarks.md).  Usage:
#   bench/compare_builds.sh OLD_BUILD_DIR NEW_BUILD_DIR OUT_DIR
# OUT_DIR gets {old,new}-<bench>-r<round>.json and machine.txt (CPU, load).
# ROUNDS=k repeats the old, new, new, old sequence k times (default 1);
# BENCHES=noise_bench,path_bench runs only those (default: all below).
set -euo pipefail
old=$1 new=$2 out=$3
mkdir -p "$out"
# name, arguments, the option that names the JSON file
benches=(
  "noise_bench|--quick|--json"
  "force_bench|--scenarios moon,horse --counts 10000 --caps 64 --seconds 3|--json"
  "path_bench|--steps 100|--json"
  "energy_bench|--sizes 10000,100000|--json"
  "policy_bench|100000 5|--out"
)
{ grep -m1 "model name" /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'; echo "cores $(nproc)"; } > "$out/machine.txt"
run() {  # run LABEL BUILD ROUND
  for b in "${benches[@]}"; do
    IFS='|' read -r name args json <<< "$b"
    [ -z "${BENCHES:-}" ] || [[ ",$BENCHES," == *",$name,"* ]] || continue
    echo "== $1 round $3: $name $args (load $(cut -d' ' -f1 /proc/loadavg))" | tee -a "$out/machine.txt"
    # shellcheck disable=SC2086
    (cd "$2/bench" && ./$name $args $json "$out/$1-$name-r$3.json" > "$out/$1-$name-r$3.txt" 2>&1) ||
      echo "   $name failed" | tee -a "$out/machine.txt"
  done
}
for ((k = 0; k < ${ROUNDS:-1}; k++)); do
  r1=$((2 * k + 1)) r2=$((2 * k + 2))
  run old "$old" $r1; run new "$new" $r1; run new "$new" $r2; run old "$old" $r2
done
# The benchmarks print where they wrote, as absolute paths: the results are
# kept in the repository, so write those relative to it (tests/python/
# test_machine_paths.py refuses a machine's absolute path in tracked files).
root=$(cd "$(dirname "$0")/.." && pwd)
find "$out" -type f \( -name '*.txt' -o -name '*.json' \) -exec sed -i "s|$root/||g" {} +
