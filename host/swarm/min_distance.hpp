// Minimum distance enforcement over the swarm's grid (kernels/min_distance.cl):
// the constraint stage Swarm::step runs after a model's advance where the
// model's StepStages ask for it; and the step statistics' counters.
#pragma once
#include <cstdint>

#include "device/buffer.hpp"
#include "spatial/grid_geometry.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

class Swarm;

// The step statistics' counters the swarm keeps between reads: agents moved
// by MDE in the last pass and summed over passes (on the device, written by
// the MDE pass), and the steps since the last read (host).
class StepCounters {
public:
    explicit StepCounters(Context& ctx);
    DeviceBuffer<cl_uint>& device() { return moved_; }
    void count_step() { ++steps_; }
    // Zeroes them (enqueued).
    void reset(Context& ctx);
    // Reads and resets them (waits for the device).
    StepStats take(Swarm& swarm);
    // Checkpoints: the counters without resetting them, and set back.
    StepStats peek(Swarm& swarm);
    void restore(Context& ctx, const StepStats& stats);

private:
    DeviceBuffer<cl_uint> moved_;
    uint64_t steps_ = 0;
};

class MinDistance {
public:
    MinDistance(Context& ctx, float d_min, uint64_t seed);

    // Rebuilds the grid if needed and pushes apart pairs closer than d_min.
    // moved[0] is set to the number of agents moved, moved[1] increased by it.
    void apply(Swarm& swarm, DeviceBuffer<cl_uint>& moved);

    float distance() const { return d_min_; }
    uint64_t seed() const { return seed_; }
    // Agents per work-item of the explicit-width kernel
    // (min_distance_enforce_w, 8 or 16 lanes) on CPU devices, used where the
    // grid's cells are at most 5 d_min; 1 (the scalar kernel everywhere) on
    // other devices or with $SWARMCL_NOISE_WIDTH = 1.
    uint32_t width() const { return width_; }
    // Whether a pass over n agents on a grid `g` runs the wide kernel.
    bool uses_wide_kernel(const GridGeometry& g, uint32_t n) const;

private:
    float d_min_;
    uint64_t seed_;
    uint32_t width_;
    cl::Kernel kernel_, wide_;
};

}  // namespace swarmcl
