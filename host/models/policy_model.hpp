// The policy model (issue 15 item 7; paper drl-swarm-animation-rule-based-
// action-generator, §III-IV): a trained actor (an MLP in a safetensors file,
// host/rl/policy_weights.hpp) drives the swarm's agents as followers of a
// leader.  Each step: the observations of Eq. 11-13 over the swarm's
// neighbour grid (kernels/policy.cl with the environment's code,
// kernels/lib/rl_common.cl), the MLP batched over agents, Eq. 2's
// kinematics; the leader moves by joystick controls or through waypoints.
// docs/rl-swarm.md, "Policy model".
#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "params/world_params.hpp"
#include "rl/leader_env.hpp"
#include "rl/policy_weights.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

enum class PolicyLeaderMode : uint32_t { Joystick = 0, Navigation = 1, Tour = 2 };

// Defaults: Table 1 and the environment's choices (RlEnvConfig), so a policy
// trained in the environment sees the same world.  The time step is the
// swarm's dt (Table 1: 0.1 s).
struct PolicyModelConfig {
    float r_sep = 1.0f, r_ali = 9.0f, r_coh = 18.0f;  // Table 1
    float neighbor_radius = 0.0f;                     // EFS neighbours; 0: r_coh
    float body_radius = 0.5f;                         // agents' sphere for the rays
    float du_max = 0.1f, dq_max_deg = 4.0f;           // Table 1 (Eq. 2's clamps)
    float u_max = 3.0f;
    // The leader: joystick (controls {Δu, Δq.xyz} set through the API, kept
    // until changed), navigation through waypoints (x, y, z, target speed;
    // it stops after the last) or a tour (starts over at the first).
    PolicyLeaderMode leader_mode = PolicyLeaderMode::Joystick;
    std::vector<std::array<float, 4>> waypoints;
    float leader_du_max = 0.1f, leader_dq_max_deg = 4.0f, reach_radius = 2.0f;
    std::array<float, 3> leader_position{{0.0f, 0.0f, 0.0f}};
    std::array<float, 3> leader_heading{{1.0f, 0.0f, 0.0f}};  // normalised
    float leader_speed = 0.5f;
    std::vector<RlObstacleBox> obstacles;
};

// Its parameters, declared once (models/policy_params.cpp).
class ParamTable;
const ParamTable& policy_param_table();

// Error(InvalidArgument) naming the field: the parameters shared with the
// RL environment through validate_leader_follow (rl/leader_follow_params.hpp),
// then the leader's start and mode.
void validate(const PolicyModelConfig& config);

// The model as a scenario or the C API describes it: the weights file's
// bytes (kept for checkpoints) or its path.
struct PolicySpec {
    PolicyModelConfig config;
    std::string weights_path;                         // read when the behaviour is built
    std::shared_ptr<const std::string> weights_bytes; // used instead of the path when set
};

// The plain C++ forward pass of the MLP for one observation (tests and the
// kernel's reference): acc = fma(w, x, acc) in input order from the bias.
std::array<float, 4> policy_forward(const PolicyWeights& w, const float* obs);

class PolicyModel : public Behavior {
public:
    // Parses the weights (Error(Parse) naming the problem) and validates the
    // configuration; nothing of the swarm changes on failure.
    PolicyModel(Swarm& swarm, PolicyModelConfig config, std::shared_ptr<const std::string> weights_bytes);

    void advance(Swarm& swarm, uint64_t step) override;
    StepStages stages() const override;
    // Checkpoints: every world's leader (position, (q, u), controls,
    // waypoint, done), world by world.
    void save_checkpoint(Swarm& swarm, ByteWriter& descriptor, ByteWriter& state) override;
    void restore_checkpoint(Swarm& swarm, ByteReader& state) override;

    // Per world (a swarm of worlds): the followers' parameters of the table
    // (r_sep, r_ali, r_coh, neighbor_radius, body_radius, du_max,
    // dq_max_deg), each world checked as the model alone.  The leader's
    // parameters and u_max, which the leader's kernel reads once for every
    // world, are refused: every world has the same leader.
    void set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) override;
    std::vector<double> world_param(const std::string& key) const override;
    std::vector<std::string> varied_world_params() const override;

    // World 0's configuration (the swarm's, with one world).
    const PolicyModelConfig& config() const { return config_; }
    const PolicyWeights& weights() const { return weights_; }
    uint32_t obs_dim() const { return weights_.obs_dim; }

    // Joystick controls {Δu, Δq.xyz} (finite), used from the next step on,
    // by every world's leader.
    void set_leader_controls(const std::array<float, 4>& controls);
    // World `world`'s leader position (x, y, z, 0) and (q.xyz, u), waits
    // for the device.
    void read_leader(cl_float4* position, cl_float4* heading_speed, uint32_t world = 0);
    // The observations of the current state (obs_dim per agent, agent-id
    // order, world by world) and the actions the policy takes on them (4 per
    // agent).
    void observe(Swarm& swarm, std::vector<float>* obs, std::vector<float>* actions);
    // The observations of the current state computed on the device and
    // kept there (the grid rebuilt if the swarm moved); waits for the
    // device.  The observation stage alone, for benchmarks.
    void observe_on_device(Swarm& swarm);
    // The MLP alone on the observations observe_on_device() left on the
    // device, into the model's action buffer (nothing copied to or from the
    // host); waits for the device.  The MLP stage alone, for benchmarks.
    void mlp_on_device(Swarm& swarm);
    // The MLP alone on `count` observations (tests, benchmarks): 4 actions each.
    std::vector<float> infer(const std::vector<float>& obs, uint32_t count);
    // The same from count * obs_dim floats into count * 4 (non-finite
    // observations refused, nothing written).
    void infer(const float* obs, uint32_t count, float* actions);
    // Agents per work-item of the MLP kernel.
    uint32_t lanes() const { return lanes_; }          // the observations' (policy_observe_w)
    uint32_t mlp_lanes() const { return mlp_lanes_; }  // the MLP's (policy_mlp)
    // True when the MLP runs as tiled matrix products, one launch a layer
    // (policy_mlp_tiled: the GPU profile, lanes not forced); false for
    // policy_mlp.
    bool tiled_mlp() const { return tiled_; }
    // Agents per chunk of the tiled MLP (its hidden activations are
    // 2 x widest hidden layer x this many floats).
    uint32_t mlp_chunk_agents() const { return tiled_chunk_; }

private:
    // The leaders' state as the observations and actions read it (lst_).
    void enqueue_leader_copy(uint32_t worlds);
    void enqueue_observe(Swarm& swarm);
    void upload_world_blocks();
    void enqueue_mlp(DeviceBuffer<float>& obs, uint32_t n, DeviceBuffer<float>& actions);
    void enqueue_mlp_tiled(DeviceBuffer<float>& obs, uint32_t n, DeviceBuffer<float>& actions);

    PolicyModelConfig config_;
    WorldConfigs<PolicyModelConfig> worlds_;
    bool blocks_current_ = false;
    std::shared_ptr<const std::string> bytes_;
    PolicyWeights weights_;
    uint32_t lanes_ = 1, mlp_lanes_ = 1, max_width_ = 0, mean_off_ = 0, std_off_ = 0;
    bool tiled_ = false;
    uint32_t tiled_chunk_ = 0, hidden_width_ = 0;  // the tiled MLP's agents a chunk, widest hidden layer
    std::vector<uint32_t> layer_table_;            // layers_ on the host (the tiled MLP's arguments)
    DeviceBuffer<float> hidden_a_, hidden_b_;      // the tiled MLP's activations, [feature][agent]
    cl::Kernel tiled_k_;
    Context& ctx_;
    DeviceBuffer<float> params_, obs_, actions_, scratch_, infer_obs_, infer_actions_;
    DeviceBuffer<cl_float> block_;  // policy_param_table()'s device block (params_ holds the MLP's weights)
    DeviceBuffer<cl_uint> layers_, wp_, done_;
    DeviceBuffer<cl_float4> lpos_, lvel_, lst_, ctl_, waypoints_, box_c_, box_h_;
    DeviceBuffer<cl_float4> qu_;  // every agent's (q, u) for the observations (policy_headings)
    cl::Kernel observe_k_, mlp_k_, apply_k_, copy_k_, leader_k_, headings_k_;
};

}  // namespace swarmcl
