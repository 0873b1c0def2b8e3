#include "spatial/neighbor_grid.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <string>
#include <utility>

#include "core/error.hpp"

namespace swarmcl {
namespace {
// Work-items of the chunked kernels (each loops over a contiguous chunk):
// enough for every core, few enough that per-chunk work stays sequential.
constexpr uint32_t kMoverChunks = 512;   // slots: mover counts and compaction
constexpr uint32_t kMinChunkSlots = 256; // ... but at least this many slots each
constexpr uint32_t kRadixBlocks = 64;    // movers: radix histograms and scatter
// Outputs per work-item of grid_merge and grid_starts: on a CPU long runs
// (each merge work-item starts with a binary search); a GPU wants the
// work-items.
constexpr uint32_t kOutputsPerItemCpu = 4096, kOutputsPerItemGpu = 256;
constexpr uint32_t kStartItems = 64;  // grid_starts: work-items at least (below)
// Digit width (2^11 x kRadixBlocks histogram): 22-bit keys of a 4M-cell grid
// in 2 passes, not 3.  1M locusts, 600k movers: 6.3 ms against 7.0-7.5 at 8
// bits (since the chunked kernels run on both cores).
constexpr uint32_t kMaxRadixBits = 11;
// The bucket sort (sort_movers_in_buckets): the low digit's width at most
// (kernels/grid.cl's BUCKET_MAX_LOW_BITS), and pass 2's work-items at most.
constexpr uint32_t kMaxBucketLowBits = 11;
constexpr uint32_t kBucketItems = 128;

uint32_t div_up(uint32_t a, uint32_t b) { return (a + b - 1) / b; }

// kernels/grid.cl's scan: SCAN_LOCAL work-items per group, SCAN_BLOCK values.
constexpr uint32_t kScanLocal = 256, kScanBlock = 256 * 8;

// The build's path: $SWARMCL_GRID_SORT ("counting" or "chunked") if set,
// else the counting sort on devices of the GPU profile.
bool counting_sort_wanted(const DeviceEntry& device) {
    if (const char* env = std::getenv("SWARMCL_GRID_SORT"); env && *env) return std::string(env) == "counting";
    return !device.cpu_profile;
}

// The movers' sort on the chunked path: the bucket sort on CPU devices
// unless $SWARMCL_MOVER_SORT is "radix" (for comparisons).
bool bucket_sort_wanted(const DeviceEntry& device) {
    if (const char* env = std::getenv("SWARMCL_MOVER_SORT"); env && *env) return std::string(env) != "radix";
    return device.cpu_profile;
}

uint32_t total_cells(const std::vector<GridGeometry>& worlds) {
    require(!worlds.empty(), "neighbour grid: at least one world expected");
    uint64_t total = 0;
    for (const GridGeometry& g : worlds) total += g.cell_count();
    require(total < (uint64_t(1) << 31), "neighbour grid: the worlds' grids exceed 2^31 cells");
    return uint32_t(total);
}
}  // namespace

NeighborGrid::NeighborGrid(Context& ctx, const GridGeometry& geometry, uint32_t capacity, uint32_t worlds)
    : NeighborGrid(ctx, std::vector<GridGeometry>(worlds, geometry), capacity) {}

NeighborGrid::NeighborGrid(Context& ctx, std::vector<GridGeometry> world_geometry, uint32_t capacity)
    : ctx_(ctx), geometry_(std::move(world_geometry)), worlds_(uint32_t(geometry_.size())),
      ncells_(total_cells(geometry_)),
      outputs_per_item_(ctx.device().cpu_profile ? kOutputsPerItemCpu : kOutputsPerItemGpu),
      radix_(ctx, ncells_ - 1u, kRadixBlocks, kMaxRadixBits) {
    std::vector<cl_float4> worlds_geo;
    uint32_t first = 0;
    for (const GridGeometry& g : geometry_) {
        cl_float4 dims;
        for (int a = 0; a < 3; ++a) std::memcpy(&dims.s[a], &g.dims[a], sizeof(float));
        std::memcpy(&dims.s[3], &first, sizeof(float));
        worlds_geo.push_back(cl_float4{{g.origin[0], g.origin[1], g.origin[2], 1.0f / g.cell}});
        worlds_geo.push_back(dims);
        first += g.cell_count();
    }
    world_geometry_.allocate(ctx, worlds_geo.size(), "grid world geometry");
    world_geometry_.upload(ctx, worlds_geo.data(), worlds_geo.size());
    capacity_ = capacity;
    keys_.allocate(ctx, capacity, "grid keys");
    perm_.allocate(ctx, capacity, "grid permutation");
    new_id_.allocate(ctx, capacity, "grid ids in the built order");
    layout_key_.allocate(ctx, capacity, "grid layout keys");
    for (auto* b : {&r_key_, &r_slot_, &r_id_, &st_slot_, &t_key_}) b->allocate(ctx, capacity, "grid movers");
    movers_.allocate(ctx, 1, "grid mover count");
    start_.allocate(ctx, size_t(ncells_) + 1, "grid cell starts");
    layout_start_.allocate(ctx, size_t(ncells_) + 1, "grid layout cell starts");
    chunk_counts_.allocate(ctx, kMoverChunks, "grid chunk counts");
    // An empty grid is valid too: every cell range empty.
    start_.fill(ctx, 0u, size_t(ncells_) + 1);
    // An invalid layout (see invalidate_layout).
    layout_key_.fill(ctx, ncells_, capacity);

    keys_k_ = ctx.kernel("grid.cl", "grid_keys_count", world_defines(worlds_));
    movers_write_ = ctx.kernel("grid.cl", "grid_movers_write");
    sort_runs_ = ctx.kernel("grid.cl", "grid_sort_runs");
    merge_ = ctx.kernel("grid.cl", "grid_merge");
    starts_ = ctx.kernel("grid.cl", "grid_starts");
    permute_state_ = ctx.kernel("grid.cl", "permute_state");
    permute_chunks_ = ctx.kernel("grid.cl", "permute_state_chunks");

    count_cells_ = ctx.kernel("grid.cl", "grid_count_cells", world_defines(worlds_));
    scan_blocks_ = ctx.kernel("grid.cl", "scan_blocks");
    scan_sums_ = ctx.kernel("grid.cl", "scan_sums");
    scan_add_ = ctx.kernel("grid.cl", "scan_add");
    scatter_ = ctx.kernel("grid.cl", "grid_scatter");
    sort_cells_ = ctx.kernel("grid.cl", "grid_sort_cells");
    scan_sums_buf_.allocate(ctx, div_up(ncells_ + 1, kScanBlock), "grid scan sums");
    use_counting_sort(counting_sort_wanted(ctx.device()));
    use_bucket_sort(bucket_sort_wanted(ctx.device()));
}

bool NeighborGrid::use_counting_sort(bool counting) {
    // The scan's groups of 256 work-items must fit the device.
    const auto fits = [&](cl::Kernel& k) {
        return k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(ctx_.device().device) >= kScanLocal;
    };
    counting_ = counting && fits(scan_blocks_) && fits(scan_sums_) && fits(scan_add_);
    return counting_;
}

cl_uint NeighborGrid::set_grid_args(cl::Kernel& kernel, cl_uint index) {
    const auto& g = geometry_[0];
    kernel.setArg(index++, cl_float4{{g.origin[0], g.origin[1], g.origin[2], 0.0f}});
    kernel.setArg(index++, 1.0f / g.cell);
    kernel.setArg(index++, cl_int4{{g.dims[0], g.dims[1], g.dims[2], 0}});
    kernel.setArg(index++, cell_start().get());
    return index;
}

cl_uint NeighborGrid::set_world_grid_args(cl::Kernel& kernel, cl_uint index) {
    index = set_grid_args(kernel, index);
    kernel.setArg(index++, world_geometry_.get());
    return index;
}

void NeighborGrid::invalidate_layout() {
    // Every slot in "cell ncells", so every agent is a mover (an invalid
    // layout always has these contents).
    if (!layout_valid_) return;
    if (start_in_layout_) {  // keep the current ranges: they move to start_
        std::swap(start_, layout_start_);
        start_in_layout_ = false;
    }
    layout_key_.fill(ctx_, ncells_, capacity_);
    layout_valid_ = false;
    layout_n_ = 0;
}

void NeighborGrid::build(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_uint>& ids, uint32_t n,
                         const StageHook& after_stage) {
    build(pos, ids, n, 0, after_stage);
}

void NeighborGrid::build(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_uint>& ids, uint32_t n,
                         uint32_t world_agents, const StageHook& after_stage) {
    const auto stage = [&](const char* name) {
        if (after_stage) after_stage(name);
    };
    built_n_ = n;
    if (layout_valid_ && layout_n_ != n) invalidate_layout();
    start_in_layout_ = false;  // this build's ranges go to start_
    if (n == 0) {
        start_.fill(ctx_, 0u, size_t(ncells_) + 1);
        return;
    }

    if (counting_) {
        build_counting(pos, ids, n, world_agents, stage);
        return;
    }
    // Cell keys, and the movers (cell differs from the layout's) per chunk.
    const uint32_t chunks = std::clamp(n / kMinChunkSlots, 1u, kMoverChunks);
    set_grid_args(keys_k_, 2);
    keys_k_.setArg(0, pos.get());
    keys_k_.setArg(1, n);
    keys_k_.setArg(6, layout_key_.get());
    keys_k_.setArg(7, chunks);
    keys_k_.setArg(8, keys_.get());
    keys_k_.setArg(9, chunk_counts_.get());
    keys_k_.setArg(10, cl_uint(world_agents ? world_agents : 0xFFFFFFFFu));
    keys_k_.setArg(11, world_geometry_.get());
    check_arg_count(keys_k_, 12);
    launch_chunks(ctx_, keys_k_, chunks);
    stage("grid_keys_count");

    // The movers compacted in slot order: r_key = new cell, r_slot = slot,
    // r_id = id; the stayers' slots in st_slot.
    set_args(movers_write_, keys_.get(), layout_key_.get(), ids.get(), n, chunks, chunk_counts_.get(), r_key_.get(),
             r_slot_.get(), r_id_.get(), st_slot_.get(), movers_.get());
    launch_chunks(ctx_, movers_write_, chunks);
    stage("movers_write");
    // The movers sorted by (new cell, id), into r_* (the bucket sort) or
    // wherever the radix sort leaves them.
    DeviceBuffer<cl_uint>*kin = &r_key_, *sin = &r_slot_, *iin = &r_id_, *kout = &t_key_;
    if (bucket_sort_) {
        sort_movers_in_buckets(n);
    } else {
        RadixSort::Columns in{&r_key_, &r_slot_, &r_id_}, out{&t_key_, &t_slot_, &t_id_};
        radix_.sort(movers_, in, out, n);  // movers <= n
        kin = in.key, sin = in.slot, iin = in.id, kout = out.key;
        set_args(sort_runs_, movers_.get(), kin->get(), sin->get(), iin->get(), kRadixBlocks);
        launch(ctx_, sort_runs_, kRadixBlocks);
    }
    stage("sort of movers");
    // The merge of stayers and movers: the permutation, the next layout's
    // keys (into the radix sort's free key buffer) and the ids in the new
    // order; then the cell starts.
    pending_key_ = kout;
    const uint32_t items = div_up(n, outputs_per_item_);
    set_args(merge_, keys_.get(), ids.get(), st_slot_.get(), movers_.get(), kin->get(), sin->get(), iin->get(), n,
             outputs_per_item_, perm_.get(), pending_key_->get(), new_id_.get());
    launch_chunks(ctx_, merge_, items);
    stage("grid_merge");
    // The starts of every cell: outputs split over at least kStartItems
    // work-items when there are few agents in many cells (the cells between
    // an item's outputs are its to write; 64 worlds x 300 agents in 216k
    // cells were 5 items, one writing most cells).
    const uint32_t per_start = std::clamp(div_up(n, kStartItems), 1u, outputs_per_item_);
    set_args(starts_, pending_key_->get(), n, ncells_, per_start, start_.get());
    launch_chunks(ctx_, starts_, div_up(n, per_start));
    stage("grid_starts");
}

void NeighborGrid::sort_movers_in_buckets(uint32_t n) {
    // Pass 1: by the high digit (key >> low bits), as records, in the radix
    // sort's blocks.  Pass 2: each bucket by the low digit, then by id
    // (kernels/grid.cl, "Movers on a CPU").
    const uint32_t top_mask = (1u << bucket_top_bits_) - 1u;
    const uint32_t blocks = RadixSort::blocks_for(n, bucket_top_bits_, kRadixBlocks);
    set_args(bucket_hist_k_, r_key_.get(), movers_.get(), bucket_low_bits_, top_mask, blocks, bucket_hist_.get());
    launch(ctx_, bucket_hist_k_, blocks);
    set_args(bucket_rows_k_, bucket_hist_.get(), blocks, top_mask + 1u, bucket_totals_.get());
    launch(ctx_, bucket_rows_k_, top_mask + 1u);
    set_args(bucket_scatter_k_, r_key_.get(), r_slot_.get(), r_id_.get(), movers_.get(), bucket_low_bits_, top_mask,
             blocks, bucket_hist_.get(), bucket_totals_.get(), records_.get(), n);
    launch_chunks(ctx_, bucket_scatter_k_, blocks);  // a work-group each: 8 KB of private counters
    // Buckets past the last cell's are empty.
    const uint32_t buckets = ((ncells_ - 1u) >> bucket_low_bits_) + 1u;
    const uint32_t items = std::clamp(n / kMinChunkSlots, 1u, kBucketItems);
    set_args(sort_buckets_k_, records_.get(), movers_.get(), bucket_totals_.get(), buckets, items,
             (1u << bucket_low_bits_) - 1u, r_key_.get(), r_slot_.get(), r_id_.get(), n);
    launch_chunks(ctx_, sort_buckets_k_, items);
}

bool NeighborGrid::use_bucket_sort(bool bucket) {
    // Keys of up to 2 x 11 bits (a 4M-cell grid): pass 2's counters are
    // private, 2^11 at most.
    const uint32_t key_bits = RadixSort::key_bits(ncells_ - 1u);
    bucket_sort_ = bucket && key_bits <= 2 * kMaxBucketLowBits;
    if (bucket_sort_) {
        bucket_low_bits_ = key_bits / 2;
        bucket_top_bits_ = key_bits - bucket_low_bits_;
        records_.reserve(ctx_, capacity_, "grid mover records");
        bucket_hist_.reserve(ctx_, size_t(kRadixBlocks) << bucket_top_bits_, "grid bucket histogram");
        bucket_totals_.reserve(ctx_, size_t(1) << bucket_top_bits_, "grid bucket totals");
        if (!bucket_scatter_k_()) {
            bucket_hist_k_ = ctx_.kernel("grid.cl", "radix_hist");
            bucket_rows_k_ = ctx_.kernel("grid.cl", "radix_rows");
            bucket_scatter_k_ = ctx_.kernel("grid.cl", "bucket_scatter");
            sort_buckets_k_ = ctx_.kernel("grid.cl", "grid_sort_buckets");
        }
    } else {
        t_slot_.reserve(ctx_, capacity_, "grid movers");
        t_id_.reserve(ctx_, capacity_, "grid movers");
    }
    return bucket_sort_;
}

void NeighborGrid::build_counting(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_uint>& ids, uint32_t n,
                                  uint32_t world_agents, const std::function<void(const char*)>& stage) {
    // Keys, ranks (in r_key_) and the count of every cell (in start_).
    start_.fill(ctx_, 0u, size_t(ncells_) + 1);
    count_cells_.setArg(0, pos.get());
    count_cells_.setArg(1, n);
    cl_uint i = set_grid_args(count_cells_, 2);
    count_cells_.setArg(i++, cl_uint(world_agents ? world_agents : 0xFFFFFFFFu));
    count_cells_.setArg(i++, world_geometry_.get());
    count_cells_.setArg(i++, keys_.get());
    count_cells_.setArg(i++, r_key_.get());
    count_cells_.setArg(i++, start_.get());
    check_arg_count(count_cells_, i);
    launch(ctx_, count_cells_, n);
    stage("grid_count_cells");
    // The counts become the cell starts (start[ncells] = n).
    const uint32_t len = ncells_ + 1, groups = div_up(len, kScanBlock);
    set_args(scan_blocks_, start_.get(), len, scan_sums_buf_.get());
    launch_groups_2d(ctx_, scan_blocks_, groups, 1, kScanLocal, 1);
    set_args(scan_sums_, scan_sums_buf_.get(), groups);
    launch_groups_2d(ctx_, scan_sums_, 1, 1, kScanLocal, 1);
    set_args(scan_add_, start_.get(), len, scan_sums_buf_.get());
    launch_groups_2d(ctx_, scan_add_, groups, 1, kScanLocal, 1);
    stage("cell starts (prefix sum)");
    // Every agent to its place; each cell's agents by id (the ids in the new
    // order in new_id_, for permute_state: "every agent moved"); the next
    // layout's keys in t_key_.
    movers_.fill(ctx_, n, 1);
    set_args(scatter_, keys_.get(), r_key_.get(), ids.get(), start_.get(), n, perm_.get(), new_id_.get());
    launch(ctx_, scatter_, n);
    stage("grid_scatter");
    pending_key_ = &t_key_;
    set_args(sort_cells_, start_.get(), ncells_, perm_.get(), new_id_.get(), pending_key_->get());
    launch(ctx_, sort_cells_, ncells_);
    stage("grid_sort_cells");
}

void NeighborGrid::permute_state(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_float4>& vel,
                                 const DeviceBuffer<cl_uint>& ids, DeviceBuffer<cl_float4>& pos_out,
                                 DeviceBuffer<cl_float4>& vel_out, DeviceBuffer<cl_uint>& ids_out, uint32_t n) {
    // CPU devices: chunks of slots copied in order, the sources prefetched
    // (kernels/grid.cl, permute_state_chunks); at 1M from random order
    // 20-26 -> 15-20 ms (docs/benchmarks.md, "The permutation in chunks").
    if (ctx_.device().cpu_profile) {
        const uint32_t chunks = std::clamp(n / kMinChunkSlots, 1u, kMoverChunks);
        set_args(permute_chunks_, pos.get(), vel.get(), ids.get(), new_id_.get(), movers_.get(), perm_.get(), n,
                 chunks, pos_out.get(), vel_out.get(), ids_out.get());
        launch_chunks(ctx_, permute_chunks_, chunks);
        return;
    }
    set_args(permute_state_, pos.get(), vel.get(), ids.get(), new_id_.get(), movers_.get(), perm_.get(), n,
             pos_out.get(), vel_out.get(), ids_out.get());
    launch(ctx_, permute_state_, n);
}

void NeighborGrid::reorder_state(DeviceBuffer<cl_float4>& pos, DeviceBuffer<cl_float4>& vel,
                                 DeviceBuffer<cl_uint>& ids, DeviceBuffer<cl_float4>& scratch,
                                 DeviceBuffer<cl_float4>& vel_scratch, DeviceBuffer<cl_uint>& ids_scratch,
                                 uint32_t n) {
    permute_state(pos, vel, ids, scratch, vel_scratch, ids_scratch, n);
    std::swap(pos, scratch);
    std::swap(vel, vel_scratch);
    std::swap(ids, ids_scratch);
    // The state is now in the built order: it is the next build's layout.
    if (n == 0 || n != built_n_) {
        invalidate_layout();
        return;
    }
    // The ranges become the layout's by a swap, not a copy (16 MB for a
    // sparse 4M-cell grid); cell_start() then names layout_start_.
    std::swap(start_, layout_start_);
    start_in_layout_ = true;
    std::swap(layout_key_, *pending_key_);
    layout_valid_ = true;
    layout_n_ = n;
}

}  // namespace swarmcl
