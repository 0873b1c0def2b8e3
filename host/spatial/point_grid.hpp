// A uniform grid over any points (a float4 device buffer and a count) at any
// cell size (kernels/point_grid.cl): the slots sorted by cell with the
// stable RadixSort (so by slot within a cell), each cell's range of sorted
// slots, and the geometry, computed on the device from the points' bounding
// box or given.  The points themselves are not moved; queries walk a cell
// range and read the points through sorted_slots().
//
// The swarm's NeighborGrid is the other index: at the swarm's interaction
// radius, it reorders the agent state and sorts only the agents that left
// their cell.  This one serves radii far from that (the force model's
// repulsion and MDE, docs/force-model.md "the fine grid").
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "device/buffer.hpp"
#include "device/context.hpp"
#include "spatial/grid_geometry.hpp"
#include "spatial/radix_sort.hpp"

namespace swarmcl {

class PointGrid {
public:
    explicit PointGrid(Context& ctx);

    // Cells of edge >= min_cell over the bounding box of the n points,
    // computed on the device (so the grid follows the points without a
    // read-back); the edge grows until there are at most max_cells(n).
    // Enqueued only.
    void build(const DeviceBuffer<cl_float4>& points, uint32_t n, float min_cell);
    // Groups (worlds): the points are `groups` runs of n / groups consecutive
    // points (groups divides n) that never see each other.  One geometry
    // over the bounding box of all of them, at most max_cells(n / groups)
    // cells; group g's cells are the keys [g cells, (g + 1) cells) of
    // cell_start(), and its sorted positions [g n / groups, (g + 1) n /
    // groups).  groups = 1 is build(points, n, min_cell).
    void build_groups(const DeviceBuffer<cl_float4>& points, uint32_t n, uint32_t groups, float min_cell);
    // Groups each with the geometry of its own points' bounding box and cell
    // edge >= min_cells[g], the one build(group's points, n / groups,
    // min_cells[g]) gives the group alone, so
    // a query walks a group's cells in the order it would alone (the force
    // model's worlds sum their repulsion in that order).  Group g's geometry
    // is geometry()[2 g], [2 g + 1], whose w is the key stride
    // max_cells(n / groups), the same for every group (>= each product of
    // dims): group g's cells are the keys [g stride, (g + 1) stride) of
    // cell_start(), its sorted positions [g n / groups, (g + 1) n / groups).
    void build_groups_apart(const DeviceBuffer<cl_float4>& points, uint32_t n, const std::vector<float>& min_cells);
    // The given cells (points outside are clamped into the border cells).
    void build(const DeviceBuffer<cl_float4>& points, uint32_t n, const GridGeometry& geometry);

    // Cells a point of a grid built from a bounding box, unless
    // set_cells_per_point says otherwise.
    static constexpr uint32_t kCellsPerPoint = 8;
    // Cells at most of a grid built over n points from their bounding box
    // (kCellsPerPoint a point; at least 1024, at most 2^30).
    static uint32_t max_cells(uint32_t n);
    // The cells a point the builds from a bounding box allow from now on,
    // 1 to 8 (coarser cells for a search that gains from more points a row:
    // the metrics' 16-lane nearest neighbours, eval/swarm_metrics.cpp).
    void set_cells_per_point(uint32_t cells);
    // The cells of a build from a bounding box over n points (a group's n
    // for build_groups).
    uint32_t cells_for(uint32_t n) const;

    uint32_t count() const { return n_; }
    // geometry()[0] = origin xyz, 1 / cell edge in w; [1] = cells per axis
    // and their product as int bits (grid_common.cl grid_from_geometry).
    DeviceBuffer<cl_float4>& geometry() { return geo_; }
    // sorted_slots()[k] = the slot at sorted position k; sorted_keys()[k]
    // its cell.  Valid after a build with n > 0.
    DeviceBuffer<cl_uint>& sorted_slots() { return *sorted_slot_; }
    DeviceBuffer<cl_uint>& sorted_keys() { return *sorted_key_; }
    // Cell c holds the sorted positions [start[c], start[c + 1]) (group g's
    // cell c: start[g cells + c]).
    DeviceBuffer<cl_uint>& cell_start() { return start_; }
    // The last build's geometry (group g's of build_groups_apart; its key
    // stride is not kept), read back (waits for the device).
    GridGeometry read_geometry(uint32_t group = 0);

private:
    uint32_t cells_per_point_ = kCellsPerPoint;
    void reserve(uint32_t n, uint32_t keys);
    void sort_and_count(const DeviceBuffer<cl_float4>& points);
    void build_bounded(const DeviceBuffer<cl_float4>& points, uint32_t n, uint32_t groups, float min_cell,
                       const std::vector<float>* apart_min_cells);

    Context& ctx_;
    uint32_t n_ = 0, keys_ = 0, groups_ = 1;
    bool apart_ = false;  // build_groups_apart: a geometry per group
    bool allocated_ = false;
    std::optional<RadixSort> radix_;  // its digits follow the cell count
    DeviceBuffer<cl_float4> part_, geo_;  // part_: per-chunk bounding boxes
    DeviceBuffer<cl_float> min_cells_;    // build_groups_apart's, as uploaded
    std::vector<float> min_cells_host_;
    DeviceBuffer<cl_uint> key_[2], slot_[2], count_, start_;
    DeviceBuffer<cl_uint>*sorted_key_ = &key_[0], *sorted_slot_ = &slot_[0];
    cl::Kernel bounds_k_, geometry_k_, keys_k_, starts_k_;
};

}  // namespace swarmcl
