// Minimum distance enforcement over the swarm's grid (kernels/min_distance.cl):
// the constraint stage Swarm::step runs after a model's advance where the
// model's StepStages ask for it; and the step statistics' counters.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "device/buffer.hpp"
#include "spatial/grid_geometry.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

class Swarm;

// The step statistics' counters the swarm keeps between reads: agents moved
// by MDE in the last pass and summed over passes (on the device, written by
// the MDE pass), and the steps since the last read (host).
// With W worlds: moved[k] and moved[W + k] are world k's.
class StepCounters {
public:
    StepCounters(Context& ctx, uint32_t worlds = 1);
    DeviceBuffer<cl_uint>& device() { return moved_; }
    void count_step() { ++steps_; }
    // Zeroes them (enqueued).
    void reset(Context& ctx);
    // Reads and resets them (waits for the device): summed over the worlds,
    // or one per world.
    StepStats take(Swarm& swarm);
    std::vector<StepStats> take_worlds(Swarm& swarm);
    // Checkpoints: the counters without resetting them, and set back.
    StepStats peek(Swarm& swarm);
    std::vector<StepStats> peek_worlds(Swarm& swarm) { return read(swarm); }
    // One per world (steps from the first).
    void restore(Context& ctx, const std::vector<StepStats>& stats);

private:
    std::vector<StepStats> read(Swarm& swarm);
    DeviceBuffer<cl_uint> moved_;
    uint32_t worlds_ = 1;
    uint64_t steps_ = 0;
};

class MinDistance {
public:
    // The distance and seed of every world (StepStages).
    MinDistance(Context& ctx, const StepStages& stages, uint32_t worlds);
    // One world at d_min, keyed by seed.
    MinDistance(Context& ctx, float d_min, uint64_t seed);

    // Rebuilds the grid if needed and pushes apart pairs closer than d_min.
    // moved[0] is set to the number of agents moved, moved[1] increased by it
    // (world k: moved[k] and moved[W + k]).
    void apply(Swarm& swarm, DeviceBuffer<cl_uint>& moved);

    // Whether this pass is the one `stages` asks for.
    bool matches(const StepStages& stages, uint32_t worlds) const;
    // Agents per work-item of the explicit-width kernel
    // (min_distance_enforce_w, 8 or 16 lanes) on CPU devices, used where the
    // grid's cells are at most 8 d_min (20 in worlds of at most 4096 agents);
    // 1 (the scalar kernel everywhere) on
    // other devices or with $SWARMCL_NOISE_WIDTH = 1.
    uint32_t width() const { return width_; }
    // Whether a pass over n agents in all, world_agents a world, on a
    // world's grid `g` runs the wide kernel.
    bool uses_wide_kernel(const GridGeometry& g, uint32_t n, uint32_t world_agents) const;

private:
    std::vector<float> d_min_;     // per world
    std::vector<uint64_t> seed_;   // per world
    float d_min_smallest_ = 0.0f;  // picks the kernel (uses_wide_kernel)
    uint32_t width_;
    // $SWARMCL_MDE_KERNEL when the pass was made: "wide", "scalar" or empty
    // (the cell-size rule of uses_wide_kernel).
    std::string kernel_choice_;
    DeviceBuffer<cl_float> d_min_buf_;
    DeviceBuffer<cl_ulong> seed_buf_;
    cl::Kernel kernel_, wide_;
};

}  // namespace swarmcl
