#include "spatial/radix_sort.hpp"

#include <algorithm>
#include <utility>

namespace swarmcl {

RadixSort::RadixSort(Context& ctx, uint32_t max_key, uint32_t blocks, uint32_t max_digit_bits)
    : ctx_(ctx), blocks_(blocks) {
    const uint32_t bits = key_bits(max_key);
    passes_ = (bits + max_digit_bits - 1) / max_digit_bits;
    bits_ = (bits + passes_ - 1) / passes_;
    hist_.allocate(ctx, size_t(blocks_) << bits_, "radix sort histogram");
    totals_.allocate(ctx, size_t(1) << bits_, "radix sort totals");
    hist_k_ = ctx.kernel("grid.cl", "radix_hist");
    rows_k_ = ctx.kernel("grid.cl", "radix_rows");
    scatter_k_ = ctx.kernel("grid.cl", "radix_scatter");
}

uint32_t RadixSort::key_bits(uint32_t max_key) {
    uint32_t bits = 1;
    while (bits < 32 && uint64_t(max_key) >> bits) ++bits;
    return bits;
}

uint32_t RadixSort::blocks_for(uint32_t max_count, uint32_t digit_bits, uint32_t max_blocks) {
    const uint64_t per_block = uint64_t(kKeysPerDigit) << digit_bits;
    return uint32_t(std::clamp<uint64_t>(max_count / per_block, 1, max_blocks));
}

void RadixSort::sort(const DeviceBuffer<cl_uint>& count, Columns& a, Columns& b, uint32_t max_count) {
    const uint32_t blocks = blocks_for(max_count);
    const bool ids = a.id != nullptr;
    if (!ids) spare_id_.reserve(ctx_, a.slot->size(), "radix sort id scratch");
    const uint32_t mask = (1u << bits_) - 1u;
    for (uint32_t p = 0; p < passes_; ++p) {
        const uint32_t shift = p * bits_;
        set_args(hist_k_, a.key->get(), count.get(), shift, mask, blocks, hist_.get());
        launch(ctx_, hist_k_, blocks);
        set_args(rows_k_, hist_.get(), blocks, mask + 1u, totals_.get());
        launch(ctx_, rows_k_, mask + 1u);
        // Without ids the slots stand in as the id input (read, never written).
        set_args(scatter_k_, a.key->get(), a.slot->get(), ids ? a.id->get() : a.slot->get(), count.get(), shift,
                 mask, blocks, hist_.get(), totals_.get(), b.key->get(), b.slot->get(),
                 ids ? b.id->get() : spare_id_.get());
        launch(ctx_, scatter_k_, blocks);
        std::swap(a, b);
    }
}

}  // namespace swarmcl
