// The batched leader-following RL environment on the device (issue 15; paper
// drl-swarm-animation-rule-based-action-generator, §III-B-D): W independent
// worlds of N followers and one leader, stepped in one launch per stage
// (kernels/rl_env.cl).  Everything crosses as whole arrays in agent-slot
// order (slot = world * N + agent), never per agent.  docs/rl-swarm.md.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "device/buffer.hpp"
#include "device/context.hpp"

namespace swarmcl {

// Per-step reward parameters (Eq. 14-19).  Weights: Table 1.  The rates λ
// are not in the paper: ours, chosen so each term spans most of (0, w] over
// the distances and speeds of Table 1's zones (docs/rl-swarm.md).
struct RlRewardParams {
    float w_spd = 1.3f, w_dir = 1.0f, w_leader = 4.9f, w_obs = 16.0f, w_dist = 9.5f;
    float l_spd = 2.0f, l_dir = 1.0f, l_leader = 0.1f, l_obs = 0.5f;
    // Eq. 19's preferred neighbour distance; 0: (R_ali - R_sep) / 2 as
    // printed in Eq. 19.
    float dist_target = 0.0f;
};

struct RlObstacleBox {
    std::array<float, 3> center{}, half{};
};

enum class RlLeaderMode : int { Joystick = 0, Navigation = 1 };

struct RlEnvConfig {
    uint32_t worlds = 1, agents = 100;
    // Table 1.
    float dt = 0.1f, du_max = 0.1f, dq_max_deg = 4.0f;
    float r_sep = 1.0f, r_ali = 9.0f, r_coh = 18.0f;
    uint32_t max_steps = 1200;  // M: truncation
    // Ours (docs/rl-swarm.md).
    float u_max = 3.0f;           // speed ceiling of every agent
    float body_radius = 0.5f;     // agents' sphere for the rays
    float neighbor_radius = 0.0f; // EFS and reward neighbours; 0: r_coh
    bool efs = true;              // false: the ablation, 51 observations
    float rag_w_sep = 4.0f, rag_w_ali = 2.0f, rag_w_coh = 2.0f;  // Eq. 8's w_*
    // The RAG's leader coupling (ours; the paper does not say how its RAG
    // follows the leader): a proportional-derivative pull k_p (|p_L - p| -
    // R_ali)+ toward the leader plus k_d (v_L - v), critically damped for
    // k_d^2 = 4 k_p; false: the leader is one more Eq. 8 term in its zone
    // (the coupling before, which surges and brakes around R_ali).
    bool rag_leader_pd = true;
    float rag_leader_kp = 0.25f, rag_leader_kd = 1.0f;
    RlRewardParams reward;
    // Leader: joystick (controls per world, set_leader_controls) or
    // navigation through waypoints (x, y, z, target speed).
    RlLeaderMode leader_mode = RlLeaderMode::Joystick;
    std::vector<std::array<float, 4>> waypoints;
    float leader_du_max = 0.1f, leader_dq_max_deg = 4.0f, reach_radius = 2.0f;
    // Joystick mode: the leader starts at the origin with a speed in
    // [leader_u0_min, leader_u0_max] and a random horizontal heading
    // (Algorithm 1 line 8); navigation: at waypoint 0 heading to waypoint 1.
    float leader_u0_min = 0.5f, leader_u0_max = 1.0f;
    // Followers start in a ball of this radius centred spawn_back behind the
    // leader, with its heading and speed.
    float spawn_radius = 6.0f, spawn_back = 8.0f;
    std::vector<RlObstacleBox> obstacles;  // shared by every world
};

// Largest W * N accepted (obs arrays stay below 2^31 floats).
constexpr uint64_t kRlMaxAgents = 1ull << 24;

class LeaderEnv {
public:
    LeaderEnv(Context& ctx, RlEnvConfig config);

    uint32_t worlds() const { return c_.worlds; }
    uint32_t agents() const { return c_.agents; }
    uint32_t obs_dim() const { return c_.efs ? 54u : 51u; }
    const RlEnvConfig& config() const { return c_; }

    // Every world to its start state (philox(seed, world, episode 0)); the
    // observations of the new state are computed.
    void reset(uint64_t seed);
    // The same with a seed per world (worlds() entries): world w gets the
    // bits it gets from reset(seeds[w]).
    void reset(const std::vector<uint64_t>& seeds);
    // Only the worlds with mask[w] != 0, each to its next episode's start.
    void reset_worlds(const uint8_t* mask, size_t count);
    // One step: the leader, then the followers by actions (W*N*4 floats,
    // finite), then observations and rewards.
    void step(const float* actions, size_t count);
    // Joystick controls per world: W*4 floats {Δu, Δq.xyz}, kept until changed.
    void set_leader_controls(const float* ctl, size_t count);

    void read_observations(float* out, size_t count);
    void read_rewards(float* out, size_t count);
    void read_terminated(uint8_t* out, size_t count) const;
    void read_truncated(uint8_t* out, size_t count) const;
    // RAG actions (Eq. 8-10) for the current state: W*N*4 floats.
    void rag_actions(float* out, size_t count);
    // State: positions / velocity (q.xyz, u) per follower (W*N*4 floats each),
    // leaders (W*4 floats each), waypoint index per world.
    void read_state(float* pos, float* vel, float* leader_pos, float* leader_vel);
    // Replaces the state (same layouts; headings normalised, speeds must lie
    // in [0, u_max]) and recomputes observations and rewards; for tests and
    // evaluations that place agents.  Episode counters are unchanged.
    void write_state(const float* pos, const float* vel, const float* leader_pos, const float* leader_vel);
    const std::vector<uint32_t>& step_counts() const { return steps_; }

private:
    void reset_world(uint32_t w, std::vector<cl_float4>& pos, std::vector<cl_float4>& vel);
    void observe();
    size_t n() const { return size_t(c_.worlds) * c_.agents; }

    Context& ctx_;
    RlEnvConfig c_;
    std::vector<uint64_t> seeds_;  // per world (reset(seed): all the same)
    bool was_reset_ = false;
    std::vector<uint32_t> episode_, steps_;
    std::vector<uint8_t> truncated_;
    mutable std::vector<uint32_t> done_host_;
    std::vector<cl_float4> lpos_h_, lvel_h_;
    DeviceBuffer<cl_float4> pos_, vel_, lpos_, lvel_, ctl_, waypoints_, box_c_, box_h_;
    DeviceBuffer<cl_uint> wp_, done_;
    DeviceBuffer<float> actions_, obs_, rewards_, prm_;
    cl::Kernel step_k_, leader_k_, rag_k_, observe_k_;
};

}  // namespace swarmcl
