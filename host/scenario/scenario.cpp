#include "io/scenario.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/philox.hpp"
#include "io/json_object.hpp"
#include "io/obj_loader.hpp"
#include "io/recorder.hpp"
#include "shapes/shape_library.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

const char* kNoiseTypes[] = {"curl", "perlin", "white", "gaussian"};

NoiseConfig read_noise(const json& j, const std::string& path) {
    JsonObject o(j, path);
    NoiseConfig c;
    const std::string type = o.string("type", "curl");
    bool known = false;
    for (int t = 0; t < 4; ++t)
        if (type == kNoiseTypes[t]) c.type = NoiseType(t), known = true;
    if (!known) bad_json(o.at("type"), "expected one of \"curl\", \"perlin\", \"white\", \"gaussian\"");
    c.scale = o.positive("scale", c.scale);
    c.gain = o.non_negative("gain", c.gain);
    c.seed = o.integer("seed", c.seed, std::numeric_limits<uint64_t>::max());
    c.time_scale = o.non_negative("time_scale", c.time_scale);
    c.boundary_distance = o.positive("boundary_distance", c.boundary_distance);
    c.domain_walls = o.boolean("domain_walls", c.domain_walls);
    c.baked = o.boolean("baked", c.baked);
    if (o.has("bake_resolution")) {
        const json& r = o.child("bake_resolution");
        if (r.is_number_integer()) {
            const auto v = r.get<int64_t>();
            if (v < 2 || v > 4096) bad_json(o.at("bake_resolution"), "expected an integer in [2, 4096] or 3 of them");
            c.bake_resolution = {uint32_t(v), uint32_t(v), uint32_t(v)};
        } else {
            const auto v = JsonObject::to_vec3(r, o.at("bake_resolution"));
            for (int a = 0; a < 3; ++a) {
                if (v[a] < 2 || v[a] > 4096 || v[a] != std::floor(v[a]))
                    bad_json(o.at("bake_resolution"), "expected an integer in [2, 4096] or 3 of them");
                c.bake_resolution[a] = uint32_t(v[a]);
            }
        }
    }
    c.finite_difference = o.boolean("finite_difference", c.finite_difference);
    o.finish();
    return c;
}

Boundary read_obstacle(const json& j, const std::string& path) {
    JsonObject o(j, path);
    Boundary b;
    o.require_key("type");
    const std::string type = o.string("type", "");
    if (type == "sphere") {
        o.allow({"type", "center", "radius"});
        b.kind = Boundary::Kind::Sphere;
        b.center = o.required_vec3("center");
        o.require_key("radius");
        b.radius = o.positive("radius", 0.0f);
    } else if (type == "box") {
        o.allow({"type", "center", "half_extents", "edge_radius"});
        b.kind = Boundary::Kind::Box;
        b.center = o.required_vec3("center");
        b.half_extents = o.required_vec3("half_extents");
        for (float h : b.half_extents)
            if (!(h > 0.0f)) bad_json(o.at("half_extents"), "expected 3 numbers > 0");
        b.radius = o.non_negative("edge_radius", 0.0f);
    } else if (type == "plane") {
        o.allow({"type", "normal", "offset"});
        b.kind = Boundary::Kind::Plane;
        b.normal = o.required_vec3("normal");
        if (b.normal[0] == 0 && b.normal[1] == 0 && b.normal[2] == 0) bad_json(o.at("normal"), "must not be zero");
        b.offset = float(o.number("offset", 0.0, -1e30, 1e30, "(finite)"));
    } else {
        bad_json(o.at("type"), "expected \"sphere\", \"box\" or \"plane\" (mesh obstacles come with the path-field model)");
    }
    o.finish();
    return b;
}

// ---- "type": "force": the shape-constrained force model (docs/force-model.md)

TriangleMesh read_keyframe_mesh(JsonObject& k, const std::string& base_dir) {
    TriangleMesh mesh;
    const bool has_shape = k.has("shape"), has_mesh = k.has("mesh"), has_obj = k.has("obj");
    if (int(has_shape) + int(has_mesh) + int(has_obj) != 1)
        bad_json(k.at("shape"), "expected one of \"shape\" (a generated shape's name), \"mesh\" or \"obj\" (an OBJ file)");
    if (has_obj) {
        // An OBJ file, a relative name read from the scenario file's folder
        // (as the path model's mesh obstacles).
        std::string file = k.string("obj", "");
        if (file.empty()) bad_json(k.at("obj"), "expected an OBJ file name");
        if (file[0] != '/' && !base_dir.empty()) file = base_dir + "/" + file;
        try {
            mesh = load_obj(file);
        } catch (const Error& e) {
            bad_json(k.at("obj"), e.what());
        }
    }
    try {
        if (has_shape) {
            mesh = generated_shape(k.string("shape", ""));
        } else if (has_mesh) {
            JsonObject m(k.child("mesh"), k.at("mesh"));
            m.allow({"vertices", "triangles"});
            m.require_key("vertices");
            m.require_key("triangles");
            const json& v = m.child("vertices");
            const json& t = m.child("triangles");
            if (!v.is_array() || !t.is_array()) bad_json(m.label(), "expected arrays of [x, y, z] and [i, j, k]");
            std::vector<float> xyz;
            std::vector<uint32_t> idx;
            for (size_t i = 0; i < v.size(); ++i) {
                const auto p = JsonObject::to_vec3(v[i], m.at("vertices") + "[" + std::to_string(i) + "]");
                xyz.insert(xyz.end(), p.begin(), p.end());
            }
            for (size_t i = 0; i < t.size(); ++i) {
                const json& f = t[i];
                if (!f.is_array() || f.size() != 3) bad_json(m.at("triangles") + "[" + std::to_string(i) + "]", "expected 3 indices");
                for (const json& x : f) {
                    if (!x.is_number_unsigned() || x.get<uint64_t>() > 0xFFFFFFFFu)
                        bad_json(m.at("triangles") + "[" + std::to_string(i) + "]", "expected 3 integers >= 0");
                    idx.push_back(uint32_t(x.get<uint64_t>()));
                }
            }
            mesh = make_mesh(xyz, idx);
        }
    } catch (const Error& e) {
        if (e.status() == Status::Parse) throw;
        bad_json(k.label(), e.what());
    }
    const float scale = k.positive("scale", 1.0f);
    const auto offset = k.vec3("offset", {0, 0, 0});
    return transformed(mesh, {scale, scale, scale}, offset);
}

ForceModelConfig read_force_model(JsonObject& o, std::vector<Boundary> obstacles, const std::string& base_dir) {
    ForceModelConfig c;
    c.r_rep = o.positive("r_rep", c.r_rep);
    c.r_ali = o.positive("r_ali", c.r_ali);
    c.r_att = o.positive("r_att", c.r_att);
    c.w_rep = o.non_negative("w_rep", c.w_rep);
    c.w_ali = o.non_negative("w_ali", c.w_ali);
    c.w_att = o.non_negative("w_att", c.w_att);
    c.w_dis = o.non_negative("w_dis", c.w_dis);
    c.w_con = o.non_negative("w_con", c.w_con);
    c.omega = o.positive("omega", c.omega);
    c.neighbor_k = o.positive("neighbor_k", c.neighbor_k);
    c.distance_scale = o.non_negative("distance_scale", c.distance_scale);
    c.neighbor_sample = uint32_t(o.integer("neighbor_sample", c.neighbor_sample, 0xFFFFFFFFu));
    const float rho = o.positive("rho", c.noise.scale);
    const float eta = o.non_negative("eta", c.noise.gain * c.noise.scale);
    c.noise.scale = rho;
    c.noise.gain = eta / rho;  // Eq. 4 in metres (ForceModelConfig::noise)
    c.noise.seed = o.integer("noise_seed", c.noise.seed, std::numeric_limits<uint64_t>::max());
    c.alpha = float(o.number("alpha", c.alpha, 0.0, 1.0, "in [0, 1]"));
    c.max_speed = o.positive("max_speed", c.max_speed);
    c.cruise_speed = o.non_negative("cruise_speed", c.cruise_speed);
    c.min_distance = o.non_negative("min_distance", c.min_distance);
    c.min_spacing = o.non_negative("min_spacing", c.min_spacing);
    const std::string assignment = o.string("assignment", "nearest");
    if (assignment == "nearest") c.assignment = Assignment::Nearest;
    else if (assignment == "curve") c.assignment = Assignment::Curve;
    else bad_json(o.at("assignment"), "expected \"nearest\" or \"curve\"");
    c.sample_seed = o.integer("sample_seed", c.sample_seed, std::numeric_limits<uint64_t>::max());
    if (o.has("keyframes")) {
        const json& list = o.child("keyframes");
        if (!list.is_array()) bad_json(o.at("keyframes"), "expected an array of {\"frame\", \"shape\" or \"mesh\"}");
        for (size_t i = 0; i < list.size(); ++i) {
            JsonObject k(list[i], o.at("keyframes") + "[" + std::to_string(i) + "]");
            k.allow({"frame", "shape", "mesh", "obj", "scale", "offset"});
            const uint64_t frame = k.integer("frame", 0, 0xFFFFFFFFu);
            if (i > 0 && frame <= c.keyframes.back().frame)
                bad_json(k.at("frame"), "keyframes must be in strictly increasing frame order");
            c.keyframes.push_back({frame, read_keyframe_mesh(k, base_dir)});
            k.finish();
        }
    }
    c.keyframe_period = o.integer("keyframe_period", 0, 0xFFFFFFFFu);
    if (o.has("path")) {
        JsonObject p(o.child("path"), o.at("path"));
        p.allow({"points", "speed", "orient"});
        p.require_key("points");
        const json& pts = p.child("points");
        if (!pts.is_array() || pts.size() < 4) bad_json(p.at("points"), "expected at least 4 [x, y, z] control points");
        for (size_t i = 0; i < pts.size(); ++i) {
            const auto v = JsonObject::to_vec3(pts[i], p.at("points") + "[" + std::to_string(i) + "]");
            c.path.insert(c.path.end(), v.begin(), v.end());
        }
        c.path_speed = p.non_negative("speed", c.path_speed);
        c.path_orient = p.boolean("orient", c.path_orient);
        p.finish();
    }
    for (size_t i = 0; i < obstacles.size(); ++i)
        if (obstacles[i].kind == Boundary::Kind::Plane)
            bad_json("obstacles[" + std::to_string(i) + "]",
                     "the force model takes sphere, box, cylinder and mesh (OBJ file) obstacles");
    c.obstacles = std::move(obstacles);
    c.obstacle_range = o.positive("obstacle_range", c.obstacle_range);
    c.mesh_cell = o.non_negative("mesh_cell", c.mesh_cell);  // mesh obstacles' grid (0: obstacle_range / 4)
    o.finish();
    try {
        validate(c);
    } catch (const Error& e) {
        bad_json("model", e.what());
    }
    return c;
}

// ---- the path model ("model": {"type": "path"}, docs/path-field.md) --------

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

// Obstacles of the path model are meshes: boxes, spheres, cylinders (the
// shared primitives) and OBJ files.
TriangleMesh read_mesh_obstacle(const json& j, const std::string& path, const std::string& base_dir) {
    JsonObject o(j, path);
    o.require_key("type");
    const std::string type = o.string("type", "");
    TriangleMesh m;
    try {
        if (type == "box") {
            o.allow({"type", "center", "half_extents", "edge_radius"});
            const auto c = o.required_vec3("center"), h = o.required_vec3("half_extents");
            for (float v : h)
                if (!(v > 0.0f)) bad_json(o.at("half_extents"), "expected 3 numbers > 0");
            o.non_negative("edge_radius", 0.0f);  // the field model's rounding; meshes keep sharp edges
            m = box_mesh(c, h);
        } else if (type == "sphere") {
            o.allow({"type", "center", "radius"});
            const auto c = o.required_vec3("center");
            o.require_key("radius");
            m = sphere_mesh(c, o.positive("radius", 0.0f), 24, 48);
        } else if (type == "cylinder") {
            o.allow({"type", "base", "radius", "height"});
            const auto b = o.required_vec3("base");
            o.require_key("radius");
            o.require_key("height");
            const float r = o.positive("radius", 0.0f), h = o.positive("height", 0.0f);
            m = cylinder_mesh(b, r, h, 48);
        } else if (type == "mesh") {
            o.allow({"type", "file", "scale", "offset"});
            o.require_key("file");
            std::string file = o.string("file", "");
            if (file.empty()) bad_json(o.at("file"), "expected an OBJ file name");
            if (file[0] != '/' && !base_dir.empty()) file = base_dir + "/" + file;
            const auto scale = o.vec3("scale", {1, 1, 1}), offset = o.vec3("offset", {0, 0, 0});
            m = transformed(load_obj(file), scale, offset);
        } else {
            bad_json(o.at("type"), "expected \"box\", \"sphere\", \"cylinder\" or \"mesh\" (an OBJ file)");
        }
    } catch (const Error& e) {
        // A scenario error, whatever the mesh's own status (an unreadable
        // OBJ file is a bad value in the scenario too).
        if (std::string(e.what()).rfind(path, 0) == 0) throw;
        fail(Status::Parse, path + ": " + e.what());
    }
    o.finish();
    return m;
}

void read_path_model(JsonObject& o, Scenario& s, const json* obstacles, const std::string& base_dir) {
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
    } else {
        o.require_key("goals");
        c.groups.push_back({0, read_goals(o.child("goals"), "model.goals")});
    }
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
    s.path_model = std::move(c);
}

void read_model(const json& j, Scenario& s, std::vector<Boundary> obstacles, const std::string& base_dir) {
    JsonObject o(j, "model");
    const std::string type = o.string("type", "field");
    if (type == "ballistic") {
        o.finish();
        if (!obstacles.empty()) bad_json("obstacles", "a ballistic model ignores obstacles: remove them or use \"field\"");
        return;
    }
    if (type == "energy") {  // FASTSWARM: host/io/scenario_energy.cpp reads the rest
        EnergyScenario e = read_energy_scenario(j, "model");
        if (o.has("noise")) e.config.noise = read_noise(o.child("noise"), "model.noise");
        e.config.noise.boundaries = std::move(obstacles);
        s.energy_model = std::move(e);
        return;
    }
    if (type == "force") {
        s.force_model = read_force_model(o, std::move(obstacles), base_dir);
        return;
    }
    if (type != "field")
        bad_json("model.type", "expected \"field\", \"path\", \"force\", \"energy\" or \"ballistic\"");
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
    s.field_model = std::move(c);
}

void read_agents(const json& j, Scenario& s) {
    JsonObject o(j, "agents");
    o.allow({"count", "capacity", "velocity", "initial"});
    o.require_key("count");
    const uint64_t count = o.integer("count", 0, 0xFFFFFFFEu);
    const uint64_t capacity = o.integer("capacity", std::max<uint64_t>(count, 1), 0xFFFFFFFEu);
    if (capacity < count || capacity == 0) bad_json(o.at("capacity"), "expected an integer >= agents.count and > 0");
    s.swarm.agent_count = 0;  // placed from `initial` after creation
    s.swarm.capacity = uint32_t(capacity);
    s.initial.velocity = o.vec3("velocity", {0, 0, 0});
    s.initial.min = s.swarm.domain_min;
    s.initial.max = s.swarm.domain_max;
    if (o.has("initial")) {
        JsonObject d(o.child("initial"), "agents.initial");
        const std::string type = d.string("type", "uniform");
        if (type == "uniform") {
            s.initial.kind = InitialDistribution::Kind::Uniform;
            s.initial.min = d.vec3("min", s.initial.min);
            s.initial.max = d.vec3("max", s.initial.max);
            for (int a = 0; a < 3; ++a)
                if (!(s.initial.min[a] <= s.initial.max[a])) bad_json(d.at("min"), "must not exceed agents.initial.max");
        } else if (type == "sphere") {
            d.allow({"type", "center", "radius"});
            s.initial.kind = InitialDistribution::Kind::Sphere;
            s.initial.center = d.required_vec3("center");
            d.require_key("radius");
            s.initial.radius = d.positive("radius", 0.0f);
        } else if (type == "points") {
            d.allow({"type", "positions"});
            s.initial.kind = InitialDistribution::Kind::Points;
            d.require_key("positions");
            const json& p = d.child("positions");
            if (!p.is_array() || p.size() != count)
                bad_json(d.at("positions"), "expected an array of agents.count (" + std::to_string(count) + ") [x, y, z]");
            for (size_t i = 0; i < p.size(); ++i) {
                const auto v = JsonObject::to_vec3(p[i], d.at("positions") + "[" + std::to_string(i) + "]");
                s.initial.points.insert(s.initial.points.end(), v.begin(), v.end());
            }
        } else {
            bad_json(d.at("type"), "expected \"uniform\", \"sphere\" or \"points\"");
        }
        d.finish();
    }
    o.finish();
    s.swarm.agent_count = uint32_t(count);
}

void read_output(const json& j, Scenario& s) {
    JsonObject o(j, "output");
    s.output_dir = o.string("dir", s.output_dir);
    if (s.output_dir.empty()) bad_json(o.at("dir"), "expected a non-empty folder name");
    if (o.has("formats")) {
        const json& f = o.child("formats");
        if (!f.is_array() || f.empty()) bad_json(o.at("formats"), "expected a non-empty array of \"csv\", \"npy\", \"vtp\"");
        s.output_formats = 0;
        for (size_t i = 0; i < f.size(); ++i) {
            const std::string at = o.at("formats") + "[" + std::to_string(i) + "]";
            const std::string name = f[i].is_string() ? f[i].get<std::string>() : std::string();
            if (name == "csv") s.output_formats |= kExportCsv;
            else if (name == "npy") s.output_formats |= kExportNpy;
            else if (name == "vtp") s.output_formats |= kExportVtp;
            else bad_json(at, "expected \"csv\", \"npy\" or \"vtp\"");
        }
    }
    s.output_every = uint32_t(o.integer("every", s.output_every, 0xFFFFFFFFu));
    if (s.output_every == 0) bad_json(o.at("every"), "expected an integer >= 1");
    o.finish();
}

// "line L, column C" of a byte offset, for JSON syntax errors.
std::string position_of(const std::string& text, size_t byte) {
    size_t line = 1, col = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) {
        if (text[i] == '\n') ++line, col = 1;
        else ++col;
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& base_dir) {
    json root;
    try {
        root = json::parse(text);
    } catch (const json::parse_error& e) {
        std::string what = e.what();
        const auto colon = what.rfind(": ");
        fail(Status::Parse, "malformed JSON at " + position_of(text, e.byte == 0 ? 0 : e.byte - 1) + ": " +
                                (colon == std::string::npos ? what : what.substr(colon + 2)));
    } catch (const json::exception& e) {
        // e.g. out_of_range.406 "number overflow parsing '1e400'": no position.
        const std::string what = e.what();
        const auto bracket = what.find("] ");
        fail(Status::Parse, "malformed JSON: " + (bracket == std::string::npos ? what : what.substr(bracket + 2)));
    }
    Scenario s;
    s.source = text;
    JsonObject top(root, "");
    s.name = top.string("name", s.name);
    // The name names the output files (and swcl_scenario_info.name[128]).
    if (s.name.empty() || s.name.size() > 127 || s.name == "." || s.name == ".." ||
        s.name.find_first_of(std::string("/\\\0", 3)) != std::string::npos)
        bad_json("name", "expected 1 to 127 characters without '/', '\\' or NUL (it names the output files)");
    s.swarm.seed = top.integer("seed", 0, std::numeric_limits<uint64_t>::max());
    s.swarm.dt = top.positive("dt", s.swarm.dt);
    s.steps = uint32_t(top.integer("steps", s.steps, 100000000));
    s.swarm.interaction_radius = top.positive("interaction_radius", s.swarm.interaction_radius);
    if (top.has("domain")) {
        JsonObject d(top.child("domain"), "domain");
        d.allow({"min", "max"});
        s.swarm.domain_min = d.required_vec3("min");
        s.swarm.domain_max = d.required_vec3("max");
        for (int a = 0; a < 3; ++a)
            if (!(s.swarm.domain_min[a] < s.swarm.domain_max[a])) bad_json("domain.min", "must be below domain.max on every axis");
        d.finish();
    }
    top.require_key("agents");
    read_agents(top.child("agents"), s);
    std::vector<Boundary> obstacles;
    // The path model reads its obstacles as meshes (read_path_model).
    const bool path_model = root.contains("model") && root["model"].is_object() && root["model"].contains("type") &&
                            root["model"]["type"] == "path";
    // The force model also takes the path model's mesh obstacles ("mesh": an
    // OBJ file, "cylinder"); its spheres and boxes stay analytic.
    const bool force_model = root.contains("model") && root["model"].is_object() &&
                             root["model"].contains("type") && root["model"]["type"] == "force";
    std::vector<TriangleMesh> force_meshes;
    if (top.has("obstacles")) {
        const json& list = top.child("obstacles");
        if (!list.is_array()) bad_json("obstacles", "expected an array");
        for (size_t i = 0; i < list.size() && !path_model; ++i) {
            const std::string where = "obstacles[" + std::to_string(i) + "]";
            const bool mesh_type = list[i].is_object() && list[i].contains("type") &&
                                   (list[i]["type"] == "mesh" || list[i]["type"] == "cylinder");
            if (force_model && mesh_type) force_meshes.push_back(read_mesh_obstacle(list[i], where, base_dir));
            else obstacles.push_back(read_obstacle(list[i], where));
        }
    }
    if (path_model) {
        JsonObject m(top.child("model"), "model");
        m.string("type", "");
        read_path_model(m, s, top.has("obstacles") ? &top.child("obstacles") : nullptr, base_dir);
    } else if (top.has("model")) read_model(top.child("model"), s, std::move(obstacles), base_dir);
    if (s.force_model && !force_meshes.empty()) {
        s.force_model->mesh_obstacles = std::move(force_meshes);
        try {
            validate(*s.force_model);
        } catch (const Error& e) {
            bad_json("obstacles", e.what());
        }
    }
    else if (!obstacles.empty()) bad_json("obstacles", "obstacles need a model (\"model\": {\"type\": \"field\"})");
    if (top.has("output")) read_output(top.child("output"), s);
    top.finish();
    for (const NoiseConfig* model_noise : {s.energy_model ? &s.energy_model->config.noise : nullptr,
                                           s.path_model ? &s.path_model->noise : nullptr}) {
        if (!model_noise) continue;
        auto noise = *model_noise;
        if (!noise.has_region()) noise.region_min = s.swarm.domain_min, noise.region_max = s.swarm.domain_max;
        try {
            NoiseField::validate(noise);
        } catch (const Error& e) {
            bad_json("model.noise", e.what());
        }
    }
    if (s.field_model) {
        // The model's own checks (noise parameters and their combinations),
        // reported under the scenario path.
        auto noise = s.field_model->noise;
        if (!noise.has_region()) noise.region_min = s.swarm.domain_min, noise.region_max = s.swarm.domain_max;
        try {
            NoiseField::validate(noise);
        } catch (const Error& e) {
            bad_json("model.noise", e.what());
        }
    }
    return s;
}

Scenario load_scenario(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(Status::Io, "cannot open scenario file '" + path + "'");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) fail(Status::Io, "cannot read scenario file '" + path + "'");
    try {
        const auto slash = path.find_last_of('/');
        return parse_scenario(text.str(), slash == std::string::npos ? "" : path.substr(0, slash));
    } catch (const Error& e) {
        fail(e.status(), path + ": " + e.what());
    }
}

std::vector<float> Scenario::initial_positions() const {
    const uint32_t n = swarm.agent_count;
    if (initial.kind == InitialDistribution::Kind::Points) return initial.points;
    std::vector<float> xyz(size_t(n) * 3);
    for (uint32_t id = 0; id < n; ++id) {
        const auto r = philox_for(swarm.seed, id, 0, 0);
        float u[3] = {uniform01(r[0]), uniform01(r[1]), uniform01(r[2])};
        if (initial.kind == InitialDistribution::Kind::Uniform) {
            for (int a = 0; a < 3; ++a) xyz[3 * size_t(id) + a] = initial.min[a] + u[a] * (initial.max[a] - initial.min[a]);
        } else {
            // Uniform in a ball: radius ∝ cbrt(u), direction uniform on the sphere.
            const float cz = 2.0f * u[1] - 1.0f, phi = 6.2831853f * u[2];
            const float sz = std::sqrt(std::max(0.0f, 1.0f - cz * cz));
            const float rad = initial.radius * std::cbrt(uniform01(r[3]));
            const float dir[3] = {sz * std::cos(phi), sz * std::sin(phi), cz};
            for (int a = 0; a < 3; ++a) xyz[3 * size_t(id) + a] = initial.center[a] + rad * dir[a];
        }
    }
    return xyz;
}

}  // namespace swarmcl
