// `swarmcl fit SCENARIO.json --tracks FILE.csv --ranges RANGES.json ...`
// (bindings/python/swarmcl/fitting.py; docs/evaluation.md).
#pragma once

namespace swarmcl_cli {

// Replaces this process with `$SWARMCL_PYTHON -m swarmcl fit ARGS`
// (python3 by default); returns only by throwing Failure.
int cmd_fit(int argc, char** argv);

}  // namespace swarmcl_cli
