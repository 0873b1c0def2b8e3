#!/usr/bin/env bash
# The main job: installs what is missing, builds, and runs the aggregation
# scenario of the curl-noise paper (1000 insects, Table 1 parameters) on the
# default OpenCL device (PoCL's CPU device where nothing else is present),
# printing statistics as it goes.  Arguments: [agents] [steps] [device] [min-distance].
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
"$root/scripts/bootstrap.sh"
"$root/scripts/build.sh" >/dev/null
"${SWARMCL_BUILD_DIR:-$root/build}/examples/aggregation" "$@"
