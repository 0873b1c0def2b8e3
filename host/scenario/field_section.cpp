// "model": {"type": "field"} (the default type): the curl-noise field model
// (docs/field-model.md) with the analytic obstacles as its noise boundaries.
// Its keys are its parameter table's (models/field_params.cpp).
#include <nlohmann/json.hpp>

#include "io/json_object.hpp"
#include "params/param_table.hpp"
#include "scenario/model_section.hpp"
#include "scenario/section_parts.hpp"

namespace swarmcl {

ModelSpec read_field_section(const SectionInput& in) {
    std::vector<Boundary> obstacles = read_obstacles(in.obstacles);
    FieldModelConfig c;
    field_param_table().read_json(in.model, "model", &c, {"type"});
    JsonObject(in.model, "model", {"type"}).string("type", "field");
    c.has_goal = in.model.contains("goal");
    c.noise.boundaries = std::move(obstacles);
    return c;
}

void check_field_section(const ModelSpec& spec, const SwarmConfig& swarm) {
    check_noise_in_domain(std::get<FieldModelConfig>(spec).noise, swarm);
}

}  // namespace swarmcl
