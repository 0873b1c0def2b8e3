#!/usr/bin/env bash
# Runs every test: installs what is missing, builds, then ctest (GoogleTest
# on the default OpenCL device, plus the installed-package check).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/bootstrap.sh"
# ccache (bootstrap.sh): the Python package's build below compiles the library
# sources of build/ again with the same flags, and takes them from the cache
# (CMake reads these variables when a build folder is first configured).
if command -v ccache >/dev/null; then
  export CMAKE_C_COMPILER_LAUNCHER="${CMAKE_C_COMPILER_LAUNCHER:-ccache}"
  export CMAKE_CXX_COMPILER_LAUNCHER="${CMAKE_CXX_COMPILER_LAUNCHER:-ccache}"
fi
"$root/scripts/build.sh"
cd "${SWARMCL_BUILD_DIR:-$root/build}"
ctest --output-on-failure -j "$(nproc)"

# ---- Python package: pip-installs the project (scikit-build-core builds the
# library into the wheel; CMake's folder build/python/ is kept, so a rerun only
# rebuilds what changed) into a venv kept at build/venv, then runs pytest.
venv="${SWARMCL_BUILD_DIR:-$root/build}/venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
# The rl extra needs torch: PyTorch's CPU-only index where it answers (a
# ~200 MB wheel), else PyPI's default Linux wheel (CUDA libraries included:
# 5.4 GB, 147 s measured on the 2-core test machine, which cannot resolve
# download.pytorch.org).  docs/rl-swarm.md, "Training", says why.
torch_index=()
if "$venv/bin/python" -c "import urllib.request as u; u.urlopen('https://download.pytorch.org/whl/cpu/', timeout=5)" \
    >/dev/null 2>&1; then
  torch_index=(--extra-index-url https://download.pytorch.org/whl/cpu)
fi
# The package's CMake build compiles the library's sources again: with the
# compiler build/ used (ccache hashes its name: build/ has /usr/bin/c++ and
# scikit-build-core's Ninja build took /usr/bin/g++, so ccache missed) they
# come from ccache.
build_cache="${SWARMCL_BUILD_DIR:-$root/build}/CMakeCache.txt"
CC="$(sed -n 's/^CMAKE_C_COMPILER:FILEPATH=//p' "$build_cache")" \
CXX="$(sed -n 's/^CMAKE_CXX_COMPILER:FILEPATH=//p' "$build_cache")" \
  "$venv/bin/python" -m pip install -q --disable-pip-version-check "${torch_index[@]}" "$root[test,fit,mpi,rl]"
cd "$root"
# The fit tests run `mpirun -np 2` (Open MPI from bootstrap.sh) with python -m
# swarmcl fit and with the swarmcl program; the rl tests need swarmcl[rl].
SWARMCL_REQUIRE_MPI=1 SWARMCL_REQUIRE_RL=1 SWARMCL_CLI="${SWARMCL_BUILD_DIR:-$root/build}/swarmcl" \
  "$venv/bin/python" -m pytest -q -p no:cacheprovider tests/python

# ---- Sanitizers (issue 16): the whole ctest suite once more, built with
# -fsanitize=address,undefined in build-asan/ (docs/reliability.md,
# "Sanitizers"); PoCL and LLVM are not instrumented, their leaks only are
# suppressed (scripts/lsan.supp).  SWARMCL_SKIP_ASAN=1 skips it locally.
if [ "${SWARMCL_SKIP_ASAN:-0}" != 1 ]; then
  "$root/scripts/asan.sh"
fi
