// Fast marching (Sethian 1996) for the eikonal equation |grad u| = f on a
// Grid3, in double on the host (docs/design.md: doubles where accuracy
// needs them).  Used for the minimum cost field of the curl-noise paper (§5.2,
// Eq. 7).
#pragma once
#include <cstdint>
#include <limits>
#include <vector>

#include "fields/grid3.hpp"

namespace swarmcl {

struct FastMarchingOptions {
    bool second_order = false;  // Sethian's second-order upwind stencil where two known cells line up
    // 1: the caller's thread alone; otherwise a second thread beside it
    // where the grid is large (over 2 MB of cells) and the machine has a
    // second processor.  The result is the same bits either way.
    unsigned threads = 0;
};

// u: in: the known values (finite) and +inf elsewhere; out: the solution.
// slowness: f per cell (> 0); +inf marks an impassable cell, which keeps
// u = +inf.  Cells the front never reaches keep +inf.
void fast_march(const Grid3& grid, const std::vector<double>& slowness, std::vector<double>& u,
                const FastMarchingOptions& options = {});

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace swarmcl
