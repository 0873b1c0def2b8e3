// Minimum distance enforcement over the swarm's grid (kernels/min_distance.cl):
// a stage any model can run after its position update.
#pragma once
#include <cstdint>

#include "device/buffer.hpp"

namespace swarmcl {

class Swarm;

class MinDistance {
public:
    MinDistance(Context& ctx, float d_min, uint64_t seed);

    // Rebuilds the grid if needed and pushes apart pairs closer than d_min.
    // moved[0] is set to the number of agents moved, moved[1] increased by it.
    void apply(Swarm& swarm, DeviceBuffer<cl_uint>& moved);

    float distance() const { return d_min_; }

private:
    float d_min_;
    uint64_t seed_;
    cl::Kernel kernel_;
};

}  // namespace swarmcl
