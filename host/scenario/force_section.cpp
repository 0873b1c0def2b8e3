// "model": {"type": "force"}: the shape-constrained force model
// (docs/force-model.md).  Its spheres and boxes stay analytic; "cylinder" and
// "mesh" (an OBJ file) obstacles are meshes as in the path model.  Its
// parameters are its table's keys (models/force_params.cpp); the legacy noise
// keys, keyframes and the path's points are read here.
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

#include "io/json_object.hpp"
#include "params/param_table.hpp"
#include "scenario/model_section.hpp"
#include "scenario/section_parts.hpp"
#include "shapes/keyframe_spec.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

// One keyframe's mesh (shapes/keyframe_spec): the source is checked and
// built before the placement is read, so a bad mesh is reported first.
TriangleMesh read_keyframe_mesh(JsonObject& k, const std::string& base_dir) {
    KeyframeSpec spec;
    TriangleMesh mesh;
    const bool has_shape = k.has("shape"), has_mesh = k.has("mesh"), has_obj = k.has("obj");
    if (int(has_shape) + int(has_mesh) + int(has_obj) != 1)
        bad_json(k.at("shape"), "expected one of \"shape\" (a generated shape's name), \"mesh\" or \"obj\" (an OBJ file)");
    if (has_obj) {
        // An OBJ file, a relative name read from the scenario file's folder
        // (as the path model's mesh obstacles).
        spec.source = KeyframeSpec::Source::Obj;
        spec.name = k.string("obj", "");
        if (spec.name.empty()) bad_json(k.at("obj"), "expected an OBJ file name");
        if (spec.name[0] != '/' && !base_dir.empty()) spec.name = base_dir + "/" + spec.name;
        try {
            mesh = keyframe_source_mesh(spec);
        } catch (const Error& e) {
            bad_json(k.at("obj"), e.what());
        }
    }
    try {
        if (has_shape) {
            spec.source = KeyframeSpec::Source::Shape;
            spec.name = k.string("shape", "");
            mesh = keyframe_source_mesh(spec);
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
            spec.source = KeyframeSpec::Source::Mesh;
            spec.vertices = xyz.data();
            spec.vertex_count = xyz.size() / 3;
            spec.triangles = idx.data();
            spec.triangle_count = idx.size() / 3;
            mesh = keyframe_source_mesh(spec);
        }
    } catch (const Error& e) {
        if (e.status() == Status::Parse) throw;
        bad_json(k.label(), e.what());
    }
    spec.scale = k.positive("scale", 1.0f);
    spec.offset = k.vec3("offset", {0, 0, 0});
    return placed_keyframe_mesh(spec, mesh);
}

// The keys of the model object that the table (models/force_params.cpp) does
// not read: the type, the legacy noise keys and the structured parts.
const std::set<std::string> kHandled = {"type",       "eta",        "rho",         "noise_seed", "noise_type",
                                        "noise_time_scale", "keyframes", "path.points"};

ForceModelConfig read_force_model(const json& model, std::vector<Boundary> obstacles, const std::string& base_dir) {
    JsonObject o(model, "model", kHandled);
    o.string("type", "field");
    ForceModelConfig c;
    if (model.is_object() && model.contains("noise")) {
        // The internal noise term as a noise object (as the field model's):
        // another type than curl gives the papers' baselines (BSwarm-style
        // Gaussian noise, Boids + Perlin / random noise; docs/baselines.md).
        // Its gain is the noise module's (force units, m/s^2), not eta / rho,
        // and it starts from the noise module's defaults, not Table 1's.
        for (const char* key : {"eta", "rho", "noise_seed", "noise_type", "noise_time_scale"})
            if (o.has(key)) bad_json(o.at(key), std::string("give either \"noise\" or ") + key + ", not both");
        c.noise = NoiseConfig{};
    }
    // Every parameter of the table present in the object (ranges, unknown keys).
    force_param_table().read_json(model, "model", &c, kHandled);
    if (!model.contains("noise")) {
        const float rho = o.positive("rho", c.noise.scale);
        const float eta = o.non_negative("eta", c.noise.gain * c.noise.scale);
        c.noise.scale = rho;
        c.noise.gain = eta / rho;  // Eq. 4 in metres (ForceModelConfig::noise)
        c.noise.seed = o.integer("noise_seed", c.noise.seed, std::numeric_limits<uint64_t>::max());
        // The noise term of Eq. 4 is curl noise; the other types stand in for
        // it in the noise paper's study of noise functions (§4.2,
        // docs/evaluation.md), with eta / rho as for curl.
        c.noise.type = read_noise_type(o, "noise_type", c.noise.type);
        // > 0: the noise field varies in time (4D noise), seconds per noise unit.
        c.noise.time_scale = o.non_negative("noise_time_scale", c.noise.time_scale);
    }
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
    if (o.has("path")) {  // "speed" and "orient" are the table's
        JsonObject p(o.child("path"), o.at("path"), {"speed", "orient"});
        p.require_key("points");
        const json& pts = p.child("points");
        if (!pts.is_array() || pts.size() < 4) bad_json(p.at("points"), "expected at least 4 [x, y, z] control points");
        for (size_t i = 0; i < pts.size(); ++i) {
            const auto v = JsonObject::to_vec3(pts[i], p.at("points") + "[" + std::to_string(i) + "]");
            c.path.insert(c.path.end(), v.begin(), v.end());
        }
    }
    for (size_t i = 0; i < obstacles.size(); ++i)
        if (obstacles[i].kind == Boundary::Kind::Plane)
            bad_json("obstacles[" + std::to_string(i) + "]",
                     "the force model takes sphere, box, cylinder and mesh (OBJ file) obstacles");
    c.obstacles = std::move(obstacles);
    try {
        validate(c);
    } catch (const Error& e) {
        bad_json("model", e.what());
    }
    return c;
}

}  // namespace

ModelSpec read_force_section(const SectionInput& in) {
    // Obstacles in file order: cylinders and OBJ meshes as meshes, the rest
    // analytic (planes are refused by read_force_model).
    std::vector<Boundary> obstacles;
    std::vector<TriangleMesh> meshes;
    if (in.obstacles)
        for (size_t i = 0; i < in.obstacles->size(); ++i) {
            const json& entry = (*in.obstacles)[i];
            const std::string where = "obstacles[" + std::to_string(i) + "]";
            const bool mesh_type = entry.is_object() && entry.contains("type") &&
                                   (entry["type"] == "mesh" || entry["type"] == "cylinder");
            if (mesh_type) meshes.push_back(read_mesh_obstacle(entry, where, in.base_dir));
            else obstacles.push_back(read_obstacle(entry, where));
        }
    ForceModelConfig c = read_force_model(in.model, std::move(obstacles), in.base_dir);
    if (!meshes.empty()) {
        c.mesh_obstacles = std::move(meshes);
        try {
            validate(c);
        } catch (const Error& e) {
            bad_json("obstacles", e.what());
        }
    }
    return c;
}

}  // namespace swarmcl
