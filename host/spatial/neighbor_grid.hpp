// The uniform neighbour grid on the device (kernels/grid.cl): cell keys, a
// deterministic sort of agent slots by (cell, agent id) without atomics, and
// the cell ranges the queries and models iterate.
//
// The grid remembers the cell ranges of the order the state is in (the
// "layout": the last build whose permutation was applied with
// reorder_state()).  A build only sorts the agents that left their layout
// cell (in two passes of buckets on CPU devices, else with the one
// RadixSort, spatial/radix_sort.hpp), so rebuilding a nearly sorted swarm (a
// simulation step) costs a few streaming passes and a sort of the movers;
// anything else (a fresh write, a new agent count) is correct too, just a
// full sort.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "device/buffer.hpp"
#include "device/context.hpp"
#include "spatial/grid_geometry.hpp"
#include "spatial/radix_sort.hpp"

namespace swarmcl {

class NeighborGrid {
public:
    // `worlds` grids of `geometry` in one (lib/grid_common.cl, "Worlds"):
    // the cells of world k are k * geometry.cell_count() + cell.
    NeighborGrid(Context& ctx, const GridGeometry& geometry, uint32_t capacity, uint32_t worlds = 1);
    // One grid per world, each of its own geometry (its own domain): world
    // k's cells follow world k - 1's in cell_start().
    NeighborGrid(Context& ctx, std::vector<GridGeometry> world_geometry, uint32_t capacity);

    // Called after each stage of build() (for the benchmark's stage timings).
    using StageHook = std::function<void(const char* stage)>;

    // Sorts the n agents of `pos` (slot order, ids[slot] = agent id) by
    // (cell, id): afterwards permutation()[new slot] = old slot, and
    // cell_start() holds the ranges of the new order.  Requires that within
    // each layout cell the slots are in increasing id order (true of any
    // layout reorder_state() made; invalidate_layout() otherwise).
    // Enqueued only; nothing waits.
    // With worlds, n counts every world's agents, world_agents of each (world
    // k in slots [k world_agents, (k + 1) world_agents) before and after);
    // 0: one world of n.
    void build(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_uint>& ids, uint32_t n,
               const StageHook& after_stage = {});
    void build(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_uint>& ids, uint32_t n,
               uint32_t world_agents, const StageHook& after_stage = {});

    // x_out[s] = x[permutation[s]] for positions, velocities and ids, in one
    // pass, for the last build; changes nothing else (benchmarks time it).
    // `ids` must be the ids the build sorted: where many agents moved the
    // ids come from the build's own copy in the new order (a random-order
    // build then gathers two arrays at random, not three).
    void permute_state(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_float4>& vel,
                       const DeviceBuffer<cl_uint>& ids, DeviceBuffer<cl_float4>& pos_out,
                       DeviceBuffer<cl_float4>& vel_out, DeviceBuffer<cl_uint>& ids_out, uint32_t n);
    // Reorders the state by the last build's permutation (permute_state()
    // into the scratch buffers, swapped in), and the new order becomes the
    // layout the next build starts from.  A model that keeps more per-agent
    // arrays adds them to the permute_state kernel.
    void reorder_state(DeviceBuffer<cl_float4>& pos, DeviceBuffer<cl_float4>& vel, DeviceBuffer<cl_uint>& ids,
                       DeviceBuffer<cl_float4>& scratch, DeviceBuffer<cl_float4>& vel_scratch,
                       DeviceBuffer<cl_uint>& ids_scratch, uint32_t n);
    // The build's algorithm (same result, bitwise): a counting sort of
    // short work-items (atomic ranks, a prefix sum, a sort per cell; for
    // GPUs), or the chunked sort of the movers (for CPU devices).  The
    // default follows the device's profile, $SWARMCL_GRID_SORT ("counting"
    // or "chunked") overrides it.  Returns whether the counting sort is now
    // used (false where the device cannot run its 256-item work-groups).
    bool use_counting_sort(bool counting);
    bool counting_sort() const { return counting_; }
    // The chunked path's sort of the movers (same result, bitwise): two
    // passes of buckets (CPU devices; kernels/grid.cl, "Movers on a CPU") or
    // the RadixSort with a sort of each cell's run by id.  The default
    // follows the device's profile, $SWARMCL_MOVER_SORT=radix forces the
    // radix sort.  Returns whether the buckets are now used (not for grids of
    // over 2^22 cells).
    bool use_bucket_sort(bool bucket);
    bool bucket_sort() const { return bucket_sort_; }

    // The state's order is no longer one a build produced (e.g. agents put
    // back in id order): the next build sorts from scratch.
    void invalidate_layout();

    // World 0's geometry (the grid's, with one world).
    const GridGeometry& geometry() const { return geometry_[0]; }
    const GridGeometry& world_geometry(uint32_t k) const { return geometry_[k]; }

    DeviceBuffer<cl_uint>& cell_start() { return start_in_layout_ ? layout_start_ : start_; }
    DeviceBuffer<cl_uint>& permutation() { return perm_; }

    // Appends the GRID_PARAMS arguments (grid_common.cl) from `index` on;
    // set_world_grid_args the GRID_WORLD_PARAMS (every world's grid too).
    cl_uint set_grid_args(cl::Kernel& kernel, cl_uint index);
    cl_uint set_world_grid_args(cl::Kernel& kernel, cl_uint index);
    uint32_t worlds() const { return worlds_; }

private:
    void sort_movers_in_buckets(uint32_t n);
    void build_counting(const DeviceBuffer<cl_float4>& pos, const DeviceBuffer<cl_uint>& ids, uint32_t n,
                        uint32_t world_agents, const std::function<void(const char*)>& stage);

    Context& ctx_;
    std::vector<GridGeometry> geometry_;  // per world
    uint32_t worlds_ = 1;
    uint32_t ncells_;  // of all worlds
    uint32_t outputs_per_item_;  // grid_merge, grid_starts
    uint32_t capacity_ = 0;
    bool layout_valid_ = false;
    bool start_in_layout_ = false;  // the current ranges are layout_start_'s (after reorder_state)
    uint32_t layout_n_ = 0;
    uint32_t built_n_ = 0;
    // Per slot: keys (cell), perm, new_id (the ids in the built order where
    // many agents moved: kernels/grid.cl, ids_from_build), layout_key (the
    // layout's cell); the movers (r_*), the radix sort's other half (t_*:
    // t_slot_ and t_id_ only for the radix sort; t_key_ the next layout's
    // keys), the stayers' slots.
    // Per cell (+1): start, layout_start.
    DeviceBuffer<cl_uint> keys_, perm_, new_id_, layout_key_, r_key_, r_slot_, r_id_, st_slot_, t_key_, t_slot_,
        t_id_, movers_;
    DeviceBuffer<cl_uint>* pending_key_ = nullptr;  // the last build's keys in its order (r_key_ or t_key_)
    DeviceBuffer<cl_uint> start_, layout_start_, chunk_counts_;
    DeviceBuffer<cl_float4> world_geometry_;  // grid_common.cl's grid_worlds
    RadixSort radix_;  // of the movers, by cell
    // The bucket sort: its digits, the records of pass 1, its histogram.
    bool bucket_sort_ = false;
    uint32_t bucket_low_bits_ = 0, bucket_top_bits_ = 0;
    DeviceBuffer<cl_uint4> records_;
    DeviceBuffer<cl_uint> bucket_hist_, bucket_totals_;
    cl::Kernel bucket_hist_k_, bucket_rows_k_, bucket_scatter_k_, sort_buckets_k_;
    cl::Kernel keys_k_, movers_write_, sort_runs_, merge_, starts_, permute_state_, permute_chunks_;
    // The counting sort (build_counting): its kernels and the scan's group sums.
    bool counting_ = false;
    cl::Kernel count_cells_, scan_blocks_, scan_sums_, scan_add_, scatter_, sort_cells_;
    DeviceBuffer<cl_uint> scan_sums_buf_;
};

}  // namespace swarmcl
