#!/usr/bin/env bash
# The main job: installs what is missing, builds, runs the default scenario —
# the curl-noise paper's aggregation (examples/scenarios/aggregation.json:
# 1000 insects, Table 1 parameters) — on the default OpenCL device (PoCL's CPU
# device where nothing else is present), printing statistics as it goes, and
# writes its outputs and a picture to out/aggregation/.
# Extra arguments go to `swarmcl run` (e.g. --steps 600, --device nvidia).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${SWARMCL_BUILD_DIR:-$root/build}
out="$root/out/aggregation"
"$root/scripts/bootstrap.sh"
"$root/scripts/build.sh" >/dev/null
"$build/swarmcl" run "$root/examples/scenarios/aggregation.json" --out "$out" --format csv,npy,vtp "$@"

# The picture: matplotlib in a venv kept at build/venv (shared with the tests).
venv="$build/venv"
[ -x "$venv/bin/python" ] || python3 -m venv "$venv"
"$venv/bin/python" -c "import numpy, matplotlib" 2>/dev/null ||
  "$venv/bin/python" -m pip install -q --disable-pip-version-check numpy matplotlib
MPLBACKEND=Agg "$venv/bin/python" "$root/bindings/python/swarmcl/plot.py" "$out"
