#include "scenario/scenario.hpp"

#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/philox.hpp"
#include "io/json_object.hpp"
#include "io/export_format.hpp"
#include "scenario/model_section.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

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
            s.initial.min_is_domain = !d.has("min");
            s.initial.max_is_domain = !d.has("max");
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
        if (!f.is_array() || f.empty())
            bad_json(o.at("formats"), "expected a non-empty array of " + export_format_choices("\""));
        s.output_formats = 0;
        for (size_t i = 0; i < f.size(); ++i) {
            const std::string at = o.at("formats") + "[" + std::to_string(i) + "]";
            const std::string name = f[i].is_string() ? f[i].get<std::string>() : std::string();
            const ExportFormatInfo* format = find_export_format(name);
            if (!format) bad_json(at, "expected " + export_format_choices("\""));
            s.output_formats |= format->bit;
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
    const json* obstacles = nullptr;
    if (top.has("obstacles")) {
        obstacles = &top.child("obstacles");
        if (!obstacles->is_array()) bad_json("obstacles", "expected an array");
    }
    const json* model = top.has("model") ? &top.child("model") : nullptr;
    ModelSectionResult read = read_model_section(model, obstacles, base_dir);
    s.model = std::move(read.spec);
    if (top.has("output")) read_output(top.child("output"), s);
    top.finish();
    if (read.section && read.section->check) read.section->check(s.model, s.swarm);
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
