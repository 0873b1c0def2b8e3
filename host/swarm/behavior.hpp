// What a swarm model plugs into the step pipeline (docs/architecture.md,
// "The step"): given the swarm, advance its agents by one time step on the
// device; and which of the swarm's stages run after that, configured per
// model (as FLAME GPU 2 orders its layers): Swarm::step runs advance(), the
// constraint stage (minimum distance enforcement, then the model's own
// after_constraints()), then counts the step statistics.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "device/buffer.hpp"

namespace swarmcl {

class Swarm;
class ByteWriter;
class ByteReader;

// Statistics of a model's minimum distance enforcement, read back from the
// device only when asked for (Swarm::take_step_stats,
// swcl_swarm_take_step_stats).
struct StepStats {
    uint32_t agents = 0;
    uint32_t mde_moved_last = 0;   // agents moved by MDE in the last step
    uint64_t mde_moved_total = 0;  // summed over steps since the last read
    uint64_t steps = 0;            // steps since the last read
};

// The swarm's stages after a model's advance().
struct StepStages {
    // Minimum distance enforcement (kernels/min_distance.cl): pairs closer
    // than `distance` are pushed apart, the pushes' random tie-breaks keyed
    // by `seed`.  0: off.
    float min_distance = 0.0f;
    uint64_t seed = 0;
    // Per world (a swarm of worlds): world k's distance and seed, or empty
    // for min_distance and seed in every world.  min_distance is then their
    // largest (0: the pass is off in every world).
    std::vector<float> world_min_distance;
    std::vector<uint64_t> world_seed;
    // true: the model runs the pass on a spatial index of its own
    // (Behavior::enforce_min_distance); false: the swarm's MinDistance over
    // its neighbour grid.
    bool own_min_distance = false;
    // Whether the swarm counts step statistics for this model (otherwise
    // Swarm::take_step_stats has none to give).
    bool stats = false;
    // false: a step of a swarm without agents runs no constraint stage and
    // is not counted (the force model's rule).
    bool count_empty_steps = true;
};

class Behavior {
public:
    virtual ~Behavior() = default;
    // Step number `step` (0-based, counted over the swarm's life).  Enqueues
    // work only; nothing waits.
    virtual void advance(Swarm& swarm, uint64_t step) = 0;
    // The stages this model asks for (asked at every step).
    virtual StepStages stages() const { return {}; }
    // The MDE pass where stages().own_min_distance: enqueues it, sets
    // moved[0] to the agents it moved and adds them to moved[1].
    virtual void enforce_min_distance(Swarm&, DeviceBuffer<cl_uint>& /*moved*/) {}
    // After the constraint stage (e.g. the force model's obstacle push-out).
    virtual void after_constraints(Swarm&, uint64_t /*step*/) {}

    // Worlds (docs/architecture.md, "Worlds"): parameter `key` of the model's
    // table in every world of the swarm, values[k * components + a] for
    // world k; all checked before any is set (Error(InvalidArgument) naming
    // the parameter, the world and the valid range).  The defaults refuse: a
    // model that does not implement them runs one world only.
    virtual void set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count);
    virtual std::vector<double> world_param(const std::string& key) const;
    // The parameters whose values differ between worlds (checkpoints keep
    // them beside the descriptor, which is the first world's).
    virtual std::vector<std::string> varied_world_params() const { return {}; }

    // Checkpoints (docs/checkpoint-format.md, host/models/model_checkpoint.hpp):
    // save_checkpoint writes the model's descriptor as it is now (section
    // MODL) and what changes over steps that the descriptor does not hold
    // (section MDST); restore_checkpoint reads the latter back into a model
    // just rebuilt from that descriptor for the same swarm (Error(Parse) for
    // state that does not fit it).  The defaults refuse: a model that does
    // not implement them cannot be checkpointed.
    virtual void save_checkpoint(Swarm& swarm, ByteWriter& descriptor, ByteWriter& state);
    virtual void restore_checkpoint(Swarm& swarm, ByteReader& state);
};

}  // namespace swarmcl
