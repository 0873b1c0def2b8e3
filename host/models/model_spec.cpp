#include "models/model_spec.hpp"

#include "models/energy_model.hpp"
#include "models/field_model.hpp"
#include "models/force_model.hpp"
#include "models/path_model.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {
namespace {

// One case per model (std::visit picks by the alternative's type).
std::shared_ptr<Behavior> behavior_for(Swarm&, const Ballistic&) { return nullptr; }
std::shared_ptr<Behavior> behavior_for(Swarm& s, const FieldModelConfig& c) { return std::make_shared<FieldModel>(s, c); }
std::shared_ptr<Behavior> behavior_for(Swarm& s, const PathModelConfig& c) { return std::make_shared<PathModel>(s, c); }
std::shared_ptr<Behavior> behavior_for(Swarm& s, const ForceModelConfig& c) { return std::make_shared<ForceModel>(s, c); }
std::shared_ptr<Behavior> behavior_for(Swarm& s, const EnergySpec& e) {
    return std::make_shared<EnergyModel>(s, e.config, energy_spec_dataset(e));
}
std::shared_ptr<Behavior> behavior_for(Swarm& s, const PolicySpec& p) {
    auto bytes = p.weights_bytes ? p.weights_bytes : std::make_shared<const std::string>(read_policy_file(p.weights_path));
    return std::make_shared<PolicyModel>(s, p.config, std::move(bytes));
}

}  // namespace

const char* model_name(const ModelSpec& spec) {
    return std::visit([](const auto& c) { return ModelTraits<std::decay_t<decltype(c)>>::name; }, spec);
}

float model_min_distance(const ModelSpec& spec) {
    return std::visit([](const auto& c) { return ModelTraits<std::decay_t<decltype(c)>>::min_distance(c); }, spec);
}

std::shared_ptr<Behavior> make_behavior(Swarm& swarm, const ModelSpec& spec) {
    return std::visit([&](const auto& c) { return behavior_for(swarm, c); }, spec);
}

}  // namespace swarmcl
