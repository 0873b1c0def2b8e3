// "model": {"type": "policy", "weights": "file.safetensors", ...}: a trained
// actor drives the swarm as followers of a leader (docs/rl-swarm.md, "Policy
// model"; docs/scenarios.md).  The weights path is relative to the scenario
// file; obstacles are boxes (the environment's analytic obstacles).
#include <nlohmann/json.hpp>

#include "io/json_object.hpp"
#include "params/param_table.hpp"
#include "scenario/model_section.hpp"
#include "scenario/section_parts.hpp"

namespace swarmcl {

namespace {

std::vector<std::array<float, 4>> read_waypoints(const nlohmann::json& j, const std::string& path) {
    if (!j.is_array()) bad_json(path, "expected an array of [x, y, z, speed]");
    std::vector<std::array<float, 4>> out;
    for (size_t k = 0; k < j.size(); ++k) {
        const nlohmann::json& w = j[k];
        const std::string at = path + "[" + std::to_string(k) + "]";
        if (!w.is_array() || w.size() != 4) bad_json(at, "expected [x, y, z, speed]");
        std::array<float, 4> v{};
        for (size_t a = 0; a < 4; ++a) {
            if (!w[a].is_number() || !std::isfinite(w[a].get<double>())) bad_json(at, "expected finite numbers");
            v[a] = w[a].get<float>();
        }
        if (v[3] < 0.0f) bad_json(at, "the speed must be >= 0");
        out.push_back(v);
    }
    return out;
}

}  // namespace

ModelSpec read_policy_section(const SectionInput& in) {
    const std::vector<Boundary> obstacles = read_obstacles(in.obstacles);
    JsonObject o(in.model, "model");
    o.string("type", "policy");
    PolicySpec p;
    PolicyModelConfig& c = p.config;
    o.require_key("weights");
    p.weights_path = o.string("weights", "");
    if (p.weights_path.empty()) bad_json(o.at("weights"), "expected the path of a safetensors file");
    if (p.weights_path[0] != '/' && !in.base_dir.empty()) p.weights_path = in.base_dir + "/" + p.weights_path;
    // Every parameter from the table (models/policy_params.cpp); the
    // waypoints are structured.
    policy_param_table().read_json(in.model, "model", &c, {"type", "weights", "leader.waypoints"});
    if (o.has("leader")) {
        JsonObject l(o.child("leader"), "model.leader", {"mode", "position", "heading", "speed", "du_max",
                                                         "dq_max_deg", "reach_radius"});
        if (l.has("waypoints")) c.waypoints = read_waypoints(l.child("waypoints"), l.at("waypoints"));
    }
    for (size_t k = 0; k < obstacles.size(); ++k) {
        const Boundary& b = obstacles[k];
        if (b.kind != Boundary::Kind::Box)
            bad_json("obstacles[" + std::to_string(k) + "]", "the policy model takes boxes only");
        c.obstacles.push_back({b.center, b.half_extents});
    }
    try {
        validate(c);
    } catch (const Error& e) {
        bad_json("model", e.what());
    }
    return p;
}

}  // namespace swarmcl
