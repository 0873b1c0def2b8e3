// FASTSWARM (Xiang et al.): each step every agent picks, from the reference
// dataset D, the velocity that minimises the energy of Eq. 2-14 over its
// speed group and the neighbouring groups, then moves p <- p + v dt (Eq. 1).
// kernels/energy_model.cl does the work; docs/energy-model.md has the
// equations, units and the choices made where the paper is vague.
#pragma once
#include <array>
#include <memory>
#include <vector>

#include "data/dataset.hpp"
#include "fields/noise_field.hpp"
#include "params/world_params.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

class Swarm;

// Weights of the energy terms (Table 1 columns).  Defaults: aggregation.
struct EnergyWeights {
    float rep = 1.0f, oa = 1.0f, cos = 0.05f, dir = 1.0f, acc = 1.0f, env = 0.0f, n = 0.2f, user = 0.0f;
};

// A stimulus of Eq. 11-12 moving as p(t) = position + velocity * t.
struct Stimulus {
    enum class Kind { Attract, Startle } kind = Kind::Attract;
    std::array<float, 3> position{};
    std::array<float, 3> velocity{};  // m/s
    float d_danger = 0.3f;            // m; startle only
};

struct EnergyModelConfig {
    EnergyWeights weights;
    // Weights of agents within d_danger of a startling stimulus (Table 1,
    // escaping "in danger": no attraction to neighbours or the centre).
    EnergyWeights danger_weights{1.0f, 0.0f, 0.0f, 1.0f, 1.0f, 2.0f, 0.3f, 0.0f};
    float rho = 2.5f;          // §5: rho = 2.5 in all experiments
    float d_rep = 0.04f;       // m, repulsion radius (Eq. 4)
    float d_att1 = 0.1f;       // m, inner attraction radius (Eq. 6)
    float d_att2 = 0.4f;       // m, outer attraction radius
    // The point E_cos (Eq. 7) pulls towards.  Default: the swarm centre (mean
    // position, a fixed-order device reduction each step).  A fixed centre
    // keeps the swarm over one place (Table 1 aggregation, "unchanged swarm
    // centre"; real swarms hover over a marker).
    bool has_fixed_centre = false;
    std::array<float, 3> fixed_centre{};
    uint32_t span = 1;         // neighbouring speed groups searched on each side
    float accel_time = 0.0f;   // s, scale of E_amag; 0: the dataset's frame time (0.01 s if unknown)
    // Eq. 6 exactly for every candidate and neighbour; otherwise (default) a
    // second-order expansion in v dt, used only where it is accurate to 1.6%
    // (rho / d_att1 * max speed * dt <= 0.4; kernels/energy_model.cl).
    bool exact_attraction = false;
    float danger_horizon = 1.0f;  // s, look-ahead of the startled prediction (Eq. 12)
    // Startling stimuli are kept out of (ours): a candidate whose predicted
    // closest approach (within danger_horizon) is inside d_danger is chosen
    // only when every candidate's is, and then the one entering least.
    bool keep_out = true;
    NoiseConfig noise;         // f_N (curl noise); default: scale 0.2 m, time_scale 1 s
    std::vector<Stimulus> stimuli;
    std::vector<std::array<float, 3>> keypoints;  // f_CD (Eq. 15); empty: none
    bool keypoints_closed = true;   // the curve is a loop (heart, star)
    bool bidirectional = true;      // odd agent ids traverse it backwards
    float keypoint_reach = 0.05f;   // m: a keypoint counts as reached within this distance

    EnergyModelConfig() {
        noise.scale = 0.2f;
        noise.time_scale = 1.0f;
    }
};

// Its parameters, declared once (models/energy_params.cpp): every field but
// the stimuli, the keypoints, the noise's boundaries and exact_attraction.
const ParamTable& energy_param_table();

// The eight terms of one candidate for one agent (checking and tests).
struct EnergyTerms {
    std::vector<float> terms;       // [agent id][candidate - first][term], EnergyModel::max_candidates() wide
    std::vector<uint32_t> chosen;   // per agent id: the chosen sample index
    std::vector<uint32_t> first, last;  // per agent id: the candidate range [first, last)
};

class EnergyModel : public Behavior {
public:
    // Validates the configuration (Error(InvalidArgument) naming the value).
    // Every world of the swarm starts with `config`; a swarm of several
    // worlds (docs/architecture.md, "Worlds") runs each world as its swarm
    // alone (the keypoints one curve for every world, each world's goals
    // kept by its agents' ids).
    EnergyModel(Swarm& swarm, EnergyModelConfig config, std::shared_ptr<const Dataset> dataset);

    // Per world: the table's parameters but those that select a kernel or
    // size a buffer (span, keep_out, has_fixed_centre, accel_time, the
    // noise's kernel-selecting keys, bidirectional, and rho / d_att1 where
    // they switch the attraction's expansion), which are refused when they
    // differ between worlds.
    void set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) override;
    std::vector<double> world_param(const std::string& key) const override;
    std::vector<std::string> varied_world_params() const override { return worlds_.varied_keys(); }

    void advance(Swarm& swarm, uint64_t step) override;
    // Checkpoints (swarm/behavior.hpp).
    void save_checkpoint(Swarm& swarm, ByteWriter& descriptor, ByteWriter& state) override;
    void restore_checkpoint(Swarm& swarm, ByteReader& state) override;

    // World 0's configuration (the swarm's, with one world).
    const EnergyModelConfig& config() const { return config_; }
    const Dataset& dataset() const { return *dataset_; }
    uint32_t max_candidates() const { return max_cand_; }
    bool taylor_attraction() const { return taylor_; }

    // Replace the stimuli / keypoints from the next step on (validated;
    // unchanged on error).  New keypoints restart every agent's traversal.
    void set_stimuli(std::vector<Stimulus> stimuli);
    void set_keypoints(std::vector<std::array<float, 3>> keypoints, bool closed);

    // Per agent id: the goal keypoint index (-1: not chosen yet) and whether
    // the agent traverses the curve backwards; world by world on a swarm of
    // worlds (W x agents a world).
    void goals(Swarm& swarm, std::vector<int32_t>& goal, std::vector<uint8_t>& backward);
    // The swarm centre the last step used (xyz) and the agent count (w);
    // with worlds, world `world`'s.
    std::array<float, 4> centre(Swarm& swarm, uint32_t world = 0);

    // Evaluates every term for the current state at step `step` without
    // moving anything (one world only).
    EnergyTerms evaluate(Swarm& swarm, uint64_t step);

    static void validate(const EnergyModelConfig& config);

private:
    void launch_per_agent(cl::Kernel& k, uint32_t n);  // energy_select, one work-item per agent
    void prepare(Swarm& swarm);  // position planes and swarm centre, before the step kernel
    cl_uint set_common_args(cl::Kernel& k, Swarm& swarm, uint64_t step);
    void sample_noise(Swarm& swarm, uint64_t step);
    void reset_goals(uint32_t capacity);
    void upload_params();  // the worlds' parameter blocks, again when keypoints_closed changes
    bool taylor_for(const EnergyModelConfig& c, float dt) const;
    void upload_noise_blocks();  // noise_host_ to the device (and each world's apart for noise_sample_w)  // EM_TAYLOR_OA for this configuration

    Context& ctx_;  // the swarm's (a swarm keeps its context alive)
    EnergyModelConfig config_;  // world 0's (worlds_[0])
    WorldConfigs<EnergyModelConfig> worlds_;
    uint32_t world_count_ = 1;
    std::vector<cl_float> noise_host_;  // each world's NoiseField::block(), one after another
    // Each world's noise boundary primitives (NoiseField::prims(), world
    // k's walls at its own domain), one run after another.
    std::vector<cl_float4> noise_prims_host_;
    DeviceBuffer<cl_float4> noise_prims_;
    float vmax_ = 0.0f;                 // the dataset's fastest sample (taylor_for)
    std::shared_ptr<const Dataset> dataset_;
    std::unique_ptr<NoiseField> noise_;
    uint32_t max_cand_ = 0;
    uint32_t fixed_centre_n_ = 0xFFFFFFFFu;  // agent count of the uploaded fixed centre
    uint32_t ds_stride_ = 0;  // floats between the dataset planes (kernels/energy_model.cl EM_P_*)
    DeviceBuffer<cl_float> ds_;
    float accel_time_ = 0.01f;
    bool taylor_ = false;
    cl::Kernel select_, terms_, prepare_, centre_final_, noise_sample_;
    bool noise_pre_ = false;  // f_N sampled beforehand by noise_sample_w (CPU devices)
    DeviceBuffer<cl_float4> dv_, centre_, partial_, stim_, kp_, vel_out_, noise_buf_;
    DeviceBuffer<cl_uint> group_start_, goal_;
    DeviceBuffer<cl_float> group_min_speed_, pxyz_;
    DeviceBuffer<cl_float> params_;  // energy_param_table()'s device block, one per world (upload_params)
    DeviceBuffer<cl_float> noise_blocks_;  // noise_host_ on the device
    std::vector<DeviceBuffer<cl_float>> noise_world_blocks_;  // noise_sample_w on worlds: world k's block
    std::vector<DeviceBuffer<cl_float4>> noise_world_prims_;  // ... and its primitives
    DeviceBuffer<cl_float4> noise_pts_, noise_one_;  // worlds with different noises: one world's positions, noise
    uint32_t capacity_ = 0, pxyz_stride_ = 0;
};

}  // namespace swarmcl
