#include "models/min_distance.hpp"

#include "swarm/swarm.hpp"

namespace swarmcl {

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
