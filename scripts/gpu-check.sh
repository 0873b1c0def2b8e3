#!/usr/bin/env bash
# The GPU run as one command (issue 27; README, "Running on a GPU"), from the
# repository root:
#
#   bash scripts/gpu-check.sh [--prebuilt DIR [--no-build]] [--quick] [--device SELECTOR] [--only STEPS]
#   bash scripts/gpu-check.sh --pack DIR      (on a build machine, see below)
#
# 1. build (Release, no examples) into build-gpu/ ($SWARMCL_BUILD_DIR) when
#    cmake, a C++ compiler and the OpenCL headers are here; else (or when the
#    build fails) use --prebuilt DIR, a folder made by --pack on a machine
#    with the packages: the test and benchmark binaries, stripped, the
#    libswarmcl they use, and the ICD loader as a fallback (a GPU machine
#    without network cannot apt-get anything); --no-build uses it even where
#    a build is possible (saves the build's minutes of device time);
# 2. every GoogleTest binary on the first GPU ($SWARMCL_DEVICE or --device
#    selects another), in parallel, each with its own timeout.  On a GPU the
#    gpu_profile./scalar./lanes variants ctest adds on PoCL are these same
#    runs, so the binaries are run directly (no ctest needed);
# 3. the GPU benchmarks: neighbour pass at 1M and 10M agents, the field and
#    path models at 1M and 10M, the force model at 100k, the energy model at 100k and 1M,
#    the policy model at 100k and 1M, and FLAME GPU 2's "circles" at 1M agents,
#    radius 2, 1 agent per unit volume, its published H100 figure beside ours
#    (bench/results/gpu/summary.json); the grid sort and the policy MLP also by
#    their CPU-device paths, before/after in one run.
#
# Each step has its own timeout and the whole run a budget (480 s,
# $GPU_CHECK_BUDGET_S): a step that would start with under 15 s left is
# recorded as skipped, so one hang cannot eat the device time.  Results:
# bench/results/gpu/*.json (each names the device) and gpu-check.log; with
# $OUT set, summary.json, gpu-check.log and gpu-results.tar.gz (all of it)
# are copied there.  --quick: small sizes and short timeouts, for
# the rehearsal on PoCL (SWARMCL_DEVICE_PROFILE=gpu).  --only STEPS: a
# comma-separated list of the steps to run (e.g. policy,policy_peer), the
# others recorded as not asked for: a rerun of a few steps costs their
# seconds only.
# Exit status: 0 when every step that ran passed, 1 otherwise, 2 on a usage or
# setup error.
set -uo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
prebuilt=""
pack=""
quick=0
nobuild=0
only=""
device_selector="${SWARMCL_DEVICE:-}"
while [ $# -gt 0 ]; do
  case "$1" in
    --prebuilt) prebuilt="${2:?--prebuilt needs a folder}"; shift 2 ;;
    --pack) pack="${2:?--pack needs a folder}"; shift 2 ;;
    --quick) quick=1; shift ;;
    --no-build) nobuild=1; shift ;;
    --device) device_selector="${2:?--device needs a selector}"; shift 2 ;;
    --only) only=",${2:?--only needs a list of steps},"; shift 2 ;;
    -h|--help) sed -n '2,37p' "$0"; exit 0 ;;
    *) echo "gpu-check: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done

test_bins() { find "$1/tests" -maxdepth 1 -type f -name 'test_*' -perm -u+x | sort; }
BENCHES="neighbor_grid_bench noise_bench path_bench force_bench energy_bench policy_bench"

# ---- --pack: a carried build folder -----------------------------------------
if [ -n "$pack" ]; then
  src="${SWARMCL_BUILD_DIR:-$root/build}"
  [ -x "$src/tests/test_device" ] || { echo "gpu-check --pack: no build in $src (bash scripts/build.sh first)" >&2; exit 2; }
  rm -rf "$pack" && mkdir -p "$pack/tests" "$pack/bench" "$pack/fallback-lib"
  for t in $(test_bins "$src"); do cp "$t" "$pack/tests/"; done
  for b in $BENCHES; do cp "$src/bench/$b" "$pack/bench/"; done
  cp "$src/swarmcl" "$pack/" 2>/dev/null || true
  cp -P "$src"/libswarmcl.so* "$pack/" 2>/dev/null || true
  strip --strip-unneeded "$pack"/tests/* "$pack"/bench/* "$pack/swarmcl" 2>/dev/null || true
  # The shared libraries the binaries use beyond the C runtime (the ICD
  # loader, tinyobjloader, libnoise, ...), used only where the GPU machine
  # lacks one of them (first run on an H100: libtinyobjloader was missing).
  ldd "$pack"/tests/* "$pack"/bench/* "$pack/swarmcl" 2>/dev/null | awk '$2 == "=>" && $3 ~ /^\// {print $3}' | sort -u |
    grep -vE '/(libc|libm|libpthread|libdl|librt|libstdc\+\+|libgcc_s|ld-linux[^/]*)\.so' | while read -r l; do cp -L "$l" "$pack/fallback-lib/"; done
  # The ICD loader apart: used only where the machine has none of its own.
  mkdir -p "$pack/fallback-lib/opencl" && mv "$pack"/fallback-lib/libOpenCL.so* "$pack/fallback-lib/opencl/" 2>/dev/null
  # Where the binaries were built: tests read sources (scenarios, kernels)
  # and the CLI from these absolute paths.
  grep -m1 '^CMAKE_HOME_DIRECTORY' "$src/CMakeCache.txt" | cut -d= -f2 > "$pack/SOURCE_DIR"
  (cd "$src" && pwd) > "$pack/BUILD_DIR"
  # One compressed file as well (the folder is ~70 MB, mostly statically
  # linked tests; gzip, present on any machine, makes it a fraction of that).
  tar -C "$(dirname "$pack")" -czf "$pack.tar.gz" "$(basename "$pack")"
  echo "gpu-check --pack: $(du -sh "$pack" | cut -f1) in $pack, $(du -sh "$pack.tar.gz" | cut -f1) as $pack.tar.gz" \
       "(carry either; then: bash scripts/gpu-check.sh --prebuilt $pack.tar.gz --no-build)"
  exit 0
fi

budget=${GPU_CHECK_BUDGET_S:-480}
start=$(date +%s)
results="$root/bench/results/gpu"
mkdir -p "$results"
log="$results/gpu-check.log"
: > "$log"
steps_json=()
failed=0

say() { echo "gpu-check: $*" | tee -a "$log"; }
elapsed() { echo $(( $(date +%s) - start )); }
json_str() { printf '%s' "$1" | sed 's/\\/\\\\/g; s/"/\\"/g' | tr -d '\n'; }

# run_step NAME TIMEOUT_S COMMAND...: runs it under its own timeout (never
# past the budget), output to the log; records status and seconds.
run_step() {
  local name=$1 limit=$2; shift 2
  if [ -n "$only" ] && [[ "$only" != *",$name,"* ]]; then
    steps_json+=("{\"step\": \"$name\", \"status\": \"not asked for\", \"seconds\": 0}")
    return 1
  fi
  local left=$(( budget - $(elapsed) ))
  if [ "$left" -lt 15 ]; then
    say "$name: SKIPPED (budget of ${budget}s spent)"
    steps_json+=("{\"step\": \"$name\", \"status\": \"skipped\", \"seconds\": 0}")
    return 1
  fi
  [ "$limit" -gt "$left" ] && limit=$left
  say "$name (timeout ${limit}s): $*"
  local t0 rc dt status=passed
  t0=$(date +%s)
  timeout --kill-after=10 "$limit" "$@" >>"$log" 2>&1
  rc=$?
  dt=$(( $(date +%s) - t0 ))
  if [ $rc -eq 124 ] || [ $rc -eq 137 ]; then status=timeout; failed=1
  elif [ $rc -ne 0 ]; then status="failed ($rc)"; failed=1; fi
  say "$name: $status in ${dt}s"
  steps_json+=("{\"step\": \"$name\", \"status\": \"$status\", \"seconds\": $dt}")
  [ "$status" = passed ]
}

# ---- 0. the OpenCL device ---------------------------------------------------
# The NVIDIA driver installs libnvidia-opencl.so.1 but, in a bare container,
# not always the ICD file that points the loader at it.
if [ ! -e /etc/OpenCL/vendors/nvidia.icd ] && ldconfig -p 2>/dev/null | grep -q libnvidia-opencl.so.1; then
  if mkdir -p /etc/OpenCL/vendors 2>/dev/null && echo libnvidia-opencl.so.1 > /etc/OpenCL/vendors/nvidia.icd; then
    say "wrote /etc/OpenCL/vendors/nvidia.icd (libnvidia-opencl.so.1)"
  else
    say "libnvidia-opencl.so.1 is installed but /etc/OpenCL/vendors/nvidia.icd is missing and cannot be written (run as root)"
  fi
fi
if command -v nvidia-smi >/dev/null; then
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader >>"$log" 2>&1
fi

# ---- 1. build ---------------------------------------------------------------
missing=()
command -v cmake >/dev/null || missing+=(cmake)
command -v c++ >/dev/null || missing+=("a C++ compiler (g++)")
[ -e /usr/include/CL/cl.h ] || missing+=("OpenCL headers (opencl-headers)")
[ -e /usr/include/CL/opencl.hpp ] || missing+=("OpenCL C++ headers (opencl-clhpp-headers)")
[ -e /usr/include/gtest/gtest.h ] || missing+=("GoogleTest (libgtest-dev)")
build=""
if [ $nobuild = 1 ]; then
  say "--no-build: using --prebuilt"
elif [ ${#missing[@]} -eq 0 ]; then
  b="${SWARMCL_BUILD_DIR:-$root/build-gpu}"
  if run_step build 240 bash -c "cmake -S '$root' -B '$b' -DCMAKE_BUILD_TYPE=Release -DSWARMCL_BUILD_EXAMPLES=OFF >/dev/null && cmake --build '$b' -j \"\$(nproc)\""; then
    build="$b"
  fi
else
  say "cannot build here, missing: ${missing[*]}"
fi
if [ -z "$build" ]; then
  if [ -z "$prebuilt" ]; then
    say "no build: give --prebuilt DIR, a folder made by 'bash scripts/gpu-check.sh --pack DIR' on a machine with" \
        "the packages (scripts/bootstrap.sh installs them), carried here"
    exit 2
  fi
  if [ -f "$prebuilt" ] && [[ "$prebuilt" == *.tar.gz ]]; then
    unpack="$root/build-gpu-prebuilt"
    archive=$(cd "$(dirname "$prebuilt")" && pwd)/$(basename "$prebuilt")
    rm -rf "$unpack" && mkdir -p "$unpack" && tar -C "$unpack" -xzf "$archive" \
      || { say "--prebuilt $prebuilt: cannot unpack"; exit 2; }
    prebuilt=$(find "$unpack" -mindepth 1 -maxdepth 1 -type d | head -1)
  fi
  build=$(cd "$prebuilt" 2>/dev/null && pwd) || { say "--prebuilt $prebuilt: no such folder"; exit 2; }
  say "using the prebuilt folder $build"
  # The binaries name the sources and their build folder by absolute path:
  # point those paths here when they do not exist on this machine.
  if [ -f "$build/SOURCE_DIR" ]; then
    old_src=$(cat "$build/SOURCE_DIR"); old_build=$(cat "$build/BUILD_DIR")
    if [ "$old_src" != "$root" ] && [ ! -e "$old_src" ]; then
      mkdir -p "$(dirname "$old_src")" 2>/dev/null && ln -s "$root" "$old_src" 2>/dev/null \
        && say "linked $old_src -> $root (the sources the binaries were built from)" \
        || say "cannot link $old_src -> $root: tests that read example files will fail"
    fi
    if [ ! -e "$old_build" ]; then
      ln -s "$build" "$old_build" 2>/dev/null && say "linked $old_build -> $build"
    fi
  fi
  # The carried libraries (not the C runtime; see --pack) always, since a
  # bare machine may have no ldd to ask (the second H100 run); the ICD
  # loader only where the machine has none.
  if [ -d "$build/fallback-lib" ]; then
    extra="$build:$build/fallback-lib"
    ldconfig -p 2>/dev/null | grep -q 'libOpenCL\.so\.1 ' || extra="$extra:$build/fallback-lib/opencl"
    export LD_LIBRARY_PATH="$extra${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    say "LD_LIBRARY_PATH=$LD_LIBRARY_PATH"
  fi
fi
[ -x "$build/tests/test_device" ] || { say "no test binaries under $build/tests"; exit 2; }

export SWARMCL_DEVICE="$device_selector"
"$build/swarmcl" devices >>"$log" 2>&1 || say "swarmcl devices failed (no OpenCL platform?): see $log"
device=$("$build/swarmcl" devices 2>/dev/null | tr '\n' ' ' | cut -c1-300)
say "devices: ${device:-none}; selector '${SWARMCL_DEVICE}' (empty: the first GPU, else the first CPU)"

# ---- 2. every test binary -------------------------------------------------------
jobs=$(nproc)
tlimit=150; [ $quick = 1 ] && tlimit=300
tests_dir="$results/tests"
rm -rf "$tests_dir" && mkdir -p "$tests_dir"
# One binary per process slot, each under its own timeout.  --quick (the
# PoCL rehearsal, 2 cores): the device-layer and grid binaries only.
list_tests() {
  if [ $quick = 1 ]; then
    for t in test_device test_kernel_args test_grid test_neighbors test_point_grid test_step_stages; do
      echo "$build/tests/$t"
    done
  else
    test_bins "$build"
  fi
}
list_tests > "$tests_dir/list"
run_step tests $(( tlimit + 30 )) env TESTS_DIR="$tests_dir" TLIMIT="$tlimit" JOBS="$jobs" bash -c \
  'xargs -P "$JOBS" -I{} bash -c '"'"'n=$(basename "$1"); timeout --kill-after=5 "$TLIMIT" "$1" --gtest_brief=1 \
     > "$TESTS_DIR/$n.log" 2>&1; rc=$?; echo "$n $rc" >> "$TESTS_DIR/status"; [ $rc -eq 0 ]'"'"' _ {} < "$TESTS_DIR/list"'
if [ -f "$tests_dir/status" ]; then
  while read -r n rc; do
    [ "$rc" = 0 ] || say "  $n: status $rc ($(grep -m3 -E '^\[  FAILED|Failure|error' "$tests_dir/$n.log" | tr '\n' ' ' | cut -c1-300))"
  done < "$tests_dir/status"
  say "tests: $(awk '$2 == 0' "$tests_dir/status" | wc -l) of $(wc -l < "$tests_dir/list") binaries passed"
fi

# ---- 3. benchmarks ----------------------------------------------------------
bb="$build/bench"
if [ $quick = 1 ]; then
  M1=20000; M10=50000; K100=5000; M1s=20000; CIRCLES=20000; BL=120
else
  M1=1000000; M10=10000000; K100=100000; M1s=1000000; CIRCLES=1000000; BL=90
fi
# Neighbour pass (grid build + every agent counts its neighbours within r)
# against nanoflann on all CPU cores, at the default density (30 within r).
# (1M only: at 10M nanoflann's tree and queries on the host alone took over
# 90 s on the first H100 run; the grid's 10M figures come from the field and
# path models below.)
run_step neighbours "$BL" "$bb/neighbor_grid_bench" --sizes "$M1" --repeats 3 --threads "$jobs" \
  --json "$results/neighbor_grid.json"
# The same pass with the grid built by the CPU devices' chunked sort (the
# GPU default is the counting sort, docs/architecture.md): before/after in
# one run.
run_step neighbours_chunked "$BL" env SWARMCL_GRID_SORT=chunked "$bb/neighbor_grid_bench" --sizes "$M1" --repeats 3 \
  --threads "$jobs" --json "$results/neighbor_grid_chunked.json"
# FLAME GPU 2 circles: radius 2 at 1 agent per unit volume, i.e. 4/3 pi 2^3 =
# 33.51 agents within r on average (the circles fixed-density experiment).
run_step circles "$BL" "$bb/neighbor_grid_bench" --sizes "$CIRCLES" --repeats 5 --radius 2 --density 33.5103 \
  --threads "$jobs" --json "$results/circles.json"
# Field model (and the curl noise it samples).
run_step field_1M "$BL" "$bb/noise_bench" --sizes "$M1" --agents "$M1" --repeats 3 --steps 5 --json "$results/field_1m.json"
run_step field_1M_chunked "$BL" env SWARMCL_GRID_SORT=chunked "$bb/noise_bench" --sizes "$M1" --agents "$M1" --repeats 3 \
  --steps 5 --json "$results/field_1m_chunked.json"
run_step field_10M "$BL" "$bb/noise_bench" --sizes "$M10" --agents "$M10" --repeats 3 --steps 3 --json "$results/field_10m.json"
# Path model: the paper's scenarios briefly, then the locusts setting at N.
run_step path_1M "$BL" "$bb/path_bench" --steps 10 --million "$M1" --json "$results/path_1m.json"
run_step path_10M "$BL" "$bb/path_bench" --steps 3 --million "$M10" --json "$results/path_10m.json"
# Force model: the moon scenario at 100k insects, neighbour sample cap 64.
# (Not 1M: the scenario keeps its domain, so each insect's neighbours within
# the attraction radius grow with N; on the H100 1M did not finish 5 steps in
# 90 s.  On 2 cores here 50k/100k/200k ran 26/9.0/2.9 steps/s.)
run_step force "$BL" "$bb/force_bench" --scenarios moon --counts "$K100" --caps 64 --warmup 3 --seconds 2 \
  --json "$results/force.json"
# Energy model (FASTSWARM aggregation) at 100k and 1M.
run_step energy "$BL" "$bb/energy_bench" --sizes "$K100,$M1s" --steps 5 --warmup 2 --json "$results/energy.json"
# Policy model (the shipped actor) at 100k and 1M.
run_step policy "$BL" "$bb/policy_bench" --out "$results/policy.json" "$K100" 5 "$M1s" 3
# ... and with the MLP of CPU devices at one lane (policy_mlp, the GPU's
# kernel before policy_mlp_tiled): before/after in one run.
run_step policy_lanes1 "$BL" env SWARMCL_POLICY_LANES=1 "$bb/policy_bench" --out "$results/policy_lanes1.json" "$K100" 5
# The MLP's peer on the device: the same layers by cuBLAS through PyTorch
# (float32, TF32 off), where python3 has torch with CUDA (the GPU image).
if python3 -c 'import torch, sys; sys.exit(0 if torch.cuda.is_available() else 1)' 2>/dev/null; then
  run_step policy_peer "$BL" python3 "$root/bench/policy_mlp_gpu_peer.py" --agents "$K100,$M1s" \
    --out "$results/policy_mlp_gpu_peer.json"
else
  say "policy_peer: no torch with CUDA here, skipped"
fi

# ---- summary ----------------------------------------------------------------
total=$(elapsed)
{
  echo "{"
  echo "  \"devices\": \"$(json_str "$device")\","
  echo "  \"device_selector\": \"$(json_str "$SWARMCL_DEVICE")\","
  echo "  \"profile_override\": \"$(json_str "${SWARMCL_DEVICE_PROFILE:-}")\","
  echo "  \"quick\": $quick,"
  echo "  \"build\": \"$(basename "$build")\","
  echo "  \"seconds\": $total,"
  echo "  \"budget_seconds\": $budget,"
  echo "  \"flamegpu2_circles_published\": {\"gpu\": \"NVIDIA H100 PCIe\", \"model\": \"circles_spatial3D_rtc\","
  echo "    \"version\": \"FLAME GPU 2.0.0-rc, CUDA 11.8\", \"agents\": 1000000, \"env_width\": 100,"
  echo "    \"comm_radius\": 2, \"agents_per_unit_volume\": 1, \"ms_per_step\": 2.12,"
  echo "    \"source\": \"github.com/FLAMEGPU/FLAMEGPU2-circles-benchmark, sample/data/h100-525.105.17/2.0.0-rc-h100-11.8-beltsoff/fixed-density_perSimulationCSV.csv: s_step_mean 0.002100-0.002147 s over 3 repeats of 200 steps\"},"
  echo "  \"steps\": ["
  for i in "${!steps_json[@]}"; do
    sep=","; [ "$i" -eq $(( ${#steps_json[@]} - 1 )) ] && sep=""
    echo "    ${steps_json[$i]}$sep"
  done
  echo "  ]"
  echo "}"
} > "$results/summary.json"
say "done in ${total}s (budget ${budget}s); results in bench/results/gpu/"
# $OUT (the device tool's folder) takes few files: the summary, the log and
# everything as one archive.
if [ -n "${OUT:-}" ]; then
  cp "$results/summary.json" "$log" "$OUT/" && tar -C "$results" -czf "$OUT/gpu-results.tar.gz" . \
    && say "copied summary.json, gpu-check.log and gpu-results.tar.gz to \$OUT"
fi
exit $failed
