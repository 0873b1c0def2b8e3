// "model": {"type": "field"} (the default type): the curl-noise field model
// (docs/field-model.md) with the analytic obstacles as its noise boundaries.
#include <nlohmann/json.hpp>

#include "io/json_object.hpp"
#include "scenario/model_section.hpp"
#include "scenario/section_parts.hpp"

namespace swarmcl {

ModelSpec read_field_section(const SectionInput& in) {
    std::vector<Boundary> obstacles = read_obstacles(in.obstacles);
    JsonObject o(in.model, "model");
    o.string("type", "field");
    FieldModelConfig c;
    if (o.has("noise")) c.noise = read_noise(o.child("noise"), "model.noise");
    c.noise.boundaries = std::move(obstacles);
    if (o.has("goal")) {
        JsonObject g(o.child("goal"), "model.goal");
        g.allow({"center", "radius", "speed", "falloff"});
        c.has_goal = true;
        c.goal = g.required_vec3("center");
        c.goal_radius = g.non_negative("radius", c.goal_radius);
        c.goal_speed = g.non_negative("speed", c.goal_speed);
        c.goal_falloff = g.non_negative("falloff", c.goal_falloff);
        g.finish();
    }
    c.min_distance = o.non_negative("min_distance", c.min_distance);
    o.finish();
    return c;
}

void check_field_section(const ModelSpec& spec, const SwarmConfig& swarm) {
    check_noise_in_domain(std::get<FieldModelConfig>(spec).noise, swarm);
}

}  // namespace swarmcl
