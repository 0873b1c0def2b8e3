#include "scenario/section_parts.hpp"

#include <cmath>
#include <limits>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "io/json_object.hpp"
#include "shapes/obstacle_spec.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

const char* kNoiseTypes[] = {"curl", "perlin", "white", "gaussian"};

}  // namespace

NoiseType read_noise_type(JsonObject& o, const std::string& key, NoiseType def) {
    const std::string type = o.string(key, kNoiseTypes[int(def)]);
    for (int t = 0; t < 4; ++t)
        if (type == kNoiseTypes[t]) return NoiseType(t);
    bad_json(o.at(key), "expected one of \"curl\", \"perlin\", \"white\", \"gaussian\"");
}

NoiseConfig read_noise(const json& j, const std::string& path) {
    JsonObject o(j, path);
    NoiseConfig c;
    c.type = read_noise_type(o, "type", NoiseType::Curl);
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

void check_noise_in_domain(NoiseConfig noise, const SwarmConfig& swarm) {
    // The model's own checks (noise parameters and their combinations),
    // reported under the scenario path.
    if (!noise.has_region()) noise.region_min = swarm.domain_min, noise.region_max = swarm.domain_max;
    try {
        NoiseField::validate(noise);
    } catch (const Error& e) {
        bad_json("model.noise", e.what());
    }
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

std::vector<Boundary> read_obstacles(const json* list) {
    std::vector<Boundary> out;
    if (list)
        for (size_t i = 0; i < list->size(); ++i)
            out.push_back(read_obstacle((*list)[i], "obstacles[" + std::to_string(i) + "]"));
    return out;
}

// Obstacles of the path model are meshes: boxes, spheres, cylinders (the
// shared primitives) and OBJ files.
TriangleMesh read_mesh_obstacle(const json& j, const std::string& path, const std::string& base_dir) {
    JsonObject o(j, path);
    o.require_key("type");
    const std::string type = o.string("type", "");
    ObstacleSpec spec;
    TriangleMesh m;
    try {
        if (type == "box") {
            o.allow({"type", "center", "half_extents", "edge_radius"});
            spec.kind = ObstacleSpec::Kind::Box;
            spec.center = o.required_vec3("center");
            spec.half_extents = o.required_vec3("half_extents");
            for (float v : spec.half_extents)
                if (!(v > 0.0f)) bad_json(o.at("half_extents"), "expected 3 numbers > 0");
            o.non_negative("edge_radius", 0.0f);  // the field model's rounding; meshes keep sharp edges
        } else if (type == "sphere") {
            o.allow({"type", "center", "radius"});
            spec.kind = ObstacleSpec::Kind::Sphere;
            spec.center = o.required_vec3("center");
            o.require_key("radius");
            spec.radius = o.positive("radius", 0.0f);
        } else if (type == "cylinder") {
            o.allow({"type", "base", "radius", "height"});
            spec.kind = ObstacleSpec::Kind::Cylinder;
            spec.center = o.required_vec3("base");
            o.require_key("radius");
            o.require_key("height");
            spec.radius = o.positive("radius", 0.0f);
            spec.height = o.positive("height", 0.0f);
        } else if (type == "mesh") {
            o.allow({"type", "file", "scale", "offset"});
            spec.kind = ObstacleSpec::Kind::Obj;
            o.require_key("file");
            spec.path = o.string("file", "");
            if (spec.path.empty()) bad_json(o.at("file"), "expected an OBJ file name");
            if (spec.path[0] != '/' && !base_dir.empty()) spec.path = base_dir + "/" + spec.path;
            spec.place = true;
            spec.scale = o.vec3("scale", {1, 1, 1});
            spec.offset = o.vec3("offset", {0, 0, 0});
        } else {
            bad_json(o.at("type"), "expected \"box\", \"sphere\", \"cylinder\" or \"mesh\" (an OBJ file)");
        }
        m = obstacle_mesh(spec);
    } catch (const Error& e) {
        // A scenario error, whatever the mesh's own status (an unreadable
        // OBJ file is a bad value in the scenario too).
        if (std::string(e.what()).rfind(path, 0) == 0) throw;
        fail(Status::Parse, path + ": " + e.what());
    }
    o.finish();
    return m;
}

}  // namespace swarmcl
