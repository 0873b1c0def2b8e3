// "model": {"type": "energy"}: FASTSWARM (docs/energy-model.md).  Its
// parameters (weights, radii, the noise, ...) are its table's keys
// (models/energy_params.cpp); read here by hand: where the reference dataset
// comes from, the stimuli and the keypoints, and the analytic obstacles as
// the noise's boundaries.
#include <cmath>
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "io/json_object.hpp"
#include "params/param_table.hpp"
#include "scenario/model_section.hpp"
#include "scenario/section_parts.hpp"

namespace swarmcl {
namespace {

using json = nlohmann::json;

void read_dataset(const json& j, const std::string& path, EnergySpec& e) {
    JsonObject r(j, path);
    const std::string type = r.string("type", "synthetic");
    if (type == "synthetic") {
        e.source = EnergySpec::Source::Synthetic;
        e.synthetic_frame_time = r.number("frame_time", e.synthetic_frame_time, 1e-6, 10.0, "in [1e-6, 10] s");
        e.synthetic_mean_speed = r.positive("mean_speed", e.synthetic_mean_speed);
    } else if (type == "file" || type == "tracks") {
        e.source = type == "file" ? EnergySpec::Source::File : EnergySpec::Source::Tracks;
        if (!r.has("path")) bad_json(r.at("path"), "missing");
        e.path = r.string("path", "");
        if (e.path.empty()) bad_json(r.at("path"), "expected a file name");
    } else {
        bad_json(r.at("type"), "expected \"synthetic\", \"file\" or \"tracks\"");
    }
    if (type == "tracks") {
        TrackLoadOptions& t = e.tracks;
        if (r.has("columns")) {
            JsonObject c(r.child("columns"), r.at("columns"));
            t.columns.id = c.string("id", t.columns.id);
            t.columns.time = c.string("time", t.columns.time);
            t.columns.x = c.string("x", t.columns.x);
            t.columns.y = c.string("y", t.columns.y);
            t.columns.z = c.string("z", t.columns.z);
            c.finish();
        }
        const std::string tf = r.string("time_format", "auto");
        if (tf == "auto") t.time_format = TimeFormat::Auto;
        else if (tf == "seconds") t.time_format = TimeFormat::Seconds;
        else if (tf == "frame") t.time_format = TimeFormat::Frame;
        else if (tf == "datetime") t.time_format = TimeFormat::DateTime;
        else bad_json(r.at("time_format"), "expected \"auto\", \"seconds\", \"frame\" or \"datetime\"");
        t.frame_time = r.number("frame_time", t.frame_time, 0.0, 10.0, "in [0, 10] s (0: estimate)");
        t.unit_scale = r.number("unit_scale", t.unit_scale, 1e-9, 1e9, "in [1e-9, 1e9]");
        t.gap_factor = r.number("gap_factor", t.gap_factor, 1.0, 1e6, ">= 1");
        t.smoothing = uint32_t(r.integer("smoothing", t.smoothing, 0, 1000));
        if (t.time_format == TimeFormat::Frame && !(t.frame_time > 0.0))
            bad_json(r.at("frame_time"), "time_format \"frame\" needs frame_time > 0");
    }
    if (type != "file") {
        e.dataset.k = uint32_t(r.integer("k", e.dataset.k, 1, 1u << 24));
        e.dataset.groups = uint32_t(r.integer("groups", e.dataset.groups, 1, 1u << 24));
        e.dataset.seed = r.integer("seed", e.dataset.seed, 0, std::numeric_limits<uint64_t>::max());
        if (e.dataset.groups > e.dataset.k) bad_json(r.at("groups"), "expected at most k groups");
    }
    r.finish();
}

// The structured keys of the model object, read by hand below; every other
// key is a row of energy_param_table().
const std::set<std::string> kStructured = {"type", "dataset", "stimuli", "keypoints"};

// The model object: the table's parameters, then the structured keys.
EnergySpec read_energy_scenario(const json& j, const std::string& path) {
    EnergySpec e;
    EnergyModelConfig& c = e.config;
    // A "noise" object describes the whole noise: keys it leaves out take
    // the noise's defaults (swcl_noise_desc_default), not the energy
    // model's own (scale 0.2 m, time_scale 1 s, which hold without the
    // object) -- as this section has always read it, so that a scenario's
    // run stays the same.
    if (j.is_object() && j.contains("noise")) c.noise = NoiseConfig{};
    energy_param_table().read_json(j, path, &c, kStructured);
    c.has_fixed_centre = j.contains("centre");
    JsonObject r(j, path, {"type"});
    if (r.has("dataset")) read_dataset(r.child("dataset"), r.at("dataset"), e);
    if (r.has("stimuli")) {
        const json& list = r.child("stimuli");
        if (!list.is_array()) bad_json(r.at("stimuli"), "expected an array");
        for (size_t i = 0; i < list.size(); ++i) {
            const std::string sp = r.at("stimuli") + "[" + std::to_string(i) + "]";
            JsonObject s(list[i], sp);
            Stimulus st;
            const std::string kind = s.string("type", "attract");
            if (kind == "attract") st.kind = Stimulus::Kind::Attract;
            else if (kind == "startle") st.kind = Stimulus::Kind::Startle;
            else bad_json(s.at("type"), "expected \"attract\" or \"startle\"");
            if (!s.has("position")) bad_json(s.at("position"), "missing");
            st.position = s.vec3("position", {});
            st.velocity = s.vec3("velocity", {0, 0, 0});
            st.d_danger = s.positive("d_danger", st.d_danger);
            s.finish();
            c.stimuli.push_back(st);
        }
    }
    if (r.has("keypoints")) {
        const json& list = r.child("keypoints");
        if (!list.is_array() || list.size() < 2)
            bad_json(r.at("keypoints"), "expected an array of at least 2 [x, y, z] keypoints");
        for (size_t i = 0; i < list.size(); ++i)
            c.keypoints.push_back(JsonObject::to_vec3(list[i], r.at("keypoints") + "[" + std::to_string(i) + "]"));
    }
    // The model's own checks (combinations such as d_att1 >= d_rep), minus
    // the noise which check_energy_section checks in the swarm's domain.
    try {
        EnergyModelConfig check = c;
        check.noise = NoiseConfig{};
        EnergyModel::validate(check);
    } catch (const Error& err) {
        bad_json(path, err.what());
    }
    return e;
}

}  // namespace

ModelSpec read_energy_section(const SectionInput& in) {
    std::vector<Boundary> obstacles = read_obstacles(in.obstacles);
    EnergySpec e = read_energy_scenario(in.model, "model");
    JsonObject(in.model, "model", {"type"}).string("type", "field");
    e.config.noise.boundaries = std::move(obstacles);
    return e;
}

void check_energy_section(const ModelSpec& spec, const SwarmConfig& swarm) {
    check_noise_in_domain(std::get<EnergySpec>(spec).config.noise, swarm);
}

}  // namespace swarmcl
