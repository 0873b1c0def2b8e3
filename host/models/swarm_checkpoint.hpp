// Saving a swarm with its model to a checkpoint and loading it back, so that
// a run of N steps equals, bit for bit, k steps + save + load (in any
// context on the same device) + N - k steps (docs/checkpoint-format.md;
// swcl_swarm_save / swcl_swarm_load).  The container is io/checkpoint.hpp;
// the model's part model_checkpoint.hpp and each model's
// Behavior::save_checkpoint / restore_checkpoint.
#pragma once
#include <memory>
#include <string>

#include "models/model_checkpoint.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

// Versions of the swarm's own sections this code writes (and reads up to).
constexpr uint32_t kSwarmSectionVersion = 1;   // SWRM: the SwarmConfig
constexpr uint32_t kAgentSectionVersion = 1;   // AGNT: steps, state in slot order
constexpr uint32_t kStatsSectionVersion = 1;   // STAT: step statistics counters
constexpr uint32_t kStateSectionVersion = 1;   // MDST: the model's state
constexpr uint32_t kWorldsSectionVersion = 2;  // WRLD: worlds (only in a swarm of several); 2: domains of their own

// A checkpoint decoded without a device: everything but the model's state,
// which the rebuilt model reads (Behavior::restore_checkpoint).
struct SwarmCheckpoint {
    SwarmConfig config;
    SwarmState state;
    CheckpointModel model;
    std::string model_state;
    // WRLD: the parameters that differ between worlds, every world's values
    // (key, worlds x components values), set after the model is rebuilt
    // from the first world's descriptor.
    std::vector<std::pair<std::string, std::vector<double>>> world_params;
};

// The checkpoint's bytes (waits for the device).  Error(InvalidArgument) for
// a model that cannot be checkpointed.
std::string swarm_checkpoint_bytes(Swarm& swarm);
// The parse of any bytes: Error(Parse) naming what is wrong, never a crash.
// A libFuzzer target calls it directly, with verify_checksum false so that
// mutations reach the sections (tests/test_checkpoint.cpp does both).
SwarmCheckpoint decode_swarm_checkpoint(const std::string& bytes, bool verify_checksum = true);
// A new swarm in `ctx` from a decoded checkpoint; Error(Parse) where the
// values do not make a valid swarm or model (their validation's message).
std::shared_ptr<Swarm> swarm_from_checkpoint(std::shared_ptr<Context> ctx, const SwarmCheckpoint& checkpoint);

// Files: written atomically (a failed save leaves any earlier file as it was).
void save_swarm(Swarm& swarm, const std::string& path);
std::shared_ptr<Swarm> load_swarm(std::shared_ptr<Context> ctx, const std::string& path);

}  // namespace swarmcl
