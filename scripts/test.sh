#!/usr/bin/env bash
# Runs every test: installs what is missing, builds, then ctest (GoogleTest
# on the default OpenCL device, plus the installed-package check).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/bootstrap.sh"
"$root/scripts/build.sh"
cd "${SWARMCL_BUILD_DIR:-$root/build}"
ctest --output-on-failure -j "$(nproc)"
