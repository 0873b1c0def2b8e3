// Kernel sources by their path under kernels/ ("grid.cl", "lib/philox.cl"):
// the copies embedded at build time, or the files of $SWARMCL_KERNEL_DIR when
// it is set (for kernel development without a rebuild).  `#include "path.cl"`
// lines are expanded here, once per file (a per-width body, "*.inc.cl", at
// every include), so kernels share helpers (lib/grid_common.cl) without a
// device-side include path.
#pragma once
#include <string>

namespace swarmcl {

// The full source of `name` (e.g. "grid.cl") with its includes expanded.
// Throws Error(Io) when a file is missing.
std::string load_kernel_source(const std::string& name);

}  // namespace swarmcl
