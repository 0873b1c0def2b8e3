#!/usr/bin/env bash
# The thread test (tests/test_threads.cpp) under ThreadSanitizer: builds the
# library and test_threads with -fsanitize=thread in its own build directory
# (build-tsan/, or $1) and runs it.  PoCL and LLVM are not instrumented, so
# scripts/tsan.supp suppresses reports from inside them (and only them);
# any report in swarmcl's code fails the run (halt_on_error, exitcode 66).
#   scripts/tsan.sh [BUILD_DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-$root/build-tsan}"
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo "${launcher[@]}" \
  -DCMAKE_C_FLAGS="-fsanitize=thread" -DCMAKE_CXX_FLAGS="-fsanitize=thread" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=thread" -DCMAKE_SHARED_LINKER_FLAGS="-fsanitize=thread" \
  -DSWARMCL_BUILD_EXAMPLES=OFF -DSWARMCL_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" -j"${JOBS:-2}" --target test_threads
export TSAN_OPTIONS="suppressions=$root/scripts/tsan.supp halt_on_error=1 exitcode=66 second_deadlock_stack=1 ${TSAN_OPTIONS:-}"
"$build/tests/test_threads"
echo "tsan: test_threads clean"
