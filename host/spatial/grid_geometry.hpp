// Where the grid's cells are: origin, cell edge and cells per axis.
#pragma once
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace swarmcl {

// An axis-aligned box: a swarm's (or one world's) domain.
struct Domain {
    std::array<float, 3> min, max;
    bool operator==(const Domain& o) const { return min == o.min && max == o.max; }
};

// Whether every world has world 0's domain (none: true).
inline bool same_domains(const std::vector<Domain>& domains) {
    return std::all_of(domains.begin(), domains.end(), [&](const Domain& d) { return d == domains[0]; });
}

struct GridGeometry {
    std::array<float, 3> origin{};
    float cell = 1.0f;
    std::array<int32_t, 3> dims{1, 1, 1};

    uint32_t cell_count() const { return uint32_t(dims[0]) * uint32_t(dims[1]) * uint32_t(dims[2]); }

    // Cells of edge `radius` over [lo, hi].  Where that would be more than
    // `max_cells` cells the edge grows (queries stay exact for any radius;
    // only the number of candidates per cell rises).
    static GridGeometry cover(const float lo[3], const float hi[3], float radius, uint32_t max_cells);
};

}  // namespace swarmcl
