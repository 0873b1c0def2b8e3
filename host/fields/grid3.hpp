// A regular grid of cubic cells over a box; values live at cell centres
// (the curl-noise paper, §5.1: "the center of the grid cell").
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>

namespace swarmcl {

struct Grid3 {
    std::array<double, 3> origin{};         // min corner of cell (0, 0, 0)
    double h = 1.0;                         // cell edge, m
    std::array<uint32_t, 3> dims{1, 1, 1};  // cells per axis

    size_t count() const { return size_t(dims[0]) * dims[1] * dims[2]; }
    size_t index(uint32_t i, uint32_t j, uint32_t k) const { return i + size_t(dims[0]) * (j + size_t(dims[1]) * k); }
    // Centre of cell (i, j, k) along axis a.
    double center(int a, uint32_t i) const { return origin[a] + (i + 0.5) * h; }
    std::array<double, 3> center(uint32_t i, uint32_t j, uint32_t k) const {
        return {center(0, i), center(1, j), center(2, k)};
    }
    std::array<double, 3> max_corner() const {
        return {origin[0] + dims[0] * h, origin[1] + dims[1] * h, origin[2] + dims[2] * h};
    }
};

// The grid over [lo, hi] with at most `resolution` cells per axis:
// cubic cells of edge max_a (hi_a - lo_a) / resolution_a, so the
// box is covered (the grid may reach past hi on the other axes).  Checks the
// box and the cell count (<= max_cells); Error(InvalidArgument) naming `what`.
Grid3 make_grid(const std::array<float, 3>& lo, const std::array<float, 3>& hi,
                const std::array<uint32_t, 3>& resolution, const char* what, uint64_t max_cells = uint64_t(1) << 28);

}  // namespace swarmcl
