#include "swarm/min_distance.hpp"

#include <string>

#include "fields/noise_field.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

StepCounters::StepCounters(Context& ctx) : moved_(ctx, 2, "MDE counters") { moved_.fill(ctx, 0u, 2); }

void StepCounters::reset(Context& ctx) {
    moved_.fill(ctx, 0u, 2);
    steps_ = 0;
}

StepStats StepCounters::take(Swarm& swarm) {
    cl_uint counts[2] = {0, 0};
    moved_.download(swarm.context(), counts, 2);
    moved_.fill(swarm.context(), 0u, 2);
    StepStats s;
    s.agents = swarm.agent_count();
    s.mde_moved_last = counts[0];
    s.mde_moved_total = counts[1];
    s.steps = steps_;
    steps_ = 0;
    return s;
}

StepStats StepCounters::peek(Swarm& swarm) {
    cl_uint counts[2] = {0, 0};
    moved_.download(swarm.context(), counts, 2);
    StepStats s;
    s.agents = swarm.agent_count();
    s.mde_moved_last = counts[0];
    s.mde_moved_total = counts[1];
    s.steps = steps_;
    return s;
}

void StepCounters::restore(Context& ctx, const StepStats& stats) {
    // moved[1] is a 32-bit device counter (the total since the last read).
    const cl_uint counts[2] = {stats.mde_moved_last, cl_uint(stats.mde_moved_total)};
    moved_.upload(ctx, counts, 2);
    steps_ = stats.steps;
}

namespace {
// Measured on 1M agents at 0.05 m (2-core PoCL CPU, CPU time of the pass):
// the wide kernel takes 0.55x the scalar one's at cells of 2 d_min, the same
// at 3 and 4 d_min, 1.6x at 6 d_min.  Since it prefetches its cell starts
// (1M locusts, AVX-512 EPYC, d_min 0.1 m): 0.8x at 4.4 d_min, about the same
// at 6, 1.3x at 9 and 1.8x at 12.
constexpr float kWideCellPerDistance = 5.0f;
// The explicit-width kernel where the noise module uses one (CPU devices;
// $SWARMCL_NOISE_WIDTH = 1 selects the scalar kernel everywhere).
uint32_t mde_width(Context& ctx) { return preferred_noise_width(ctx.device()); }
}  // namespace

MinDistance::MinDistance(Context& ctx, float d_min, uint64_t seed)
    : d_min_(d_min), seed_(seed), width_(mde_width(ctx)),
      kernel_(ctx.kernel("min_distance.cl", "min_distance_enforce")) {
    if (width_ > 1) wide_ = ctx.kernel("min_distance.cl", "min_distance_enforce_w", "-DMDE_WIDTH=" + std::to_string(width_));
}

bool MinDistance::uses_wide_kernel(const GridGeometry& g, uint32_t n) const {
    // The wide kernel pays off where each agent's box holds few candidates:
    // cells of at most kWideCellPerDistance * d_min (the scalar kernel's long
    // loops over big cells predict well).  Its lanes index floats and cells
    // as 32-bit ints.
    return width_ > 1 && g.cell <= kWideCellPerDistance * d_min_ && uint64_t(n) * 4 < (uint64_t(1) << 31) &&
           uint64_t(g.cell_count()) + 1 < (uint64_t(1) << 31);
}

void MinDistance::apply(Swarm& swarm, DeviceBuffer<cl_uint>& moved) {
    swarm.ensure_grid();
    const uint32_t n = swarm.agent_count();
    const bool wide = uses_wide_kernel(swarm.grid().geometry(), n);
    cl::Kernel& k = wide ? wide_ : kernel_;
    cl_uint i = 0;
    k.setArg(i++, swarm.positions().get());
    k.setArg(i++, swarm.ids().get());
    k.setArg(i++, n);
    i = swarm.grid().set_grid_args(k, i);
    k.setArg(i++, d_min_);
    k.setArg(i++, cl_ulong(seed_));
    k.setArg(i++, swarm.scratch().get());
    k.setArg(i++, moved.get());
    check_arg_count(k, i);
    fill_buffer(swarm.context(), moved.get(), cl_uint(0), 0, sizeof(cl_uint));
    launch(swarm.context(), k, wide ? (n + width_ - 1) / width_ : n);
    swarm.swap_positions_with_scratch();
}

}  // namespace swarmcl
