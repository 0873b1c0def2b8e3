// The one seam between a swarm and its models: a ModelSpec says which model
// drives the swarm and with what parameters; make_behavior builds it.  A model
// is a config plus a Behavior (host/models/<model>_model.*), one alternative
// of ModelSpec, one ModelTraits entry and one make_behavior case here, one
// scenario section (host/scenario/<model>_section.cpp) and one C API file
// (capi/src/capi_<model>.cpp): docs/architecture.md, "How to add a model".
#pragma once
#include <memory>
#include <variant>

#include "models/energy_spec.hpp"
#include "models/field_model.hpp"
#include "models/force_model.hpp"
#include "models/path_model.hpp"
#include "models/policy_model.hpp"

namespace swarmcl {

class Behavior;
class Swarm;

// No model: agents keep their velocity (the swarm's own integration).
struct Ballistic {};

using ModelSpec =
    std::variant<Ballistic, FieldModelConfig, PathModelConfig, ForceModelConfig, EnergySpec, PolicySpec>;

// Per model: its name ("model.type" in scenario files, swcl_scenario_info.model)
// and its minimum distance enforcement threshold (0: none).  Left undefined
// for a type that is not a model, so a new ModelSpec alternative without an
// entry does not compile.
template <class Config>
struct ModelTraits;

template <>
struct ModelTraits<Ballistic> {
    static constexpr const char* name = "ballistic";
    static float min_distance(const Ballistic&) { return 0.0f; }
};
template <>
struct ModelTraits<FieldModelConfig> {
    static constexpr const char* name = "field";
    static float min_distance(const FieldModelConfig& c) { return c.min_distance; }
};
template <>
struct ModelTraits<PathModelConfig> {
    static constexpr const char* name = "path";
    static float min_distance(const PathModelConfig& c) { return c.min_distance; }
};
template <>
struct ModelTraits<ForceModelConfig> {
    static constexpr const char* name = "force";
    static float min_distance(const ForceModelConfig& c) { return c.min_distance; }
};
template <>
struct ModelTraits<EnergySpec> {
    static constexpr const char* name = "energy";
    static float min_distance(const EnergySpec&) { return 0.0f; }  // no MDE: the energy terms keep distances
};
template <>
struct ModelTraits<PolicySpec> {
    static constexpr const char* name = "policy";
    static float min_distance(const PolicySpec&) { return 0.0f; }  // no MDE: the policy keeps its spacing (Eq. 19)
};

const char* model_name(const ModelSpec& spec);
float model_min_distance(const ModelSpec& spec);

// The model's Behavior for `swarm` (nullptr for Ballistic).  Builds what the
// model precomputes (fields, targets, the energy model's dataset); Error as
// the model's constructor.
std::shared_ptr<Behavior> make_behavior(Swarm& swarm, const ModelSpec& spec);

}  // namespace swarmcl
