#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the C example on
# the default OpenCL device (PoCL's CPU device where nothing else is present).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/bootstrap.sh"
"$root/scripts/build.sh" >/dev/null
"${SWARMCL_BUILD_DIR:-$root/build}/examples/nearest_neighbors" "$@"
