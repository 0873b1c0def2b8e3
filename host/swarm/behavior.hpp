// What a swarm model plugs into the step pipeline (DESIGN.md, "The step"):
// given the swarm, advance its agents by one time step on the device.
#pragma once
#include <cstdint>

namespace swarmcl {

class Swarm;

class Behavior {
public:
    virtual ~Behavior() = default;
    // Step number `step` (0-based, counted over the swarm's life).  Enqueues
    // work only; nothing waits.
    virtual void advance(Swarm& swarm, uint64_t step) = 0;
};

}  // namespace swarmcl
