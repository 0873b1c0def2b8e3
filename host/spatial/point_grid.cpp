#include "spatial/point_grid.hpp"

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.hpp"

namespace swarmcl {
namespace {
// Work-items of the bounding box pass; radix blocks and digit width (a few
// thousand cells per agent count: 9 bits, as the force model's fine grid
// was tuned); cells per point at most, and at least this many cells.
constexpr uint32_t kBoundsChunks = 16, kRadixBlocks = 16, kMaxRadixBits = 9;
constexpr uint32_t kMinCells = 1024, kMaxCells = 1u << 30;
}  // namespace

PointGrid::PointGrid(Context& ctx) : ctx_(ctx) {
    bounds_k_ = ctx.kernel("point_grid.cl", "point_grid_bounds");
    geometry_k_ = ctx.kernel("point_grid.cl", "point_grid_geometry");
    keys_k_ = ctx.kernel("point_grid.cl", "point_grid_keys");
    starts_k_ = ctx.kernel("point_grid.cl", "point_grid_starts");
    part_.allocate(ctx, 2 * kBoundsChunks, "point grid bounds");
    geo_.allocate(ctx, 2, "point grid geometry");  // 2 per group in build_groups_apart
    count_.allocate(ctx, 1, "point grid count");
}

// In 64 bits and capped: 8 n wrapped around in 32 bits for n >= 2^29 (a
// 2^29-point grid got 1024 cells), and the cell index must stay 32-bit.
uint32_t PointGrid::max_cells(uint32_t n) {
    return uint32_t(std::clamp<uint64_t>(uint64_t(kCellsPerPoint) * n, kMinCells, kMaxCells));
}

void PointGrid::set_cells_per_point(uint32_t cells) {
    require(cells >= 1 && cells <= kCellsPerPoint, "point grid: cells a point must be 1 to 8");
    cells_per_point_ = cells;
}

uint32_t PointGrid::cells_for(uint32_t n) const {
    return uint32_t(std::clamp<uint64_t>(uint64_t(cells_per_point_) * n, kMinCells, kMaxCells));
}

void PointGrid::reserve(uint32_t n, uint32_t keys) {
    if (allocated_ && n == n_ && keys == keys_) return;
    n_ = n;
    keys_ = keys;
    allocated_ = true;
    radix_.emplace(ctx_, keys - 1u, kRadixBlocks, kMaxRadixBits);
    const size_t slots = std::max<uint32_t>(n, 1);
    for (int k = 0; k < 2; ++k) {
        key_[k].allocate(ctx_, slots, "point grid keys");
        slot_[k].allocate(ctx_, slots, "point grid slots");
    }
    start_.allocate(ctx_, size_t(keys) + 1, "point grid cell starts");
}

void PointGrid::build(const DeviceBuffer<cl_float4>& points, uint32_t n, float min_cell) {
    build_groups(points, n, 1, min_cell);
}

void PointGrid::build_groups(const DeviceBuffer<cl_float4>& points, uint32_t n, uint32_t groups, float min_cell) {
    build_bounded(points, n, groups, min_cell, nullptr);
}

void PointGrid::build_groups_apart(const DeviceBuffer<cl_float4>& points, uint32_t n,
                                   const std::vector<float>& min_cells) {
    require(!min_cells.empty(), "point grid: groups apart need a cell size per group");
    build_bounded(points, n, uint32_t(min_cells.size()), min_cells[0], &min_cells);
}

void PointGrid::build_bounded(const DeviceBuffer<cl_float4>& points, uint32_t n, uint32_t groups, float min_cell,
                              const std::vector<float>* apart_min_cells) {
    require(groups >= 1 && n % groups == 0, "point grid: the groups must split the points evenly");
    const uint32_t cells = cells_for(n / groups);
    require(uint64_t(cells) * groups <= kMaxCells, "point grid: too many groups of cells for 32-bit keys");
    groups_ = groups;
    // One group apart is build(): the same chunks, geometry and keys.
    apart_ = apart_min_cells && groups > 1;
    reserve(n, cells * groups);
    const uint32_t boxes = apart_ ? groups : 1;
    part_.reserve(ctx_, size_t(2) * kBoundsChunks * boxes, "point grid bounds");
    geo_.reserve(ctx_, size_t(2) * boxes, "point grid geometry");
    if (apart_ && (*apart_min_cells != min_cells_host_ || !min_cells_.get()())) {
        // Uploaded when they change only (an upload waits for the queue).
        min_cells_host_ = *apart_min_cells;
        min_cells_.allocate(ctx_, groups, "point grid cell sizes");
        min_cells_.upload(ctx_, min_cells_host_.data(), groups);
    }
    set_args(bounds_k_, points.get(), n, kBoundsChunks, boxes, part_.get());
    launch(ctx_, bounds_k_, size_t(kBoundsChunks) * boxes);
    // Without groups apart the cell sizes are not read (part_ binds the slot).
    if (apart_) {
        set_args(geometry_k_, part_.get(), kBoundsChunks, min_cell, min_cells_.get(), cells, boxes, cl_uint(cells),
                 geo_.get());
    } else {
        set_args(geometry_k_, part_.get(), kBoundsChunks, min_cell, part_.get(), cells, boxes, cl_uint(0u), geo_.get());
    }
    launch(ctx_, geometry_k_, boxes);
    sort_and_count(points);
}

void PointGrid::build(const DeviceBuffer<cl_float4>& points, uint32_t n, const GridGeometry& g) {
    groups_ = 1;
    apart_ = false;
    reserve(n, g.cell_count());
    const cl_int cells = cl_int(g.cell_count());
    cl_float4 geo[2] = {{{g.origin[0], g.origin[1], g.origin[2], 1.0f / g.cell}}, {}};
    for (int a = 0; a < 3; ++a) std::memcpy(&geo[1].s[a], &g.dims[size_t(a)], sizeof(float));
    std::memcpy(&geo[1].s[3], &cells, sizeof(float));
    geo_.upload(ctx_, geo, 2);
    sort_and_count(points);
}

void PointGrid::sort_and_count(const DeviceBuffer<cl_float4>& points) {
    const uint32_t n = n_;
    sorted_key_ = &key_[0];
    sorted_slot_ = &slot_[0];
    if (n > 0) {
        set_args(keys_k_, points.get(), n, n / groups_, cl_uint(apart_ ? 1u : 0u), geo_.get(), key_[0].get(),
                 slot_[0].get(), count_.get());
        launch(ctx_, keys_k_, n);
        RadixSort::Columns a{&key_[0], &slot_[0], nullptr}, b{&key_[1], &slot_[1], nullptr};
        radix_->sort(count_, a, b, n);  // count_ holds n
        sorted_key_ = a.key;
        sorted_slot_ = a.slot;
    }
    set_args(starts_k_, sorted_key_->get(), n, groups_, geo_.get(), start_.get());
    launch(ctx_, starts_k_, size_t(n) + 1);
}

GridGeometry PointGrid::read_geometry(uint32_t group) {
    require(group == 0 || (apart_ && group < groups_), "point grid: no geometry of group " + std::to_string(group));
    std::vector<cl_float4> all(size_t(2) * (apart_ ? groups_ : 1));
    geo_.download(ctx_, all.data(), all.size());
    const cl_float4* geo = all.data() + size_t(2) * group;
    GridGeometry g;
    for (int a = 0; a < 3; ++a) {
        g.origin[size_t(a)] = geo[0].s[a];
        std::memcpy(&g.dims[size_t(a)], &geo[1].s[a], sizeof(float));
    }
    g.cell = 1.0f / geo[0].s[3];
    return g;
}

}  // namespace swarmcl
