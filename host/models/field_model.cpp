#include "models/field_model.hpp"

#include "models/model_descriptor.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "params/param_block.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

FieldModel::FieldModel(Swarm& swarm, FieldModelConfig config)
    : worlds_(field_param_table(), config, swarm.worlds()) {
    const FieldModelConfig& c = worlds_[0];
    const ParamTable& table = field_param_table();
    table.validate(const_cast<FieldModelConfig*>(&c));
    Context& ctx = swarm.context();
    check_noise_for_world_domains(c.noise, swarm.world_domains(), "field model noise");
    noise_ = std::make_unique<NoiseField>(ctx, c.noise, &swarm.config().domain_min, &swarm.config().domain_max);
    // Built for this noise configuration (NoiseField::defines).
    // On CPU devices the explicit-width variant (NoiseField::width() agents per
    // work-item).
    width_ = noise_->width();
    advance_ = noise_->kernel("field_model.cl", width_ > 1 ? "field_model_advance_w" : "field_model_advance",
                              table.device_defines("FIELD") + world_defines(swarm.worlds()));
    const std::vector<cl_float> block = noise_->block();
    noise_host_.reserve(block.size() * worlds_.worlds());
    for (uint32_t k = 0; k < worlds_.worlds(); ++k) noise_host_.insert(noise_host_.end(), block.begin(), block.end());
    noise_prims_host_ = world_noise_prims(ctx, swarm.world_domains(), c.noise, *noise_, "field model noise", noise_host_);
    upload_world_blocks(ctx);
}

void FieldModel::upload_world_blocks(Context& ctx) {
    const std::vector<float> blocks = worlds_.device_blocks();
    params_.reserve(ctx, blocks.size(), "model parameter blocks");
    params_.upload(ctx, blocks.data(), blocks.size());
    noise_blocks_.reserve(ctx, noise_host_.size(), "noise parameter blocks");
    noise_blocks_.upload(ctx, noise_host_.data(), noise_host_.size());
    noise_prims_.reserve(ctx, noise_prims_host_.size(), "noise boundaries of the worlds");
    noise_prims_.upload(ctx, noise_prims_host_.data(), noise_prims_host_.size());
    blocks_current_ = true;
}

void FieldModel::set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) {
    const bool noise = key.compare(0, 6, "noise.") == 0;
    std::vector<float> noise_next = noise_host_;
    std::vector<cl_float4> prims_next = noise_prims_host_;
    worlds_.set(key, values, count, [&](const FieldModelConfig& changed, uint32_t k) {
        if (!noise) return;
        write_world_noise_block(swarm.context(), changed.noise, &swarm.world_domain(k).min,
                                &swarm.world_domain(k).max, *noise_, "field model " + key, noise_next, k,
                                &prims_next);
    });
    noise_host_ = std::move(noise_next);
    noise_prims_host_ = std::move(prims_next);
    blocks_current_ = false;
}

std::vector<double> FieldModel::world_param(const std::string& key) const { return worlds_.get(key); }

void FieldModel::advance(Swarm& swarm, uint64_t step) {
    if (!blocks_current_) upload_world_blocks(swarm.context());
    const uint32_t n = swarm.agent_count();
    cl_uint i = swarm.set_step_args(advance_, step);
    const cl_uint noise_at = i;
    i = noise_->set_args(advance_, i);
    advance_.setArg(noise_at, noise_blocks_.get());      // the worlds' blocks (world 0's with one)
    advance_.setArg(noise_at + 1, noise_prims_.get());  // and their boundaries
    advance_.setArg(i++, params_.get());
    check_arg_count(advance_, i);
    launch_worlds(swarm.context(), advance_, (size_t(n) + width_ - 1) / width_, swarm.worlds());
    swarm.positions_changed();
}

StepStages FieldModel::stages() const {
    StepStages s;
    s.min_distance = worlds_[0].min_distance;
    s.seed = worlds_[0].noise.seed;
    s.stats = true;
    if (worlds_.worlds() > 1) {
        for (uint32_t k = 0; k < worlds_.worlds(); ++k) {
            s.world_min_distance.push_back(worlds_[k].min_distance);
            s.world_seed.push_back(worlds_[k].noise.seed);
            s.min_distance = std::max(s.min_distance, worlds_[k].min_distance);
        }
    }
    return s;
}

// The field model keeps nothing that changes over steps: its field is
// rebuilt from the descriptor (the noise bake is deterministic).
void FieldModel::save_checkpoint(Swarm&, ByteWriter& descriptor, ByteWriter&) {
    write_model_descriptor(descriptor, worlds_[0]);  // the other worlds: their varied parameters (WRLD)
}
void FieldModel::restore_checkpoint(Swarm&, ByteReader& state) { state.expect_end(); }

}  // namespace swarmcl
