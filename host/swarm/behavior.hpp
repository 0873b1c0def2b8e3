// What a swarm model plugs into the step pipeline (DESIGN.md, "The step"):
// given the swarm, advance its agents by one time step on the device.
#pragma once
#include <cstdint>
#include <optional>

namespace swarmcl {

class Swarm;

// Statistics of a model's minimum distance enforcement, read back from the
// device only when asked for (swcl_swarm_take_step_stats).
struct StepStats {
    uint32_t agents = 0;
    uint32_t mde_moved_last = 0;   // agents moved by MDE in the last step
    uint64_t mde_moved_total = 0;  // summed over steps since the last read
    uint64_t steps = 0;            // steps since the last read
};

class Behavior {
public:
    virtual ~Behavior() = default;
    // Step number `step` (0-based, counted over the swarm's life).  Enqueues
    // work only; nothing waits.
    virtual void advance(Swarm& swarm, uint64_t step) = 0;
    // Reads and resets the model's statistics (waits for the device); none
    // for a model without them.
    virtual std::optional<StepStats> take_stats(Swarm&) { return std::nullopt; }
};

}  // namespace swarmcl
