#!/usr/bin/env bash
# Fuzzes every parser of outside bytes (bench/fuzz/targets.cmake) with
# libFuzzer + ASan + UBSan, each target for SECONDS (default 600), two at a
# time under nice; then writes bench/results/fuzz/<UTC date>.json and prints it.
#
#   bash bench/fuzz/run.sh [SECONDS] [TARGET...]
#
# Builds into build-fuzz/ with clang (installs clang and libclang-rt-dev from
# Debian when missing, as scripts/bootstrap.sh does for the normal build).
# The growing corpus stays in build-fuzz/corpus/<target>/ between runs;
# seeds come from bench/fuzz/corpus/<target>/ and the example files.  A crash
# leaves its input in build-fuzz/artifacts/<target>/: minimise it
# (build-fuzz/bench/fuzz/fuzz_<target> -minimize_crash=1 -runs=10000 FILE),
# fix the parser, and commit it under tests/fuzz_regressions/<target>/, which
# the normal test run replays (ctest -R fuzz_replay).
set -euo pipefail

secs="${1:-600}"
shift || true
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
cd "$root"
build="$root/build-fuzz"
jobs=2

# ---- toolchain -----------------------------------------------------------------
need=()
command -v clang++ >/dev/null || need+=(clang)
fuzzer_lib_ok() {
  echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' |
    clang++ -x c++ -fsanitize=fuzzer,address,undefined - -o /dev/null 2>/dev/null
}
if [ ${#need[@]} -gt 0 ] || ! fuzzer_lib_ok; then
  ver="$(clang++ --version 2>/dev/null | sed -n 's/.*clang version \([0-9]*\).*/\1/p' | head -1)"
  need+=("libclang-rt-${ver:-14}-dev")
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  echo "fuzz: installing ${need[*]}"
  DEBIAN_FRONTEND=noninteractive $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi

# ---- targets and build ---------------------------------------------------------
declare -A seeds
all=()
while read -r name dirs; do
  all+=("$name")
  seeds[$name]="$dirs"
done < <(cmake -P bench/fuzz/list_targets.cmake)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")

CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Debug \
  -DCMAKE_CXX_FLAGS_DEBUG="-O1 -g" -DCMAKE_C_FLAGS_DEBUG="-O1 -g" -DSWARMCL_BUILD_FUZZERS=ON \
  -DSWARMCL_BUILD_TESTS=OFF -DSWARMCL_BUILD_EXAMPLES=OFF -DSWARMCL_BUILD_BENCH=OFF -DSWARMCL_BUILD_CLI=OFF >/dev/null
nice -n 10 cmake --build "$build" -j"$jobs" --target "${targets[@]/#/fuzz_}"

# ---- run, two at a time ----------------------------------------------------------
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
logs="$build/logs"
mkdir -p "$logs"
run_one() {
  local t="$1" corpus="$build/corpus/$1" art="$build/artifacts/$1/"
  mkdir -p "$corpus" "$art"
  local extra=()
  for d in "bench/fuzz/corpus/$t" ${seeds[$t]}; do [ ! -d "$root/$d" ] || extra+=("$root/$d"); done
  local start end
  start=$(date +%s)
  nice -n 10 "$build/bench/fuzz/fuzz_$t" -max_total_time="$secs" -rss_limit_mb=2048 -timeout=30 \
    -print_final_stats=1 -artifact_prefix="$art" "$corpus" "${extra[@]}" >"$logs/$t.log" 2>&1 || true
  end=$(date +%s)
  echo "$((end - start))" >"$logs/$t.seconds"
}
stamp="$(date -u +%Y-%m-%dT%H%M%SZ)"
marker="$logs/.start-$stamp"
touch "$marker"
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  echo "fuzz: $t for ${secs} s"
  run_one "$t" &
done
wait

# ---- summary -------------------------------------------------------------------
out="$root/bench/results/fuzz"
mkdir -p "$out"
json="$out/$stamp.json"
python3 - "$json" "$secs" "$build" "$marker" "${targets[@]}" <<'PY'
import json, os, platform, re, subprocess, sys
path, secs, build, marker, targets = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5:]
def stat(log, key):
    m = re.findall(r"stat::%s:\s*(\d+)" % key, log)
    return int(m[-1]) if m else None
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), platform.processor())
clang = subprocess.run(["clang++", "--version"], capture_output=True, text=True).stdout.splitlines()[0]
since = os.path.getmtime(marker)
rows = []
for t in targets:
    log = open(f"{build}/logs/{t}.log", errors="replace").read()
    art = f"{build}/artifacts/{t}"
    found = sorted(f for f in os.listdir(art) if os.path.getmtime(os.path.join(art, f)) >= since)
    wall = int(open(f"{build}/logs/{t}.seconds").read())
    execs = stat(log, "number_of_executed_units")
    rows.append({
        "target": t, "seconds_requested": secs, "seconds": wall, "execs": execs,
        "exec_per_s": round(execs / wall, 1) if execs and wall else None,
        "libfuzzer_exec_per_s": stat(log, "average_exec_per_sec"),
        "new_units": stat(log, "new_units_added"), "peak_rss_mb": stat(log, "peak_rss_mb"),
        "corpus_files": len(os.listdir(f"{build}/corpus/{t}")),
        "crashes": len(found), "crash_files": found,
        "status": "crash" if found or "==ERROR" in log or "SUMMARY:" in log else "ok",
    })
result = {"what": "libFuzzer + ASan + UBSan over swarmcl's parsers of outside bytes (bench/fuzz/run.sh)",
          "cpu": cpu, "compiler": clang, "jobs_at_once": 2, "targets": rows}
open(path, "w").write(json.dumps(result, indent=2) + "\n")
print(json.dumps(result, indent=2))
PY
rm -f "$marker"
echo "fuzz: wrote $json"
