#include "spatial/neighbor_grid.hpp"

namespace swarmcl {
namespace {
// Cells per scan block: the top-level scan is serial over ncells / kScanBlock.
constexpr uint32_t kScanBlock = 256;
}  // namespace

NeighborGrid::NeighborGrid(Context& ctx, const GridGeometry& geometry, uint32_t capacity)
    : ctx_(ctx), geometry_(geometry), ncells_(geometry.cell_count()),
      nblocks_((ncells_ + kScanBlock - 1) / kScanBlock) {
    keys_.allocate(ctx, capacity, "grid keys");
    counts_.allocate(ctx, ncells_, "grid cell counts");
    start_.allocate(ctx, size_t(ncells_) + 1, "grid cell starts");
    perm_.allocate(ctx, capacity, "grid permutation");
    block_sums_.allocate(ctx, nblocks_, "grid scan sums");
    counts_.fill(ctx, 0u, ncells_);
    // An empty grid is valid too: every cell range empty.
    start_.fill(ctx, 0u, size_t(ncells_) + 1);
    count_ = ctx.kernel("grid.cl", "grid_count");
    scan_blocks_ = ctx.kernel("grid.cl", "grid_scan_blocks");
    scan_top_ = ctx.kernel("grid.cl", "grid_scan_top");
    scan_write_ = ctx.kernel("grid.cl", "grid_scan_write");
    scatter_ = ctx.kernel("grid.cl", "grid_scatter");
    sort_ = ctx.kernel("grid.cl", "grid_sort_cells");
    permute_f4_ = ctx.kernel("grid.cl", "permute_float4");
    permute_ids_ = ctx.kernel("grid.cl", "permute_ids");
}

cl_uint NeighborGrid::set_grid_args(cl::Kernel& kernel, cl_uint index) {
    const auto& g = geometry_;
    kernel.setArg(index++, cl_float4{{g.origin[0], g.origin[1], g.origin[2], 0.0f}});
    kernel.setArg(index++, 1.0f / g.cell);
    kernel.setArg(index++, cl_int4{{g.dims[0], g.dims[1], g.dims[2], 0}});
    kernel.setArg(index++, start_.get());
    return index;
}

void NeighborGrid::build(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_uint>& ids, uint32_t n) {
    // counts_ is all zero here: the scatter of the previous build decremented
    // every count back to zero (unless that build was interrupted).
    if (counts_dirty_) counts_.fill(ctx_, 0u, ncells_);
    counts_dirty_ = true;
    set_grid_args(count_, 2);
    count_.setArg(0, pos.get());
    count_.setArg(1, n);
    count_.setArg(6, keys_.get());
    count_.setArg(7, counts_.get());
    launch(ctx_, count_, n);

    set_args(scan_blocks_, counts_.get(), ncells_, kScanBlock, block_sums_.get());
    launch(ctx_, scan_blocks_, nblocks_);
    set_args(scan_top_, block_sums_.get(), nblocks_);
    launch(ctx_, scan_top_, 1);
    set_args(scan_write_, counts_.get(), ncells_, kScanBlock, block_sums_.get(), start_.get(), n);
    launch(ctx_, scan_write_, nblocks_);

    set_args(scatter_, keys_.get(), n, start_.get(), counts_.get(), perm_.get());
    launch(ctx_, scatter_, n);
    counts_dirty_ = false;
    set_args(sort_, start_.get(), ncells_, ids.get(), perm_.get());
    launch(ctx_, sort_, ncells_);
}

void NeighborGrid::permute(const DeviceBuffer<cl_float4>& src, DeviceBuffer<cl_float4>& dst, uint32_t n) {
    set_args(permute_f4_, src.get(), perm_.get(), n, dst.get());
    launch(ctx_, permute_f4_, n);
}

void NeighborGrid::permute_ids(const DeviceBuffer<cl_uint>& src, DeviceBuffer<cl_uint>& dst,
                               DeviceBuffer<cl_uint>& slot_of, uint32_t n) {
    set_args(permute_ids_, src.get(), perm_.get(), n, dst.get(), slot_of.get());
    launch(ctx_, permute_ids_, n);
}

}  // namespace swarmcl
