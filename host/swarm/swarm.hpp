// A swarm: agent state on the device (structure of arrays, float4, kept in
// grid-cell order with an id array mapping back), its neighbour grid, and the
// step pipeline (docs/architecture.md, "The step"): the model's advance, the
// constraint stage (minimum distance enforcement) and the step statistics.
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "device/buffer.hpp"
#include "device/context.hpp"
#include "spatial/neighbor_grid.hpp"
#include "swarm/behavior.hpp"
#include "swarm/min_distance.hpp"

namespace swarmcl {

// Worlds (docs/architecture.md, "Worlds"): `worlds` independent swarms of
// agent_count agents each (capacity each), stepped by the same launches.
// World k is placed, seeded and stepped as a swarm alone with seed
// world_seeds[k] (default: seed + k) would be, bitwise, in its own domain
// (world_domains[k]; default domain_min..domain_max); all worlds share the
// model's kernel, each has its own parameter block and grid.
struct SwarmConfig {
    uint32_t capacity = 1024;
    uint32_t agent_count = 0;
    uint64_t seed = 0;
    uint32_t worlds = 1;
    std::vector<uint64_t> world_seeds;  // empty, or one per world
    std::array<float, 3> domain_min{-1.0f, -1.0f, -1.0f};
    std::array<float, 3> domain_max{1.0f, 1.0f, 1.0f};
    // Empty: every world's domain is domain_min..domain_max.  Else one per
    // world; the swarm then sets domain_min/max to world 0's.
    std::vector<Domain> world_domains;
    float interaction_radius = 0.1f;
    float dt = 1.0f / 60.0f;
};

enum class Attribute { Position, Velocity };

// What a step depends on in the swarm itself, for checkpoints
// (host/models/swarm_checkpoint.hpp): the agent state in slot order, as the
// device holds it (so the next step runs on the same arrays in the same
// order), ids[slot] the agent id; the step counter, which with the seeds in
// the configs is all of the random state (Philox is keyed by seed, agent id
// and step: no other RNG state exists); and the step statistics' counters.
struct SwarmState {
    uint64_t steps = 0;
    std::vector<cl_float4> positions, velocities;  // agent_count each, slot order
    std::vector<cl_uint> ids;                      // slot -> agent id, a permutation of 0..n-1 per world
    StepStats stats;                               // counters since the last take_step_stats (summed)
    std::vector<StepStats> world_stats;            // the same per world (several worlds only)
};

class Swarm {
public:
    // Validates the configuration (Error(InvalidArgument) naming the field).
    Swarm(std::shared_ptr<Context> ctx, const SwarmConfig& config);
    // Waits for the swarm's queued work: PoCL compiles a kernel for its launch
    // size when the command runs, and a command still compiling while the
    // process exits crashes inside LLVM (seen with the driver's local sizes,
    // the GPU profile on PoCL, after a last step nobody read).
    ~Swarm();

    // Agents of each world (of the swarm when it has one world).
    uint32_t agent_count() const { return n_; }
    uint32_t worlds() const { return worlds_; }
    // Agents of all worlds (the count of write/read).
    size_t total_agents() const { return size_t(n_) * worlds_; }
    // World k's seed (SwarmConfig::world_seeds).
    uint64_t world_seed(uint32_t k) const;
    // World k's domain (SwarmConfig::world_domains), and whether every world
    // has world 0's.
    const Domain& world_domain(uint32_t k) const { return domains_[k]; }
    const std::vector<Domain>& world_domains() const { return domains_; }
    bool same_domain_in_every_world() const { return same_domain_; }
    // Error(InvalidArgument) naming `what` when the worlds' domains differ
    // (for the parts that need one domain: the path model's grid).
    void require_one_domain(const std::string& what) const;
    uint64_t step_count() const { return steps_; }
    const SwarmConfig& config() const { return config_; }
    Context& context() { return *ctx_; }

    // Packed xyz, agent-id order, world by world (count = worlds x agents a
    // world).  See swcl_swarm_write / swcl_swarm_read.
    void write(Attribute attribute, const float* src, size_t count);
    void read(Attribute attribute, float* dst, size_t count);
    // Steps `frames` x `every` steps and writes the positions after each
    // `every` steps into dst, frame after frame (each as read(Position)
    // gives it; count = frames x total_agents()).  The frames gather on the
    // device and come back a few at a time, so the device is not waited on
    // after every frame (swcl_swarm_step_frames).
    void step_frames(uint32_t frames, uint32_t every, float* dst, size_t count);
    void step(uint32_t steps);

    // Neighbour queries at the current positions, outputs in agent-id order.
    void neighbor_count(float radius, uint32_t* out_counts, size_t count);
    void nearest_neighbor(float* out_distances, uint32_t* out_ids, size_t count);
    uint32_t neighbor_lists(float radius, uint32_t cap, uint32_t* out_ids, uint32_t* out_counts, size_t count);

    // Sorts agents by cell (reordering the state) unless already current.
    void ensure_grid();
    NeighborGrid& grid() { return grid_; }
    DeviceBuffer<cl_float4>& positions() { return pos_; }
    DeviceBuffer<cl_float4>& velocities() { return vel_; }
    DeviceBuffer<cl_uint>& ids() { return ids_; }
    // id -> slot, the inverse of ids(); built on demand (only reads and
    // writes in id order need it, so a step does not pay for it).
    DeviceBuffer<cl_uint>& slot_of() {
        ensure_slot_of();
        return slot_of_;
    }
    // A float4 array of the capacity that a stage may write new positions to,
    // then swap in (the grid then needs a rebuild).
    DeviceBuffer<cl_float4>& scratch() { return scratch_; }
    void swap_positions_with_scratch();
    // Marks positions changed by a stage: the grid is rebuilt when next needed.
    void positions_changed() { grid_current_ = false; }

    // Sets the arguments every model's step kernel starts with, from `index`
    // on: pos, vel, ids (slot order), n, dt, t = step * dt, step; returns the
    // next index.
    cl_uint set_step_args(cl::Kernel& kernel, uint64_t step, cl_uint index = 0);

    // The model that moves the agents (nullptr: ballistic motion); its step
    // statistics start from zero.
    void set_behavior(std::shared_ptr<Behavior> behavior);
    Behavior* behavior() const { return behavior_.get(); }
    // Reads and resets the step statistics (waits for the device); none
    // without a model or for a model whose StepStages count none.  Summed
    // over the worlds; take_world_step_stats gives one per world.
    std::optional<StepStats> take_step_stats();
    std::optional<std::vector<StepStats>> take_world_step_stats();
    // Error(InvalidArgument) naming `what` when the swarm has several worlds
    // (for the parts that do not run worlds yet).
    void require_one_world(const std::string& what) const;

    // Checkpoints: the state now (waits for the device), and a state put
    // back in place of this swarm's (validated first: Error(Parse) for a
    // count above the capacity, ids that are not a permutation, non-finite
    // values; nothing changes then).  Put back after set_behavior, which
    // zeroes the statistics: restore_step_stats puts them back after it.
    SwarmState export_state();
    // With worlds, positions, velocities and ids hold every world's slots
    // (world k's at [k n, (k + 1) n), ids from 0 in each world).
    void import_state(const SwarmState& state);
    void restore_step_stats(const StepStats& stats);
    void restore_world_step_stats(const std::vector<StepStats>& stats);

    // Held by the C API around every call on this swarm.
    std::mutex& mutex() { return mutex_; }

private:
    void check_count(size_t count, const char* what) const;
    void place_uniformly(uint32_t count);
    void set_count(uint32_t n);
    void ensure_slot_of();
    // The stages after the model's advance (Behavior::stages).
    void run_stages(uint64_t step);
    MinDistance& min_distance_pass(const StepStages& stages);

    std::shared_ptr<Context> ctx_;
    SwarmConfig config_;
    std::vector<Domain> domains_;  // per world
    bool same_domain_ = true;
    NeighborGrid grid_;
    uint32_t n_ = 0;  // agents a world
    uint32_t worlds_ = 1;
    uint64_t steps_ = 0;
    bool grid_current_ = false;
    bool slot_of_current_ = true;  // slot_of_ is the inverse of ids_
    DeviceBuffer<cl_float4> pos_, vel_, scratch_, vel_scratch_;  // vel_scratch_: reorder only
    DeviceBuffer<cl_uint> ids_, ids_scratch_, slot_of_;
    DeviceBuffer<cl_float> packed_;  // 3 floats per agent: the caller's layout
    DeviceBuffer<cl_float> frames_;  // step_frames: a few frames of packed positions
    DeviceBuffer<cl_uint> query_u32_;
    DeviceBuffer<cl_float> query_f32_;
    cl::Kernel gather_, scatter_, identity_, integrate_, slot_of_k_, frame_k_;
    cl::Kernel count_, nearest_, lists_;
    uint32_t lanes_ = 1;  // slots a work-item of count_ (neighbor_count_w on CPU devices)
    std::shared_ptr<Behavior> behavior_;
    StepCounters stats_;
    std::optional<MinDistance> mde_;  // the swarm's MDE pass, for the model's distance and seed
    std::mutex mutex_;
};

}  // namespace swarmcl
