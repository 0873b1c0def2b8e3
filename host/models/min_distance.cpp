#include "models/min_distance.hpp"

#include "swarm/swarm.hpp"

namespace swarmcl {

MdeCounters::MdeCounters(Context& ctx) : moved_(ctx, 2, "MDE counters") { moved_.fill(ctx, 0u, 2); }

StepStats MdeCounters::take(Swarm& swarm) {
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

MinDistance::MinDistance(Context& ctx, float d_min, uint64_t seed)
    : d_min_(d_min), seed_(seed), kernel_(ctx.kernel("min_distance.cl", "min_distance_enforce")) {}

void MinDistance::apply(Swarm& swarm, DeviceBuffer<cl_uint>& moved) {
    swarm.ensure_grid();
    const uint32_t n = swarm.agent_count();
    cl_uint i = 0;
    kernel_.setArg(i++, swarm.positions().get());
    kernel_.setArg(i++, swarm.ids().get());
    kernel_.setArg(i++, n);
    i = swarm.grid().set_grid_args(kernel_, i);
    kernel_.setArg(i++, d_min_);
    kernel_.setArg(i++, cl_ulong(seed_));
    kernel_.setArg(i++, swarm.scratch().get());
    kernel_.setArg(i++, moved.get());
    swarm.context().queue().enqueueFillBuffer(moved.get(), cl_uint(0), 0, sizeof(cl_uint));
    launch(swarm.context(), kernel_, n);
    swarm.swap_positions_with_scratch();
}

}  // namespace swarmcl
