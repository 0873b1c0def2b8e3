#include "spatial/grid_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace swarmcl {

GridGeometry GridGeometry::cover(const float lo[3], const float hi[3], float radius, uint32_t max_cells) {
    GridGeometry g;
    double cell = radius;
    for (int attempt = 0; attempt < 64; ++attempt) {
        double total = 1.0;
        for (int a = 0; a < 3; ++a) total *= std::max(1.0, std::ceil((double(hi[a]) - lo[a]) / cell));
        if (total <= max_cells) break;
        cell *= std::max(1.01, std::cbrt(total / max_cells));
    }
    g.cell = float(cell);
    for (int a = 0; a < 3; ++a) {
        g.origin[a] = lo[a];
        g.dims[a] = int32_t(std::max(1.0, std::ceil((double(hi[a]) - lo[a]) / cell)));
    }
    return g;
}

}  // namespace swarmcl
