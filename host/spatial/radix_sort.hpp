// The one stable LSD radix sort on the device (kernels/grid.cl radix_hist,
// radix_rows, radix_scatter): (key, slot, id) triples sorted by key, equal
// keys kept in input order, without atomics (per-block digit histograms, a
// fixed partition, so the result is deterministic).  The length is read on
// the device (*count), so a sort can follow the kernel that counts.  The
// neighbour grid sorts its movers with it, the point grid its slots.
#pragma once
#include <cstdint>

#include "device/buffer.hpp"
#include "device/context.hpp"

namespace swarmcl {

class RadixSort {
public:
    // Keys in [0, max_key]: as few passes as their width needs at <=
    // max_digit_bits bits each, the bits spread evenly; `blocks` work-items
    // (histogram columns) per pass.
    RadixSort(Context& ctx, uint32_t max_key, uint32_t blocks, uint32_t max_digit_bits);

    // The columns of a sort.  id == nullptr: no id column (the slots are
    // sorted alone; the kernel's id output goes to a scratch buffer).
    struct Columns {
        DeviceBuffer<cl_uint>* key = nullptr;
        DeviceBuffer<cl_uint>* slot = nullptr;
        DeviceBuffer<cl_uint>* id = nullptr;
    };

    // Sorts the first *count entries of `a` by key, through `b` and back
    // (one pass each way): on return `a` names the buffers holding the
    // sorted columns and `b` the others.  max_count bounds *count (known on
    // the host): fewer blocks for fewer keys (blocks_for).  Enqueued only.
    void sort(const DeviceBuffer<cl_uint>& count, Columns& a, Columns& b, uint32_t max_count = UINT32_MAX);

    // The blocks a pass of up to max_count keys uses: at least
    // kKeysPerDigit keys a block for each digit value (a block's fixed work
    // is its histogram row: 64 rows of 512 digits were most of a step of 64
    // worlds x 300 agents), at most the constructor's count, at least 1.
    uint32_t blocks_for(uint32_t max_count) const { return blocks_for(max_count, bits_, blocks_); }
    // The same rule for digits of digit_bits and at most max_blocks blocks
    // (the neighbour grid's bucket sort, whose pass 1 is these kernels').
    static uint32_t blocks_for(uint32_t max_count, uint32_t digit_bits, uint32_t max_blocks);
    static constexpr uint32_t kKeysPerDigit = 4;
    // The bits keys in [0, max_key] need (at least 1).
    static uint32_t key_bits(uint32_t max_key);

    uint32_t passes() const { return passes_; }
    uint32_t digit_bits() const { return bits_; }

private:
    Context& ctx_;
    uint32_t blocks_, bits_, passes_;
    DeviceBuffer<cl_uint> hist_, totals_, spare_id_;
    cl::Kernel hist_k_, rows_k_, scatter_k_;
};

}  // namespace swarmcl
