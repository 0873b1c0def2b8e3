// The parameter tables (host/params/, issue 24): reading a scenario's model
// object from a table (values, ranges, unknown keys, required keys), the
// range checks of a config, the device block's layout, the exported JSON
// (swcl_model_parameters) and the generated tables of docs/scenarios.md.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <type_traits>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "data/dataset.hpp"
#include "models/energy_spec.hpp"
#include "models/field_model.hpp"
#include "models/force_model.hpp"
#include "models/path_model.hpp"
#include "models/policy_model.hpp"
#include "models/model_checkpoint.hpp"
#include "models/swarm_checkpoint.hpp"
#include "params/param_table.hpp"
#include "scenario/scenario.hpp"
#include "swarmcl/swarmcl.h"

namespace {

using namespace swarmcl;
using json = nlohmann::json;

std::string read_error(const ParamTable& t, const std::string& text, void* config) {
    try {
        t.read_json(json::parse(text), "model", config, {"type"});
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Parse) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "read: " << text;
    return {};
}

TEST(ParamTable, ReadsEveryKindOfValue) {
    FieldModelConfig c;
    field_param_table().read_json(json::parse(R"({"type": "field", "goal": {"center": [1, 2, 3], "radius": 0.5,
        "speed": 2, "falloff": 1}, "min_distance": 0.01, "noise": {"type": "perlin", "scale": 0.7, "seed": 18446744073709551615,
        "domain_walls": true, "bake_resolution": [8, 9, 10]}})"),
                                  "model", &c, {"type"});
    EXPECT_EQ(c.goal, (std::array<float, 3>{1, 2, 3}));
    EXPECT_EQ(c.goal_radius, 0.5f);
    EXPECT_EQ(c.goal_speed, 2.0f);
    EXPECT_EQ(c.goal_falloff, 1.0f);
    EXPECT_EQ(c.min_distance, 0.01f);
    EXPECT_EQ(c.noise.type, NoiseType::Perlin);
    EXPECT_EQ(c.noise.scale, 0.7f);
    EXPECT_EQ(c.noise.seed, 18446744073709551615ull);  // no trip through a double
    EXPECT_TRUE(c.noise.domain_walls);
    EXPECT_EQ(c.noise.bake_resolution, (std::array<uint32_t, 3>{8, 9, 10}));
    FieldModelConfig d;
    field_param_table().read_json(json::parse(R"({"noise": {"bake_resolution": 5}})"), "model", &d, {});
    EXPECT_EQ(d.noise.bake_resolution, (std::array<uint32_t, 3>{5, 5, 5}));
    EXPECT_EQ(d.noise.scale, FieldModelConfig().noise.scale);  // untouched keys keep their defaults
}

TEST(ParamTable, BadValuesNameTheKeyAndTheRange) {
    FieldModelConfig c;
    const ParamTable& t = field_param_table();
    EXPECT_EQ(read_error(t, R"({"min_distance": -0.1})", &c), "model.min_distance: expected a number >= 0");
    EXPECT_EQ(read_error(t, R"({"noise": {"scale": 0}})", &c), "model.noise.scale: expected a number > 0");
    EXPECT_EQ(read_error(t, R"({"noise": {"scale": 1e-320}})", &c), "model.noise.scale: expected a number > 0");
    EXPECT_EQ(read_error(t, R"({"noise": {"scale": "big"}})", &c), "model.noise.scale: expected a number > 0");
    EXPECT_EQ(read_error(t, R"({"noise": {"type": "pink"}})", &c),
              "model.noise.type: expected one of \"curl\", \"perlin\", \"white\", \"gaussian\"");
    EXPECT_EQ(read_error(t, R"({"noise": {"baked": 1}})", &c), "model.noise.baked: expected true or false");
    EXPECT_EQ(read_error(t, R"({"noise": {"seed": -1}})", &c),
              "model.noise.seed: expected an integer in [0, 18446744073709551615]");
    EXPECT_EQ(read_error(t, R"({"noise": {"bake_resolution": 1}})", &c),
              "model.noise.bake_resolution: expected an integer in [2, 4096] or 3 of them");
    EXPECT_EQ(read_error(t, R"({"noise": {"bake_resolution": [8, 8, 1e9]}})", &c),
              "model.noise.bake_resolution: expected an integer in [2, 4096] or 3 of them");
    EXPECT_EQ(read_error(t, R"({"goal": {"center": [1e39, 0, 0]}})", &c),
              "model.goal.center: expected an array of 3 finite numbers");
    EXPECT_EQ(read_error(t, R"({"goal": {"radius": 1}})", &c), "model.goal.center: missing");
    EXPECT_EQ(read_error(t, R"({"goal": 3})", &c), "model.goal: expected an object");
    // An unknown key lists the model's parameters.
    const std::string unknown = read_error(t, R"({"goal": {"center": [0, 0, 0], "sped": 1}})", &c);
    EXPECT_EQ(unknown.rfind("model.goal.sped: unknown key; the field model's parameters: ", 0), 0u) << unknown;
    EXPECT_NE(unknown.find("goal.speed"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("noise.scale"), std::string::npos) << unknown;
    EXPECT_EQ(unknown.find("has_goal"), std::string::npos) << "implied, not a key: " << unknown;
    EXPECT_EQ(read_error(t, R"({"has_goal": true})", &c).rfind("model.has_goal: unknown key", 0), 0u);
}

TEST(ParamTable, ValidateNamesTheFieldItsValueAndRange) {
    FieldModelConfig c;
    field_param_table().validate(&c);  // the defaults are valid
    c.goal_radius = -1.0f;
    try {
        field_param_table().validate(&c);
        FAIL() << "validated";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_STREQ(e.what(), "field model goal_radius = -1 is outside [0, inf) (m)");
    }
    c = FieldModelConfig();
    c.goal[1] = NAN;
    EXPECT_THROW(field_param_table().validate(&c), Error);
    c = FieldModelConfig();
    c.noise.type = NoiseType(7);
    try {
        field_param_table().validate(&c);
        FAIL() << "validated";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "field model noise.type = 7 is outside curl | perlin | white | gaussian");
    }
}

TEST(ParamTable, DeviceBlockIsLaidOutFromTheTable) {
    const ParamTable& t = field_param_table();
    FieldModelConfig c;
    c.has_goal = true;
    c.goal = {1, 2, 3};
    c.goal_radius = 0.25f;
    c.goal_speed = 2.5f;
    c.goal_falloff = 0.5f;
    ASSERT_EQ(t.device_floats(), 8u);  // has_goal, centre (3), radius, speed, falloff, max_speed
    std::vector<float> block(t.device_floats(), -99.0f);
    t.write_device_block(&c, block.data());
    const auto slot = [&](const char* key) { return t.find(key)->device; };
    EXPECT_EQ(block[size_t(slot("has_goal"))], 1.0f);
    EXPECT_EQ(block[size_t(slot("goal.center")) + 2], 3.0f);
    EXPECT_EQ(block[size_t(slot("goal.radius"))], 0.25f);
    EXPECT_EQ(block[size_t(slot("goal.speed"))], 2.5f);
    EXPECT_EQ(block[size_t(slot("goal.falloff"))], 0.5f);
    EXPECT_EQ(t.find("min_distance")->device, -1);  // host only
    const std::string defines = t.device_defines("FIELD");
    EXPECT_NE(defines.find("-DFIELD_GOAL_SPEED=" + std::to_string(slot("goal.speed"))), std::string::npos) << defines;
    EXPECT_NE(defines.find("-DFIELD_FLOATS=8"), std::string::npos) << defines;
}

TEST(ParamTable, DefaultsComeFromTheConfig) {
    const ParamTable& t = field_param_table();
    const FieldModelConfig c;
    EXPECT_EQ(float(t.find("goal.speed")->def[0]), c.goal_speed);
    EXPECT_EQ(float(t.find("noise.scale")->def[0]), c.noise.scale);
    EXPECT_EQ(uint32_t(t.find("noise.bake_resolution")->def[2]), c.noise.bake_resolution[2]);
}

TEST(ParamTable, EveryRowIsDocumented) {
    for (const ParamTable* t : model_param_tables())
        for (const Param& p : t->params()) {
            EXPECT_FALSE(p.doc.empty()) << t->model() << " " << p.key;
            EXPECT_FALSE(p.ref.empty()) << t->model() << " " << p.key;
            EXPECT_FALSE(p.c_field.empty()) << t->model() << " " << p.key;
            if (p.type == ParamType::Enum) EXPECT_FALSE(p.enum_names.empty()) << p.key;
            EXPECT_TRUE(p.type == ParamType::UInt64 || p.valid(p.def[0])) << t->model() << " default of " << p.key;
        }
}

TEST(ParamTable, ExportedThroughTheCApi) {
    const char* text = nullptr;
    ASSERT_EQ(swcl_model_parameters("field", &text), SWCL_OK) << swcl_last_error();
    const json rows = json::parse(text);
    ASSERT_TRUE(rows.is_array());
    ASSERT_EQ(rows.size(), field_param_table().params().size());
    bool saw = false;
    for (const json& r : rows)
        if (r["key"] == "goal.speed") {
            saw = true;
            EXPECT_EQ(r["c_field"], "goal_speed");
            EXPECT_EQ(r["default"].get<double>(), double(FieldModelConfig().goal_speed));
            EXPECT_EQ(r["min"].get<double>(), 0.0);
            EXPECT_TRUE(r["max"].is_null());
            EXPECT_EQ(r["unit"], "m/s");
            EXPECT_TRUE(r["device"].get<bool>());
        }
    EXPECT_TRUE(saw);
    const char* all = nullptr;
    ASSERT_EQ(swcl_model_parameters(nullptr, &all), SWCL_OK);
    EXPECT_TRUE(json::parse(all).contains("field"));
    ASSERT_EQ(swcl_model_parameters("noise", &text), SWCL_OK);
    EXPECT_EQ(json::parse(text)[0]["key"], "type");
    EXPECT_EQ(swcl_model_parameters("boids", &text), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("known: "), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_model_parameters("field", nullptr), SWCL_ERROR_INVALID_ARGUMENT);
}

// The force model's section reads its table's keys; the legacy noise keys
// keep their meaning, and a "noise" object starts from the noise module's
// defaults, not Table 1's (scenario/force_section.cpp).
TEST(ParamTable, ForceSectionReadsTheTableAndTheLegacyNoiseKeys) {
    const auto model_of = [](const std::string& m) {
        return std::get<ForceModelConfig>(parse_scenario(R"({"agents": {"count": 5}, "model": )" + m + "}").model);
    };
    const ForceModelConfig d = model_of(R"({"type": "force", "r_rep": 0.5, "keyframe_period": 4294967295,
        "keyframes": [{"frame": 0, "shape": "sphere"}],
        "path": {"points": [[0,0,0],[1,0,0],[2,0,0],[3,0,0]], "speed": 2, "orient": false}, "assignment": "curve"})");
    EXPECT_EQ(d.r_rep, 0.5f);
    EXPECT_EQ(d.keyframe_period, 4294967295u);
    EXPECT_EQ(d.path_speed, 2.0f);
    EXPECT_FALSE(d.path_orient);
    EXPECT_EQ(d.path.size(), 12u);
    EXPECT_EQ(d.assignment, Assignment::Curve);
    EXPECT_EQ(d.noise.scale, ForceModelConfig().noise.scale);  // Table 1's rho
    const ForceModelConfig legacy = model_of(R"({"type": "force", "rho": 0.5, "eta": 0.25, "noise_seed": 3,
        "noise_type": "perlin", "noise_time_scale": 2})");
    EXPECT_EQ(legacy.noise.scale, 0.5f);
    EXPECT_EQ(legacy.noise.gain, 0.25f / 0.5f);
    EXPECT_EQ(legacy.noise.seed, 3u);
    EXPECT_EQ(legacy.noise.type, NoiseType::Perlin);
    EXPECT_EQ(legacy.noise.time_scale, 2.0f);
    const ForceModelConfig object = model_of(R"({"type": "force", "noise": {"type": "white"}})");
    EXPECT_EQ(object.noise.scale, NoiseConfig().scale);  // the noise module's default, not rho
    EXPECT_EQ(object.noise.gain, NoiseConfig().gain);
    const auto error_of = [&](const std::string& m) {
        try {
            model_of(m);
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::Parse) << e.what();
            return std::string(e.what());
        }
        return std::string("parsed");
    };
    EXPECT_EQ(error_of(R"({"type": "force", "keyframe_period": 4294967296})"),
              "model.keyframe_period: expected an integer in [0, 4294967295]");
    EXPECT_EQ(error_of(R"({"type": "force", "path": {"speed": 1}})"), "model.path.points: missing");
    EXPECT_EQ(error_of(R"({"type": "force", "assignment": "far"})"),
              "model.assignment: expected one of \"nearest\", \"curve\"");
    const std::string unknown = error_of(R"({"type": "force", "terms": 1})");
    EXPECT_EQ(unknown.rfind("model.terms: unknown key; the force model's parameters: r_rep, ", 0), 0u) << unknown;
    EXPECT_NE(error_of(R"({"type": "force", "rho": 1, "noise": {}})").find("model.rho: give either"), std::string::npos);
    ForceModelConfig c;
    c.alpha = 1.5f;
    try {
        validate(c);
        ADD_FAILURE() << "validated";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "force model alpha = 1.5 is outside [0, 1]");
    }
    c = ForceModelConfig();
    c.noise.scale = 0.0f;  // the descriptor's rho
    EXPECT_THROW(validate(c), Error);
    c = ForceModelConfig();
    c.r_ali = 0.1f;  // below r_rep: the zones' order is checked beside the table
    EXPECT_THROW(validate(c), Error);
}

TEST(ParamTable, ForceAndPathDeviceBlocks) {
    const ParamTable& f = force_param_table();
    ForceModelConfig fc;
    fc.terms = kForceAlignment | kForceCurl;
    fc.neighbor_sample = 7;
    std::vector<float> block(f.device_floats());
    f.write_device_block(&fc, block.data());
    uint32_t bits = 0;
    std::memcpy(&bits, &block[size_t(f.find("terms")->device)], 4);
    EXPECT_EQ(bits, uint32_t(kForceAlignment | kForceCurl));  // integers bit-cast
    std::memcpy(&bits, &block[size_t(f.find("neighbor_sample")->device)], 4);
    EXPECT_EQ(bits, 7u);
    EXPECT_EQ(block[size_t(f.find("max_speed")->device)], fc.max_speed);
    EXPECT_EQ(f.find("sample_seed")->device, -1);  // 64 bits: an argument
    EXPECT_NE(f.device_defines("FORCE").find("-DFORCE_R_REP="), std::string::npos);
    const ParamTable& p = path_param_table();
    PathModelConfig pc;
    pc.lamp.enabled = true;
    pc.lamp.center = {1, 2, 3};
    block.assign(p.device_floats(), 0.0f);
    p.write_device_block(&pc, block.data());
    EXPECT_EQ(block[size_t(p.find("lamp.center")->device) + 2], 3.0f);
    EXPECT_EQ(block[size_t(p.find("lamp.enabled")->device)], 1.0f);
    EXPECT_EQ(block[size_t(p.find("speed")->device)], pc.speed);
}

// The path model's section: "grid", "cost", "lamp" and "moving_goal" are
// objects whose scalar keys are table rows; the rest is the section's.
TEST(ParamTable, PathSectionReadsTheTable) {
    const std::string head = R"({"agents": {"count": 5}, "model": {"type": "path", "goals": [{"center": [1, 1, 1]}], )";
    const auto model_of = [&](const std::string& rest) {
        return std::get<PathModelConfig>(parse_scenario(head + rest + "}}").model);
    };
    const PathModelConfig c = model_of(R"("cost": {"A": 0.7, "second_order": true}, "grid": {"resolution": [8, 9, 10],
        "min": [0, 0, 0], "max": [2, 2, 2]}, "lamp": {"center": [1, 1, 1], "angle_deg": 90}, "moving_goal":
        {"waypoints": [[1, 1, 1]], "every": 5})");
    EXPECT_EQ(c.weights.A, double(0.7f));  // read as a float, as before
    EXPECT_EQ(c.weights.B, CostWeights().B);
    EXPECT_TRUE(c.second_order);
    EXPECT_EQ(c.resolution, (std::array<uint32_t, 3>{8, 9, 10}));
    EXPECT_TRUE(c.has_grid_box);
    EXPECT_EQ(c.grid_max[2], 2.0f);
    EXPECT_TRUE(c.lamp.enabled);
    EXPECT_EQ(c.lamp.angle, float(90.0 * 3.14159265358979323846 / 180.0));
    EXPECT_EQ(c.waypoint_every, 5u);
    EXPECT_EQ(c.waypoints.size(), 1u);
    const auto error_of = [&](const std::string& rest) {
        try {
            model_of(rest);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("parsed");
    };
    EXPECT_EQ(error_of(R"("lamp": {"radius": 0.1})"), "model.lamp.center: missing");
    EXPECT_EQ(error_of(R"("lamp": {"center": [1, 1, 1], "probability": 2})"),
              "model.lamp.probability: expected a number in [0, 1]");
    EXPECT_EQ(error_of(R"("grid": {"min": [0, 0, 0]})"), "model.grid.max: missing");
    EXPECT_EQ(error_of(R"("cost": {"A": 0})"), "model.cost.A: expected a number > 0");
    EXPECT_EQ(error_of(R"("moving_goal": {"every": 2})"), "model.moving_goal.waypoints: missing");
    EXPECT_EQ(error_of(R"("lamp": {"center": [1, 1, 1], "enabled": true})").rfind("model.lamp.enabled: unknown key", 0),
              0u);
}

// A valid value of row `p` (component a) other than its default.
double other_value(const Param& p, int a) {
    const double d = p.def[a];
    switch (p.type) {
        case ParamType::Bool: return 1.0 - d;
        case ParamType::Enum: return double((int(d) + 1) % int(p.enum_names.size()));
        case ParamType::UInt32:
        case ParamType::UInt64:
        case ParamType::UInt3: return p.valid(d + 1) ? d + 1 : d - 1;
        default:
            for (double v : {d + 0.5, d * 2 + 0.25, d * 0.5, p.lo + 0.125})
                if (v != d && p.valid(v)) return v;
    }
    ADD_FAILURE() << "no other valid value for " << p.key;
    return d;
}

// The config a decoded model section holds (the energy model's is in its
// EnergySpec).
template <class Config>
Config& spec_config(ModelSpec& spec) {
    if constexpr (std::is_same_v<Config, EnergyModelConfig>) return std::get<EnergySpec>(spec).config;
    else if constexpr (std::is_same_v<Config, PolicyModelConfig>) return std::get<PolicySpec>(spec).config;
    else return std::get<Config>(spec);
}

// Every row of the table survives a checkpoint's model section (MODL): the
// checkpoint holds each parameter the table declares.  `extra`: what
// write_model_descriptor takes after the config (the energy model's dataset).
template <class Config, class... Extra>
void expect_every_row_round_trips(const ParamTable& t, const Extra&... extra) {
    Config c;
    for (const Param& p : t.params())
        for (int a = 0; a < p.components(); ++a) p.set(&c, other_value(p, a), a);
    ByteWriter w;
    write_model_descriptor(w, c, extra...);
    ByteReader r(w.data(), "test");
    CheckpointModel m = read_model_descriptor(r);
    Config& back = spec_config<Config>(m.spec);
    for (const Param& p : t.params())
        for (int a = 0; a < p.components(); ++a) {
            EXPECT_NE(p.get(&c, a), p.def[a]) << t.model() << " " << p.key << ": the test did not change it";
            EXPECT_EQ(p.get(&back, a), p.get(&c, a)) << t.model() << " " << p.key << "[" << a << "]";
        }
}

TEST(ParamTable, EveryParameterIsInTheCheckpoint) {
    expect_every_row_round_trips<FieldModelConfig>(field_param_table());
    expect_every_row_round_trips<ForceModelConfig>(force_param_table());
    expect_every_row_round_trips<PathModelConfig>(path_param_table());
    expect_every_row_round_trips<EnergyModelConfig>(energy_param_table(), synthetic_dataset(DatasetOptions{}));
    expect_every_row_round_trips<PolicyModelConfig>(policy_param_table(), std::string("weights"));
}

// The policy model's checks are the ones it shares with the RL environment
// (rl/leader_follow_params); its table states the same ranges: a value just
// outside a row's range is refused, naming the row's field, and the
// defaults pass.
TEST(PolicyParams, TheTablesRangesAreTheSharedValidations) {
    const ParamTable& t = policy_param_table();
    validate(PolicyModelConfig{});
    int checked = 0;
    for (const Param& p : t.params()) {
        if (p.type != ParamType::Float || !std::isfinite(p.lo)) continue;
        PolicyModelConfig c;
        p.set(&c, p.lo_open ? p.lo : std::nextafter(float(p.lo), -1.0f));
        try {
            validate(c);
            ADD_FAILURE() << p.key << " = just outside " << p.range_text() << " was accepted";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(p.c_field), std::string::npos) << p.key << ": " << e.what();
        }
        ++checked;
    }
    EXPECT_EQ(checked, 12);
    // Scenario keys come from the table: the leader's object included.
    const Scenario s = parse_scenario(R"({"agents": {"count": 4}, "model": {"type": "policy", "weights": "w.safetensors",
        "r_coh": 20, "u_max": 2.5, "leader": {"mode": "tour", "speed": 0.7, "reach_radius": 3,
        "waypoints": [[1, 0, 0, 1], [0, 1, 0, 1]]}}})");
    const PolicyModelConfig& c = std::get<PolicySpec>(s.model).config;
    EXPECT_EQ(c.r_coh, 20.0f);
    EXPECT_EQ(c.u_max, 2.5f);
    EXPECT_EQ(c.leader_mode, PolicyLeaderMode::Tour);
    EXPECT_EQ(c.leader_speed, 0.7f);
    EXPECT_EQ(c.reach_radius, 3.0f);
    EXPECT_EQ(c.waypoints.size(), 2u);
    try {
        parse_scenario(R"({"agents": {"count": 4}, "model": {"type": "policy", "weights": "w", "leader": {"sped": 1}}})");
        ADD_FAILURE() << "parsed";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("model.leader.sped: unknown key; the policy model's parameters: ", 0), 0u)
            << e.what();
    }
}

// The energy model's table (models/energy_params.cpp): its scenario keys read
// as the section always read them, its checks, its device block as
// energy_select reads it, and its MODL version 1 checkpoints still read.
const EnergyModelConfig& energy_config(const Scenario& s) { return std::get<EnergySpec>(s.model).config; }

std::string energy_parse_error(const std::string& model) {
    try {
        parse_scenario(R"({"agents": {"count": 10}, "model": )" + model + "}");
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Parse) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "parsed: " << model;
    return {};
}

TEST(EnergyParams, ScenarioKeysComeFromTheTable) {
    const Scenario s = parse_scenario(R"({"agents": {"count": 10}, "model": {"type": "energy",
        "weights": {"rep": 2, "n": 0.5}, "danger_weights": {"env": 3}, "rho": 2, "d_rep": 0.05, "d_att1": 0.2,
        "d_att2": 0.5, "centre": [1, 2, 3], "span": 2, "accel_time": 0.02, "danger_horizon": 0.5, "keep_out": false,
        "keypoints": [[0, 0, 0], [1, 0, 0]], "keypoints_closed": false, "bidirectional": false, "keypoint_reach": 0.1,
        "stimuli": [{"type": "startle", "position": [1, 0, 0]}], "dataset": {"type": "synthetic", "k": 50}}})");
    const EnergyModelConfig& c = energy_config(s);
    const EnergyModelConfig d;
    EXPECT_EQ(c.weights.rep, 2.0f);
    EXPECT_EQ(c.weights.n, 0.5f);
    EXPECT_EQ(c.weights.cos, d.weights.cos);  // untouched weights keep their defaults
    EXPECT_EQ(c.danger_weights.env, 3.0f);
    EXPECT_EQ(c.danger_weights.n, d.danger_weights.n);
    EXPECT_EQ(c.rho, 2.0f);
    EXPECT_EQ(c.d_rep, 0.05f);
    EXPECT_EQ(c.d_att1, 0.2f);
    EXPECT_EQ(c.d_att2, 0.5f);
    EXPECT_TRUE(c.has_fixed_centre);
    EXPECT_EQ(c.fixed_centre, (std::array<float, 3>{1, 2, 3}));
    EXPECT_EQ(c.span, 2u);
    EXPECT_EQ(c.accel_time, 0.02f);
    EXPECT_EQ(c.danger_horizon, 0.5f);
    EXPECT_FALSE(c.keep_out);
    EXPECT_FALSE(c.keypoints_closed);
    EXPECT_FALSE(c.bidirectional);
    EXPECT_EQ(c.keypoint_reach, 0.1f);
    EXPECT_EQ(c.keypoints.size(), 2u);
    EXPECT_EQ(c.stimuli.size(), 1u);
    EXPECT_EQ(std::get<EnergySpec>(s.model).dataset.k, 50u);
    // Without "centre" E_cos pulls to the mean; without "noise" the energy
    // model's own noise; a "noise" object is the whole noise (the keys it
    // leaves out take NoiseConfig's defaults, as this section always read it).
    const Scenario plain = parse_scenario(R"({"agents": {"count": 10}, "model": {"type": "energy"}})");
    EXPECT_FALSE(energy_config(plain).has_fixed_centre);
    EXPECT_EQ(energy_config(plain).noise.scale, 0.2f);
    EXPECT_EQ(energy_config(plain).noise.time_scale, 1.0f);
    EXPECT_EQ(float(energy_param_table().find("noise.scale")->def[0]), 0.2f);  // the table's default
    const Scenario noisy =
        parse_scenario(R"({"agents": {"count": 10}, "model": {"type": "energy", "noise": {"gain": 0.1}}})");
    EXPECT_EQ(energy_config(noisy).noise.gain, 0.1f);
    EXPECT_EQ(energy_config(noisy).noise.scale, NoiseConfig().scale);
    EXPECT_EQ(energy_config(noisy).noise.time_scale, NoiseConfig().time_scale);
}

TEST(EnergyParams, BadScenarioValuesNameTheKeyAndTheRange) {
    EXPECT_EQ(energy_parse_error(R"({"type": "energy", "weights": {"rep": -1}})"),
              "model.weights.rep: expected a number >= 0");
    EXPECT_EQ(energy_parse_error(R"({"type": "energy", "span": 2000})"), "model.span: expected an integer in [0, 1024]");
    EXPECT_EQ(energy_parse_error(R"({"type": "energy", "rho": 0})"), "model.rho: expected a number > 0");
    EXPECT_EQ(energy_parse_error(R"({"type": "energy", "centre": [1, 2]})"),
              "model.centre: expected an array of 3 numbers");
    EXPECT_EQ(energy_parse_error(R"({"type": "energy", "keep_out": 1})"), "model.keep_out: expected true or false");
    EXPECT_EQ(energy_parse_error(R"({"type": "energy", "noise": {"scale": -1}})"),
              "model.noise.scale: expected a number > 0");
    EXPECT_EQ(energy_parse_error(R"({"type": "energy", "d_rep": 0.5, "d_att1": 0.1})"),
              "model: energy model d_att1 must be a finite number >= d_rep");
    const std::string unknown = energy_parse_error(R"({"type": "energy", "weights": {"repulsion": 1}})");
    EXPECT_EQ(unknown.rfind("model.weights.repulsion: unknown key; the energy model's parameters: ", 0), 0u) << unknown;
    EXPECT_NE(unknown.find("danger_weights.n"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("keypoint_reach"), std::string::npos) << unknown;
    EXPECT_EQ(unknown.find("has_fixed_centre"), std::string::npos) << "implied, not a key: " << unknown;
    EXPECT_EQ(energy_parse_error(R"({"type": "energy", "has_fixed_centre": true})").rfind("model.has_fixed_centre: unknown key", 0), 0u);
}

TEST(EnergyParams, ValidateNamesTheFieldItsValueAndRange) {
    EnergyModelConfig c;
    EnergyModel::validate(c);
    c.weights.rep = -1.0f;
    try {
        EnergyModel::validate(c);
        FAIL() << "validated";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_STREQ(e.what(), "energy model weights.rep = -1 is outside [0, inf)");
    }
    c = EnergyModelConfig();
    c.span = 1025;
    try {
        EnergyModel::validate(c);
        FAIL() << "validated";
    } catch (const Error& e) {
        EXPECT_STREQ(e.what(), "energy model span = 1025 is outside [0, 1024]");
    }
    c = EnergyModelConfig();
    c.danger_weights.n = NAN;
    try {
        EnergyModel::validate(c);
        FAIL() << "validated";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("danger_weights.noise = nan"), std::string::npos) << e.what();
    }
    c = EnergyModelConfig();
    c.d_att2 = c.d_att1 / 2;  // a cross-parameter check, kept by hand
    EXPECT_THROW(EnergyModel::validate(c), Error);
}

TEST(EnergyParams, DeviceBlockIsLaidOutFromTheTable) {
    const ParamTable& t = energy_param_table();
    // Both weight sets (8 + 8), rho, d_rep, d_att1, d_att2, span,
    // danger_horizon, keypoints_closed, keypoint_reach.
    ASSERT_EQ(t.device_floats(), 24u);
    const auto slot = [&](const char* key) { return t.find(key)->device; };
    // energy_select reads each weight set as one float8.
    const char* names[8] = {"rep", "oa", "cos", "dir", "acc", "env", "n", "user"};
    for (int k = 0; k < 8; ++k) {
        EXPECT_EQ(slot(("weights." + std::string(names[k])).c_str()), slot("weights.rep") + k) << names[k];
        EXPECT_EQ(slot(("danger_weights." + std::string(names[k])).c_str()), slot("danger_weights.rep") + k);
    }
    EnergyModelConfig c;
    c.weights.user = 0.75f;
    c.danger_weights.env = 2.5f;
    c.d_att2 = 0.625f;
    c.span = 3;
    c.keypoints_closed = false;
    std::vector<float> block(t.device_floats(), -99.0f);
    t.write_device_block(&c, block.data());
    for (float v : block) EXPECT_NE(v, -99.0f);
    EXPECT_EQ(block[size_t(slot("weights.user"))], 0.75f);
    EXPECT_EQ(block[size_t(slot("danger_weights.env"))], 2.5f);
    EXPECT_EQ(block[size_t(slot("d_att2"))], 0.625f);
    uint32_t span = 0;
    std::memcpy(&span, &block[size_t(slot("span"))], 4);  // as_uint() in the kernel
    EXPECT_EQ(span, 3u);
    EXPECT_EQ(block[size_t(slot("keypoints_closed"))], 0.0f);
    EXPECT_EQ(slot("accel_time"), -1);  // derived per model (0: the dataset's frame time): an argument
    EXPECT_EQ(slot("noise.scale"), -1);
    const std::string defines = t.device_defines("ENERGY");
    EXPECT_NE(defines.find("-DENERGY_DANGER_WEIGHTS_REP=" + std::to_string(slot("danger_weights.rep"))),
              std::string::npos) << defines;
    EXPECT_NE(defines.find("-DENERGY_FLOATS=24"), std::string::npos) << defines;
}

// A MODL version 1 energy descriptor (every field in the fields() order of
// that version, then the dataset) still reads.
TEST(EnergyParams, VersionOneCheckpointsStillRead) {
    ByteWriter w;
    w.string("energy");
    const float weights[8] = {2, 1, 0.5f, 1, 1, 0, 0.25f, 0}, danger[8] = {1, 0, 0, 1, 1, 3, 0.5f, 0};
    for (float v : weights) w.f32(v);
    for (float v : danger) w.f32(v);
    w.f32(2.0f), w.f32(0.05f), w.f32(0.2f), w.f32(0.5f);  // rho, d_rep, d_att1, d_att2
    w.boolean(true), w.f32(1), w.f32(2), w.f32(3);        // has_fixed_centre, fixed_centre
    w.u32(2), w.f32(0.02f), w.boolean(true), w.f32(0.5f), w.boolean(false);  // span .. keep_out
    // noise: type, scale, gain, seed, time_scale, boundary_distance, domain_walls,
    // region_min, region_max, boundaries, baked, bake_resolution, finite_difference, fd_step
    w.u32(1), w.f32(0.3f), w.f32(0.1f), w.u64(7), w.f32(2.0f), w.f32(0.4f), w.boolean(false);
    for (int k = 0; k < 6; ++k) w.f32(0.0f);
    w.u64(0), w.boolean(false), w.u32(64), w.u32(64), w.u32(64), w.boolean(false), w.f32(0.0f);
    w.u64(1), w.u32(1), w.f32(1), w.f32(0), w.f32(0), w.f32(0.1f), w.f32(0), w.f32(0), w.f32(0.4f);  // a startle stimulus
    w.u64(2), w.f32(0), w.f32(0), w.f32(0), w.f32(1), w.f32(0), w.f32(0);  // two keypoints
    w.boolean(false), w.boolean(false), w.f32(0.1f);  // keypoints_closed, bidirectional, keypoint_reach
    w.string(dataset_to_bytes(synthetic_dataset(DatasetOptions{})));
    ByteReader r(w.data(), "test");
    const CheckpointModel m = read_model_descriptor(r, 1);
    const EnergyModelConfig& c = std::get<EnergySpec>(m.spec).config;
    EXPECT_EQ(c.weights.rep, 2.0f);
    EXPECT_EQ(c.weights.n, 0.25f);
    EXPECT_EQ(c.danger_weights.env, 3.0f);
    EXPECT_EQ(c.rho, 2.0f);
    EXPECT_EQ(c.d_att2, 0.5f);
    EXPECT_TRUE(c.has_fixed_centre);
    EXPECT_EQ(c.fixed_centre[2], 3.0f);
    EXPECT_EQ(c.span, 2u);
    EXPECT_TRUE(c.exact_attraction);
    EXPECT_FALSE(c.keep_out);
    EXPECT_EQ(c.noise.type, NoiseType::Perlin);
    EXPECT_EQ(c.noise.seed, 7u);
    ASSERT_EQ(c.stimuli.size(), 1u);
    EXPECT_EQ(c.stimuli[0].kind, Stimulus::Kind::Startle);
    EXPECT_EQ(c.stimuli[0].d_danger, 0.4f);
    ASSERT_EQ(c.keypoints.size(), 2u);
    EXPECT_FALSE(c.keypoints_closed);
    EXPECT_EQ(c.keypoint_reach, 0.1f);
    ASSERT_NE(m.dataset, nullptr);
    EXPECT_EQ(m.dataset->size(), synthetic_dataset(DatasetOptions{}).size());
}

// A checkpoint written before MODL v2 (the fuzz corpus' field model seed,
// made from examples/scenarios/aggregation.json) still loads: its fields in
// the version 1 layout, a parameter added since (max_speed) at its default.
TEST(ParamTable, AVersion1FieldCheckpointStillLoads) {
    std::ifstream in(std::string(SWARMCL_SOURCE_DIR) + "/bench/fuzz/corpus/checkpoint/aggregation", std::ios::binary);
    ASSERT_TRUE(in);
    // The fuzz seed's first byte tells the fuzz target whether to check the
    // CRC (bench/fuzz/make_seeds.cpp); the checkpoint follows.
    const std::string seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    ASSERT_GT(seed.size(), 1u);
    const std::string bytes = seed.substr(1);
    const auto sections = parse_checkpoint(bytes);
    bool v1 = false;
    for (const auto& sec : sections) v1 = v1 || (sec.tag == section_tag("MODL") && sec.version == 1);
    ASSERT_TRUE(v1) << "the seed is no longer a version 1 file";
    const SwarmCheckpoint cp = decode_swarm_checkpoint(bytes);
    const auto& c = std::get<FieldModelConfig>(cp.model.spec);
    EXPECT_EQ(c.noise.gain, 0.25f);
    EXPECT_EQ(c.noise.seed, 7u);
    EXPECT_TRUE(c.noise.domain_walls);
    EXPECT_TRUE(c.has_goal);
    EXPECT_EQ(c.goal, (std::array<float, 3>{0, 0, 2}));
    EXPECT_EQ(c.goal_falloff, 1.0f);
    EXPECT_EQ(c.min_distance, 0.03f);
    EXPECT_EQ(c.max_speed, 0.0f);
}

// docs/scenarios.md holds each table between markers; the test fails when
// they drift.  SWARMCL_WRITE_PARAM_DOCS=1 rewrites them instead.
TEST(ParamDocs, ScenariosMdHoldsTheGeneratedTables) {
    const std::string path = std::string(SWARMCL_SOURCE_DIR) + "/docs/scenarios.md";
    std::ifstream in(path);
    ASSERT_TRUE(in) << path;
    std::stringstream ss;
    ss << in.rdbuf();
    std::string doc = ss.str();
    const char* write = std::getenv("SWARMCL_WRITE_PARAM_DOCS");
    std::vector<const ParamTable*> tables = model_param_tables();
    for (const ParamTable* t : tables) {
        const std::string begin = "<!-- parameters:" + t->model() + " (generated from the table; tests/test_params.cpp) -->\n";
        const std::string end = "<!-- end parameters:" + t->model() + " -->";
        const size_t b = doc.find(begin), e = doc.find(end);
        ASSERT_NE(b, std::string::npos) << "docs/scenarios.md has no " << begin;
        ASSERT_NE(e, std::string::npos) << "docs/scenarios.md has no " << end;
        const std::string have = doc.substr(b + begin.size(), e - b - begin.size());
        const std::string want = t->to_markdown();
        if (write && std::string(write) == "1") doc.replace(b + begin.size(), have.size(), want);
        else EXPECT_EQ(have, want) << t->model() << "'s table in docs/scenarios.md drifted: rerun with SWARMCL_WRITE_PARAM_DOCS=1";
    }
    if (write && std::string(write) == "1") std::ofstream(path) << doc;
}

}  // namespace
