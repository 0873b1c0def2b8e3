#include "fields/grid3.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace swarmcl {

Grid3 make_grid(const std::array<float, 3>& lo, const std::array<float, 3>& hi,
                const std::array<uint32_t, 3>& resolution, const char* what, uint64_t max_cells) {
    const std::string w(what);
    uint64_t cells = 1;
    double h = 0.0;
    for (int a = 0; a < 3; ++a) {
        require(std::isfinite(lo[a]) && std::isfinite(hi[a]) && lo[a] < hi[a],
                w + ": the box must be finite with min < max on every axis");
        require(resolution[a] >= 2, w + ": resolution[" + std::to_string(a) + "] must be >= 2 cells");
        cells *= resolution[a];
        require(cells <= max_cells, w + ": " + std::to_string(resolution[0]) + "x" + std::to_string(resolution[1]) +
                                        "x" + std::to_string(resolution[2]) + " cells is more than the limit (" +
                                        std::to_string(max_cells) + ")");
        h = std::max(h, (double(hi[a]) - lo[a]) / resolution[a]);
    }
    Grid3 g;
    g.h = h;
    for (int a = 0; a < 3; ++a) {
        g.origin[a] = lo[a];
        // Cubic cells: an axis shorter than resolution * h keeps its count
        // of cells only as far as needed to cover the box.
        g.dims[a] = std::max<uint32_t>(2, uint32_t(std::ceil((double(hi[a]) - lo[a]) / h - 1e-9)));
    }
    return g;
}

}  // namespace swarmcl
