#include "models/field_model.hpp"

#include "models/model_descriptor.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "params/param_block.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

FieldModel::FieldModel(Swarm& swarm, FieldModelConfig config)
    : config_(std::move(config)) {
    const auto& c = config_;
    const ParamTable& table = field_param_table();
    table.validate(&config_);
    Context& ctx = swarm.context();
    noise_ = std::make_unique<NoiseField>(ctx, c.noise, &swarm.config().domain_min, &swarm.config().domain_max);
    // Built for this noise configuration (NoiseField::defines).
    // On CPU devices the explicit-width variant (NoiseField::width() agents per
    // work-item).
    width_ = noise_->width();
    advance_ = noise_->kernel("field_model.cl", width_ > 1 ? "field_model_advance_w" : "field_model_advance",
                              table.device_defines("FIELD"));
    params_ = upload_param_block(ctx, table, &c);
}

void FieldModel::advance(Swarm& swarm, uint64_t step) {
    const uint32_t n = swarm.agent_count();
    cl_uint i = swarm.set_step_args(advance_, step);
    i = noise_->set_args(advance_, i);
    advance_.setArg(i++, params_.get());
    check_arg_count(advance_, i);
    launch(swarm.context(), advance_, (size_t(n) + width_ - 1) / width_);
    swarm.positions_changed();
}

StepStages FieldModel::stages() const {
    StepStages s;
    s.min_distance = config_.min_distance;
    s.seed = config_.noise.seed;
    s.stats = true;
    return s;
}

// The field model keeps nothing that changes over steps: its field is
// rebuilt from the descriptor (the noise bake is deterministic).
void FieldModel::save_checkpoint(Swarm&, ByteWriter& descriptor, ByteWriter&) {
    write_model_descriptor(descriptor, config_);
}
void FieldModel::restore_checkpoint(Swarm&, ByteReader& state) { state.expect_end(); }

}  // namespace swarmcl
