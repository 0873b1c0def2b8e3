// "model": {"type": "path"}: the path-field model (docs/path-field.md) with
// the obstacles as meshes.  Its parameters are its table's keys
// (models/path_params.cpp); goals, groups, targets, the moving goal's
// waypoints and the lamp's angle in degrees are read here.
#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "io/json_object.hpp"
#include "params/param_table.hpp"
#include "scenario/model_section.hpp"
#include "scenario/section_parts.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

Goal read_goal(const json& j, const std::string& path) {
    JsonObject o(j, path);
    Goal g;
    const std::string type = o.string("type", "point");
    if (type == "point") {
        o.allow({"type", "center"});
        g.kind = Goal::Kind::Point;
    } else if (type == "sphere") {
        o.allow({"type", "center", "radius"});
        g.kind = Goal::Kind::Sphere;
        o.require_key("radius");
        g.radius = o.positive("radius", 0.0f);
    } else if (type == "box") {
        o.allow({"type", "center", "half_extents"});
        g.kind = Goal::Kind::Box;
        g.half_extents = o.required_vec3("half_extents");
        for (float h : g.half_extents)
            if (!(h > 0.0f)) bad_json(o.at("half_extents"), "expected 3 numbers > 0");
    } else {
        bad_json(o.at("type"), "expected \"point\", \"sphere\" or \"box\"");
    }
    g.center = o.required_vec3("center");
    o.finish();
    return g;
}

std::vector<Goal> read_goals(const json& j, const std::string& path) {
    if (!j.is_array() || j.empty()) bad_json(path, "expected a non-empty array of goals");
    std::vector<Goal> out;
    for (size_t i = 0; i < j.size(); ++i) out.push_back(read_goal(j[i], path + "[" + std::to_string(i) + "]"));
    return out;
}

// "targets": [{"center", "radius", "group"}]: chasing targets (§7).
std::vector<PathTarget> read_targets(const json& j, const std::string& path) {
    if (!j.is_array() || j.empty()) bad_json(path, "expected a non-empty array of targets");
    std::vector<PathTarget> out;
    for (size_t i = 0; i < j.size(); ++i) {
        JsonObject o(j[i], path + "[" + std::to_string(i) + "]");
        o.allow({"center", "radius", "group"});
        PathTarget t;
        t.center = o.required_vec3("center");
        o.require_key("radius");
        t.radius = o.positive("radius", t.radius);
        t.group = uint32_t(o.integer("group", 0, 63));
        o.finish();
        out.push_back(t);
    }
    return out;
}

// The keys of the model object that the table (models/path_params.cpp) does
// not read: the type and the structured parts.
const std::set<std::string> kHandled = {"type",  "goals",   "groups", "targets", "moving_goal.waypoints",
                                        "lamp.angle_deg"};

}  // namespace

ModelSpec read_path_section(const SectionInput& in) {
    JsonObject o(in.model, "model", kHandled);
    o.string("type", "");
    const json* obstacles = in.obstacles;
    const std::string& base_dir = in.base_dir;
    PathModelConfig c;
    // Every parameter of the table present in the object (ranges, unknown
    // keys; "grid": {"resolution", "min", "max"}, "cost": {"A", "B",
    // "second_order"}, "lamp": {...}, "moving_goal": {"every"}).
    path_param_table().read_json(in.model, "model", &c, kHandled);
    if (obstacles)
        for (size_t i = 0; i < obstacles->size(); ++i)
            c.obstacles.push_back(read_mesh_obstacle((*obstacles)[i], "obstacles[" + std::to_string(i) + "]", base_dir));
    if (o.has("grid")) {
        JsonObject g(o.child("grid"), "model.grid", {"resolution"});
        if (g.has("min") || g.has("max")) {  // both, min below max
            c.has_grid_box = true;
            g.require_key("min");
            g.require_key("max");
            for (int a = 0; a < 3; ++a)
                if (!(c.grid_min[a] < c.grid_max[a])) bad_json(g.at("min"), "must be below model.grid.max on every axis");
        }
    }
    if (o.has("groups")) {
        const json& gs = o.child("groups");
        if (!gs.is_array() || gs.empty() || gs.size() > 64) bad_json("model.groups", "expected an array of 1 to 64 groups");
        for (size_t i = 0; i < gs.size(); ++i) {
            const std::string at = "model.groups[" + std::to_string(i) + "]";
            JsonObject g(gs[i], at);
            g.allow({"agents", "goals"});
            PathGroup pg;
            pg.agents = uint32_t(g.integer("agents", 0, 0xFFFFFFFEu));
            g.require_key("goals");
            pg.goals = read_goals(g.child("goals"), at + ".goals");
            g.finish();
            c.groups.push_back(std::move(pg));
        }
        if (o.has("goals")) bad_json("model.goals", "give either goals (one group) or groups, not both");
    } else if (o.has("goals") || !o.has("targets")) {  // a target alone may be the goal
        o.require_key("goals");
        c.groups.push_back({0, read_goals(o.child("goals"), "model.goals")});
    } else {
        c.groups.push_back({0, {}});
    }
    if (o.has("targets")) c.targets = read_targets(o.child("targets"), "model.targets");
    if (o.has("lamp")) {  // phototaxis (§7); the angle in degrees
        JsonObject l(o.child("lamp"), "model.lamp", {"center", "radius", "probability", "speed", "keep_out"});
        c.lamp.enabled = true;
        c.lamp.angle = float(l.number("angle_deg", 0.0, 0.0, 90.0, "in [0, 90]") * 3.14159265358979323846 / 180.0);
    }
    if (o.has("moving_goal")) {  // "every" is the table's
        JsonObject m(o.child("moving_goal"), "model.moving_goal", {"every"});
        m.require_key("waypoints");
        const json& w = m.child("waypoints");
        if (!w.is_array() || w.empty()) bad_json(m.at("waypoints"), "expected a non-empty array of [x, y, z]");
        for (size_t i = 0; i < w.size(); ++i)
            c.waypoints.push_back(JsonObject::to_vec3(w[i], m.at("waypoints") + "[" + std::to_string(i) + "]"));
    }
    return c;
}

void check_path_section(const ModelSpec& spec, const SwarmConfig& swarm) {
    check_noise_in_domain(std::get<PathModelConfig>(spec).noise, swarm);
}

}  // namespace swarmcl
