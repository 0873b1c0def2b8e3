// "model": {"type": "path"}: the path-field model (docs/path-field.md) with
// the obstacles as meshes.
#include <cmath>

#include <nlohmann/json.hpp>

#include "io/json_object.hpp"
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

// "lamp": phototaxis (§7); the angle in degrees.
PathLamp read_lamp(const json& j, const std::string& path) {
    JsonObject o(j, path);
    o.allow({"center", "radius", "probability", "speed", "angle_deg", "keep_out"});
    PathLamp l;
    l.enabled = true;
    l.center = o.required_vec3("center");
    l.radius = o.positive("radius", l.radius);
    l.probability = float(o.number("probability", l.probability, 0.0, 1.0, "in [0, 1]"));
    l.speed = o.non_negative("speed", l.speed);
    l.angle = float(o.number("angle_deg", 0.0, 0.0, 90.0, "in [0, 90]") * 3.14159265358979323846 / 180.0);
    l.keep_out = o.positive("keep_out", l.keep_out);
    o.finish();
    return l;
}

}  // namespace

ModelSpec read_path_section(const SectionInput& in) {
    JsonObject o(in.model, "model");
    o.string("type", "");
    const json* obstacles = in.obstacles;
    const std::string& base_dir = in.base_dir;
    PathModelConfig c;
    if (o.has("noise")) c.noise = read_noise(o.child("noise"), "model.noise");
    if (obstacles)
        for (size_t i = 0; i < obstacles->size(); ++i)
            c.obstacles.push_back(read_mesh_obstacle((*obstacles)[i], "obstacles[" + std::to_string(i) + "]", base_dir));
    if (o.has("grid")) {
        JsonObject g(o.child("grid"), "model.grid");
        g.allow({"resolution", "min", "max"});
        if (g.has("resolution")) {
            const auto r = JsonObject::to_vec3(g.child("resolution"), g.at("resolution"));
            for (int a = 0; a < 3; ++a) {
                if (r[a] < 2 || r[a] > 4096 || r[a] != std::floor(r[a]))
                    bad_json(g.at("resolution"), "expected 3 integers in [2, 4096]");
                c.resolution[a] = uint32_t(r[a]);
            }
        }
        if (g.has("min") || g.has("max")) {
            c.has_grid_box = true;
            c.grid_min = g.required_vec3("min");
            c.grid_max = g.required_vec3("max");
            for (int a = 0; a < 3; ++a)
                if (!(c.grid_min[a] < c.grid_max[a])) bad_json(g.at("min"), "must be below model.grid.max on every axis");
        }
        g.finish();
    }
    if (o.has("cost")) {
        JsonObject k(o.child("cost"), "model.cost");
        k.allow({"A", "B", "second_order"});
        c.weights.A = k.positive("A", float(c.weights.A));
        c.weights.B = k.non_negative("B", float(c.weights.B));
        c.second_order = k.boolean("second_order", c.second_order);
        k.finish();
    }
    c.speed = o.non_negative("speed", c.speed);
    c.goal_falloff = o.non_negative("goal_falloff", c.goal_falloff);
    c.min_distance = o.non_negative("min_distance", c.min_distance);
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
    if (o.has("lamp")) c.lamp = read_lamp(o.child("lamp"), "model.lamp");
    if (o.has("moving_goal")) {
        JsonObject m(o.child("moving_goal"), "model.moving_goal");
        m.allow({"waypoints", "every"});
        m.require_key("waypoints");
        const json& w = m.child("waypoints");
        if (!w.is_array() || w.empty()) bad_json(m.at("waypoints"), "expected a non-empty array of [x, y, z]");
        for (size_t i = 0; i < w.size(); ++i)
            c.waypoints.push_back(JsonObject::to_vec3(w[i], m.at("waypoints") + "[" + std::to_string(i) + "]"));
        c.waypoint_every = uint32_t(m.integer("every", 60, 0xFFFFFFFFu));
        if (c.waypoint_every == 0) bad_json(m.at("every"), "expected an integer >= 1");
        m.finish();
    }
    o.finish();
    return c;
}

void check_path_section(const ModelSpec& spec, const SwarmConfig& swarm) {
    check_noise_in_domain(std::get<PathModelConfig>(spec).noise, swarm);
}

}  // namespace swarmcl
