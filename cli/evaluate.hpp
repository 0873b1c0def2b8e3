// `swarmcl evaluate SCENARIO.json --tracks FILE.csv ...` (docs/evaluation.md).
#pragma once

namespace swarmcl_cli {

// Returns the exit status; throws Usage / Failure as the other commands do.
int cmd_evaluate(int argc, char** argv);

}  // namespace swarmcl_cli
