// The local behaviour of the curl-noise paper (§4, §6): velocity from the
// (boundary-aware) noise field plus an optional pull to a goal at speed s0,
// the position update; minimum distance enforcement is the swarm's stage
// after it (stages()).
#pragma once
#include <array>
#include <memory>

#include "fields/noise_field.hpp"
#include "params/world_params.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

struct FieldModelConfig {
    NoiseConfig noise;
    bool has_goal = false;
    std::array<float, 3> goal{};
    float goal_radius = 0.0f;   // no pull inside this sphere around the goal
    float goal_speed = 1.5f;    // s0, m/s (Table 1, two blocks and chasing; aggregation has 2.5)
    float goal_falloff = 0.0f;  // m over which the pull ramps up to s0; 0: at once
    float min_distance = 0.0f;  // MDE threshold, m; 0: no enforcement
    // m/s: each agent's velocity (noise + pull) is scaled down to this
    // speed when faster; 0: no limit (the paper's).
    float max_speed = 0.0f;
};

// Its parameters, declared once (models/field_params.cpp).
const ParamTable& field_param_table();

class FieldModel : public Behavior {
public:
    // Validates; the noise region defaults to the swarm's domain.  Every
    // world of the swarm starts with `config`.
    FieldModel(Swarm& swarm, FieldModelConfig config);

    void advance(Swarm& swarm, uint64_t step) override;
    // World 0's configuration (the swarm's, with one world).
    const FieldModelConfig& config() const { return worlds_[0]; }

    // Per world: any parameter of the table but those that choose the
    // kernel (noise.type, a time scale of 0 or not, finite differences) or
    // what is baked (a baked noise is the same in every world).
    void set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) override;
    std::vector<double> world_param(const std::string& key) const override;
    std::vector<std::string> varied_world_params() const override { return worlds_.varied_keys(); }

    // MDE at min_distance (keyed by the noise seed), and step statistics.
    StepStages stages() const override;
    // Checkpoints (swarm/behavior.hpp).
    void save_checkpoint(Swarm& swarm, ByteWriter& descriptor, ByteWriter& state) override;
    void restore_checkpoint(Swarm& swarm, ByteReader& state) override;

private:
    void upload_world_blocks(Context& ctx);

    WorldConfigs<FieldModelConfig> worlds_;
    std::unique_ptr<NoiseField> noise_;
    cl::Kernel advance_;
    DeviceBuffer<cl_float> params_;  // field_param_table()'s device block, one per world
    DeviceBuffer<cl_float> noise_blocks_;  // NoiseField::block() of each world
    std::vector<cl_float> noise_host_;     // noise_blocks_' contents
    // Each world's noise boundary primitives (NoiseField::prims(), world
    // k's walls at its own domain), one run after another.
    std::vector<cl_float4> noise_prims_host_;
    DeviceBuffer<cl_float4> noise_prims_;
    bool blocks_current_ = false;
    uint32_t width_ = 1;  // agents per work-item of advance_ (NoiseField::width)
};

}  // namespace swarmcl
