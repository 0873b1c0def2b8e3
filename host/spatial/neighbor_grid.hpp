// The uniform neighbour grid on the device (kernels/grid.cl): cell keys, a
// stable deterministic sort of agent slots by (cell, agent id), and the cell
// ranges the queries and models iterate.
#pragma once
#include <cstdint>

#include "device/buffer.hpp"
#include "device/context.hpp"
#include "spatial/grid_geometry.hpp"

namespace swarmcl {

class NeighborGrid {
public:
    NeighborGrid(Context& ctx, const GridGeometry& geometry, uint32_t capacity);

    // Sorts the n agents of `pos` (slot order, ids[slot] = agent id) by cell:
    // afterwards permutation()[new slot] = old slot, and cell_start() holds the
    // ranges of the new order.  Enqueued only; nothing waits.
    void build(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_uint>& ids, uint32_t n);

    // dst[s] = src[permutation[s]] for the last build.
    void permute(const DeviceBuffer<cl_float4>& src, DeviceBuffer<cl_float4>& dst, uint32_t n);
    // ids follow the permutation; slot_of[id] = new slot.
    void permute_ids(const DeviceBuffer<cl_uint>& src, DeviceBuffer<cl_uint>& dst,
                     DeviceBuffer<cl_uint>& slot_of, uint32_t n);

    const GridGeometry& geometry() const { return geometry_; }
    DeviceBuffer<cl_uint>& cell_start() { return start_; }
    DeviceBuffer<cl_uint>& permutation() { return perm_; }

    // Appends the GRID_PARAMS arguments (grid_common.cl) from `index` on.
    cl_uint set_grid_args(cl::Kernel& kernel, cl_uint index);

private:
    Context& ctx_;
    GridGeometry geometry_;
    uint32_t ncells_;
    uint32_t nblocks_;
    bool counts_dirty_ = false;  // a build stopped half way: counts need zeroing
    DeviceBuffer<cl_uint> keys_, counts_, start_, perm_, block_sums_;
    cl::Kernel count_, scan_blocks_, scan_top_, scan_write_, scatter_, sort_, permute_f4_, permute_ids_;
};

}  // namespace swarmcl
