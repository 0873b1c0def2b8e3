// Scenario files: the example files parse to what they say, every kind of bad
// input gets a Parse error naming the line and column or the key path, the
// parser survives random and mutated input, initial placement is where the
// file says and deterministic; and the same through the C API
// (swcl_scenario_*, swcl_recorder_*).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "io/recorder.hpp"
#include "models/model_spec.hpp"
#include "scenario/scenario.hpp"
#include "io_test_support.hpp"
#include "swarmcl/swarmcl.h"

namespace {

using namespace swarmcl;
using namespace swarmcl::iotest;

const std::string kExamples = std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios";

std::vector<std::string> example_files() {
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(kExamples))
        if (e.path().extension() == ".json") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    return files;
}

// The Parse error of `text`; fails the test if it parses or throws anything else.
std::string parse_error(const std::string& text) {
    try {
        parse_scenario(text);
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Parse) << e.what();
        return e.what();
    } catch (const std::exception& e) {
        ADD_FAILURE() << "non-swarmcl exception: " << e.what() << "\nfor: " << text;
        return {};
    }
    ADD_FAILURE() << "parsed: " << text;
    return {};
}

// The error must start with "<path>: ".
#define EXPECT_PATH_ERROR(text, path)                                                              \
    do {                                                                                           \
        const std::string msg_ = parse_error(text);                                                \
        EXPECT_EQ(msg_.rfind(std::string(path) + ": ", 0), 0u) << "expected '" << (path)           \
                                                              << ": ...', got '" << msg_ << "'"; \
    } while (0)

// A small valid scenario with `extra` spliced into the top-level object and
// `agents` / `model` replaceable.
std::string scenario(const std::string& extra = "", const std::string& agents = R"({"count": 10})",
                     const std::string& model = R"({"type": "field", "noise": {"scale": 0.5}})") {
    return R"({"name": "t", "seed": 5, "dt": 0.02, "steps": 10,
  "domain": {"min": [0, 0, 0], "max": [4, 2, 1]},
  "agents": )" + agents + R"(,
  "model": )" + model + (extra.empty() ? "" : ",\n  " + extra) + "\n}";
}

// ---- the example files ------------------------------------------------------

TEST(Scenario, EveryExampleFileParses) {
    const auto files = example_files();
    ASSERT_GE(files.size(), 2u);
    for (const auto& f : files) {
        SCOPED_TRACE(f);
        Scenario s;
        ASSERT_NO_THROW(s = load_scenario(f));
        EXPECT_GT(s.swarm.agent_count, 0u);
        EXPECT_GE(s.swarm.capacity, s.swarm.agent_count);
        EXPECT_EQ(s.initial_positions().size(), 3u * s.swarm.agent_count);
        EXPECT_EQ(s.source, read_bytes(f));
        EXPECT_EQ(s.name, fs::path(f).stem().string()) << "the example's name matches its file";
    }
}

TEST(Scenario, AggregationFieldsLandWhereExpected) {
    const Scenario s = load_scenario(kExamples + "/aggregation.json");
    EXPECT_EQ(s.name, "aggregation");
    EXPECT_EQ(s.swarm.seed, 2024u);
    EXPECT_EQ(s.swarm.dt, 0.0333333f);
    EXPECT_EQ(s.steps, 300u);
    EXPECT_EQ(s.swarm.domain_min, (std::array<float, 3>{-1.5f, -1.5f, 0.5f}));
    EXPECT_EQ(s.swarm.domain_max, (std::array<float, 3>{1.5f, 1.5f, 3.5f}));
    EXPECT_EQ(s.swarm.interaction_radius, 0.1f);
    EXPECT_EQ(s.swarm.agent_count, 1000u);
    EXPECT_EQ(s.swarm.capacity, 1000u);
    EXPECT_EQ(s.initial.kind, InitialDistribution::Kind::Uniform);
    EXPECT_EQ(s.initial.min, s.swarm.domain_min);  // uniform defaults to the domain
    EXPECT_EQ(s.initial.max, s.swarm.domain_max);
    EXPECT_EQ(s.initial.velocity, (std::array<float, 3>{0, 0, 0}));
    ASSERT_TRUE(std::holds_alternative<FieldModelConfig>(s.model));
    const FieldModelConfig& m = std::get<FieldModelConfig>(s.model);
    EXPECT_EQ(m.noise.type, NoiseType::Curl);
    EXPECT_EQ(m.noise.scale, 0.4f);
    EXPECT_EQ(m.noise.gain, 0.25f);
    EXPECT_EQ(m.noise.seed, 7u);
    EXPECT_EQ(m.noise.time_scale, 2.0f);
    EXPECT_TRUE(m.noise.domain_walls);
    EXPECT_FALSE(m.noise.baked);
    EXPECT_TRUE(m.noise.boundaries.empty());
    EXPECT_TRUE(m.has_goal);
    EXPECT_EQ(m.goal, (std::array<float, 3>{0.0f, 0.0f, 2.0f}));
    EXPECT_EQ(m.goal_radius, 1.2f);
    EXPECT_EQ(m.goal_speed, 1.5f);
    EXPECT_EQ(m.goal_falloff, 1.0f);
    EXPECT_EQ(m.min_distance, 0.03f);
    EXPECT_EQ(s.output_dir, "out/aggregation");
    EXPECT_EQ(s.output_formats, uint32_t(kExportCsv | kExportNpy | kExportVtp));
    EXPECT_EQ(s.output_every, 10u);
}

TEST(Scenario, ChasingHasItsObstacleAndSphere) {
    const Scenario s = load_scenario(kExamples + "/chasing.json");
    EXPECT_EQ(s.initial.kind, InitialDistribution::Kind::Sphere);
    EXPECT_EQ(s.initial.center, (std::array<float, 3>{2, 2, 2}));
    EXPECT_EQ(s.initial.radius, 0.8f);
    ASSERT_TRUE(std::holds_alternative<FieldModelConfig>(s.model));
    ASSERT_EQ(std::get<FieldModelConfig>(s.model).noise.boundaries.size(), 1u);
    const Boundary& b = std::get<FieldModelConfig>(s.model).noise.boundaries[0];
    EXPECT_EQ(b.kind, Boundary::Kind::Sphere);
    EXPECT_EQ(b.center, (std::array<float, 3>{4, 2, 6}));
    EXPECT_EQ(b.radius, 0.7f);
}

TEST(Scenario, Defaults) {
    const Scenario s = parse_scenario(R"({"agents": {"count": 3}})");
    EXPECT_EQ(s.name, "scenario");
    EXPECT_EQ(s.swarm.seed, 0u);
    EXPECT_EQ(s.swarm.dt, 1.0f / 60.0f);
    EXPECT_EQ(s.steps, 100u);
    EXPECT_EQ(s.swarm.domain_min, (std::array<float, 3>{-1, -1, -1}));
    EXPECT_EQ(s.swarm.domain_max, (std::array<float, 3>{1, 1, 1}));
    EXPECT_EQ(s.swarm.agent_count, 3u);
    EXPECT_FALSE(std::holds_alternative<FieldModelConfig>(s.model)) << "no model key: ballistic";
    EXPECT_EQ(s.output_dir, "out");
    EXPECT_EQ(s.output_formats, uint32_t(kExportCsv));
    EXPECT_EQ(s.output_every, 1u);
    // "model": {} is the field model with its defaults.
    const Scenario f = parse_scenario(R"({"agents": {"count": 3}, "model": {}})");
    ASSERT_TRUE(std::holds_alternative<FieldModelConfig>(f.model));
    EXPECT_EQ(std::get<FieldModelConfig>(f.model).noise.scale, NoiseConfig{}.scale);
}

TEST(Scenario, ObstaclesOfEveryKind) {
    const Scenario s = parse_scenario(scenario(R"("obstacles": [
      {"type": "sphere", "center": [1, 1, 0.5], "radius": 0.2},
      {"type": "box", "center": [2, 1, 0.5], "half_extents": [0.1, 0.2, 0.3], "edge_radius": 0.05},
      {"type": "plane", "normal": [0, 0, 1], "offset": 0.1}])"));
    ASSERT_TRUE(std::holds_alternative<FieldModelConfig>(s.model));
    const auto& b = std::get<FieldModelConfig>(s.model).noise.boundaries;
    ASSERT_EQ(b.size(), 3u);
    EXPECT_EQ(b[0].kind, Boundary::Kind::Sphere);
    EXPECT_EQ(b[0].radius, 0.2f);
    EXPECT_EQ(b[1].kind, Boundary::Kind::Box);
    EXPECT_EQ(b[1].half_extents, (std::array<float, 3>{0.1f, 0.2f, 0.3f}));
    EXPECT_EQ(b[1].radius, 0.05f);
    EXPECT_EQ(b[2].kind, Boundary::Kind::Plane);
    EXPECT_EQ(b[2].normal, (std::array<float, 3>{0, 0, 1}));
    EXPECT_EQ(b[2].offset, 0.1f);
}

// ---- malformed JSON -----------------------------------------------------------

TEST(ScenarioErrors, MalformedJsonNamesLineAndColumn) {
    // A stray character: column of that character (1-based).
    std::string msg = parse_error("{\n  \"name\": \"x\",\n  \"seed\": @\n}");
    EXPECT_EQ(msg.rfind("malformed JSON at line 3, column 11", 0), 0u) << msg;
    // A doubled comma on line 3.
    msg = parse_error("{\n  \"name\": \"x\",\n  \"seed\": 1,,\n}");
    EXPECT_EQ(msg.rfind("malformed JSON at line 3, column 13", 0), 0u) << msg;
    // Line 1.
    msg = parse_error("{\"agents\" {\"count\": 1}}");
    EXPECT_EQ(msg.rfind("malformed JSON at line 1, column 11", 0), 0u) << msg;
    // A missing closing brace: the error is at the end of the input.
    msg = parse_error("{\n  \"agents\": {\"count\": 1}\n");
    EXPECT_NE(msg.find("malformed JSON at line 3"), std::string::npos) << msg;
    // Empty input and whitespace only.
    msg = parse_error("");
    EXPECT_EQ(msg.rfind("malformed JSON at line 1, column 1", 0), 0u) << msg;
    msg = parse_error("\n\n   ");
    EXPECT_EQ(msg.rfind("malformed JSON at line 3", 0), 0u) << msg;
    // Trailing garbage after a valid document.
    msg = parse_error("{\"agents\": {\"count\": 1}}\nx");
    EXPECT_EQ(msg.rfind("malformed JSON at line 2, column 1", 0), 0u) << msg;
    // NaN and comments are not JSON.
    EXPECT_EQ(parse_error("{\"agents\": {\"count\": 1}, \"dt\": NaN}").rfind("malformed JSON at line 1, column 32", 0), 0u);
    EXPECT_EQ(parse_error("// c\n{\"agents\": {\"count\": 1}}").rfind("malformed JSON at line 1, column 1", 0), 0u);
}

TEST(ScenarioErrors, LoadNamesTheFile) {
    TempDir dir;
    write_text(dir / "bad.json", "{\n\n  ]");
    try {
        load_scenario(dir / "bad.json");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Parse);
        const std::string msg = e.what();
        EXPECT_NE(msg.find(dir / "bad.json"), std::string::npos) << msg;
        EXPECT_NE(msg.find("line 3, column 3"), std::string::npos) << msg;
    }
    try {
        load_scenario(dir / "missing.json");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Io);
        EXPECT_NE(std::string(e.what()).find(dir / "missing.json"), std::string::npos) << e.what();
    }
    try {
        load_scenario(dir.path());  // a folder
        FAIL();
    } catch (const Error& e) {
        EXPECT_TRUE(e.status() == Status::Io || e.status() == Status::Parse) << e.what();
    }
}

// ---- bad values ------------------------------------------------------------------

TEST(ScenarioErrors, UnknownKeysAnywhere) {
    ASSERT_NO_THROW(parse_scenario(scenario()));
    EXPECT_PATH_ERROR(scenario(R"("nmae": "typo")"), "nmae");
    std::string msg = parse_error(scenario(R"("nmae": "typo")"));
    EXPECT_NE(msg.find("unknown key"), std::string::npos) << msg;
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"noise": {"scael": 0.5}})"), "model.noise.scael");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"goal": {"center": [1,1,1], "sped": 1}})"), "model.goal.sped");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"min_distanse": 0.1})"), "model.min_distanse");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": [{"type": "sphere", "center": [1,1,1], "radius": 0.1},
                                                {"type": "sphere", "center": [1,1,1], "raduis": 0.1}])"),
                      "obstacles[1].raduis");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "cuont": 3})"), "agents.cuont");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "initial": {"type": "uniform", "radius": 1}})"), "agents.initial.radius");
    EXPECT_PATH_ERROR(scenario(R"("domain2": {})"), "domain2");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": {"min": [0,0,0], "max": [1,1,1], "mid": 1}})", "domain.mid");
    EXPECT_PATH_ERROR(scenario(R"("output": {"dir": "o", "evry": 2})"), "output.evry");
    // A ballistic model has no parameters.
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"type": "ballistic", "noise": {}})"), "model.noise");
}

TEST(ScenarioErrors, WrongTypesAndRanges) {
    const auto with_noise = [](const std::string& noise) {
        return scenario("", R"({"count": 10})", R"({"noise": )" + noise + "}");
    };
    for (const char* bad : {"0", "-0.5", "\"big\"", "null", "[0.4]", "1e39"}) {
        SCOPED_TRACE(bad);
        const std::string msg = parse_error(with_noise(std::string(R"({"scale": )") + bad + "}"));
        EXPECT_EQ(msg.rfind("model.noise.scale: expected a number > 0", 0), 0u) << msg;
    }
    EXPECT_PATH_ERROR(with_noise(R"({"type": "pink"})"), "model.noise.type");
    EXPECT_PATH_ERROR(with_noise(R"({"gain": -1})"), "model.noise.gain");
    EXPECT_PATH_ERROR(with_noise(R"({"seed": -1})"), "model.noise.seed");
    EXPECT_PATH_ERROR(with_noise(R"({"domain_walls": 1})"), "model.noise.domain_walls");
    EXPECT_PATH_ERROR(with_noise(R"({"bake_resolution": 1})"), "model.noise.bake_resolution");
    EXPECT_PATH_ERROR(with_noise(R"({"bake_resolution": [8, 8, 8.5]})"), "model.noise.bake_resolution");
    EXPECT_PATH_ERROR(with_noise(R"({"bake_resolution": [8, 8]})"), "model.noise.bake_resolution");
    // The noise model's own combination rules, under the noise's path.
    EXPECT_PATH_ERROR(with_noise(R"({"type": "white", "baked": true})"), "model.noise");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"type": "swarmy"})"), "model.type");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"goal": {"radius": 1}})"), "model.goal.center");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"min_distance": -0.1})"), "model.min_distance");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"([1, 2])"), "model");

    for (const char* bad : {"-5", "1.5", "\"10\"", "true", "4294967295", "99999999999", "1e3"}) {
        SCOPED_TRACE(bad);
        EXPECT_PATH_ERROR(scenario("", std::string(R"({"count": )") + bad + "}"), "agents.count");
    }
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "capacity": 5})"), "agents.capacity");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 0, "capacity": 0})"), "agents.capacity");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "velocity": [1, 2]})"), "agents.velocity");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "velocity": [1, 2, "3"]})"), "agents.velocity");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "initial": {"type": "cube"}})"), "agents.initial.type");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "initial": {"type": "uniform", "min": [3, 0, 0], "max": [1, 1, 1]}})"),
                      "agents.initial.min");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "initial": {"type": "sphere", "center": [1, 1, 1]}})"),
                      "agents.initial.radius");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "initial": {"type": "sphere", "center": [1, 1, 1], "radius": -1}})"),
                      "agents.initial.radius");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10, "initial": "uniform"})"), "agents.initial");

    EXPECT_PATH_ERROR(scenario(R"("output": {"formats": ["csv", "gif"]})"), "output.formats[1]");
    EXPECT_PATH_ERROR(scenario(R"("output": {"formats": ["csv", 2]})"), "output.formats[1]");
    EXPECT_PATH_ERROR(scenario(R"("output": {"formats": ["csv,npy", "npy"]})"), "output.formats[0]");
    EXPECT_PATH_ERROR(scenario(R"("output": {"formats": "csv"})"), "output.formats");
    // No format at all passes nothing a run could write.
    EXPECT_PATH_ERROR(scenario(R"("output": {"formats": []})"), "output.formats");
    EXPECT_PATH_ERROR(scenario(R"("output": {"formats": [""]})"), "output.formats[0]");
    EXPECT_PATH_ERROR(scenario(R"("output": {"every": 0})"), "output.every");
    EXPECT_PATH_ERROR(scenario(R"("output": {"dir": ""})"), "output.dir");

    for (const char* bad : {"0", "-0.1", "\"x\"", "1e39", "null", "1e-320"}) {
        SCOPED_TRACE(bad);
        const std::string extra = std::string(R"("interaction_radius": )") + bad;
        const std::string text = R"({"agents": {"count": 1}, "dt": )" + std::string(bad) + "}";
        EXPECT_PATH_ERROR(text, "dt");
        EXPECT_PATH_ERROR(scenario(extra), "interaction_radius");
    }
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "steps": -1})", "steps");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "steps": 2.5})", "steps");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "steps": 1e20})", "steps");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "steps": 18446744073709551615})", "steps");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "seed": -1})", "seed");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "seed": 1e30})", "seed");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "seed": 18446744073709551616})", "seed");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "name": 3})", "name");

    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": {"min": [1, 0, 0], "max": [1, 1, 1]}})", "domain.min");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": {"min": [0, 0], "max": [1, 1, 1]}})", "domain.min");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": {"min": [0, 0, "0"], "max": [1, 1, 1]}})", "domain.min");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": {"max": [1, 1, 1]}})", "domain.min");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": {"min": [0, 0, 0]}})", "domain.max");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": [0, 1]})", "domain");
}

TEST(ScenarioErrors, HugeNumbersDoNotBecomeInfinity) {
    // Finite in JSON (a double) but beyond float: must be rejected, not
    // silently turned into inf.
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": {"min": [-1e39, 0, 0], "max": [1, 1, 1]}})", "domain.min");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "domain": {"min": [0, 0, 0], "max": [1, 1, 1e300]}})", "domain.max");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1, "velocity": [3e38, 3e38, 1e39]}})", "agents.velocity");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "dt": 3.5e38})", "dt");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"noise": {"boundary_distance": 1e39}})"),
                      "model.noise.boundary_distance");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 10})", R"({"goal": {"center": [1e39, 0, 0]}})"), "model.goal.center");
    // Numbers beyond double (JSON text "1e400"): a Parse error naming the number.
    for (const char* text : {R"({"agents": {"count": 1}, "domain": {"min": [-1e400, 0, 0], "max": [1, 1, 1]}})",
                             R"({"agents": {"count": 1}, "x": 1e400})", "1e400", "[-1e400]"}) {
        const std::string msg = parse_error(text);
        EXPECT_NE(msg.find("1e400"), std::string::npos) << text << " -> " << msg;
    }
    // The largest float is fine.
    EXPECT_NO_THROW(parse_scenario(R"({"agents": {"count": 1}, "domain": {"min": [-3.4e38, 0, 0], "max": [1, 1, 1]}})"));
}

TEST(ScenarioErrors, RequiredPiecesAndCombinations) {
    EXPECT_PATH_ERROR(R"({"name": "x"})", "agents");
    EXPECT_NE(parse_error(R"({"name": "x"})").find("missing"), std::string::npos);
    EXPECT_PATH_ERROR(R"({"agents": {}})", "agents.count");
    EXPECT_PATH_ERROR(R"({"agents": [10]})", "agents");
    EXPECT_PATH_ERROR(R"([{"agents": {"count": 1}}])", "(top level)");
    EXPECT_PATH_ERROR(R"("just a string")", "(top level)");
    // points: one per agent.
    EXPECT_PATH_ERROR(scenario("", R"({"count": 3, "initial": {"type": "points", "positions": [[0,0,0], [1,1,1]]}})"),
                      "agents.initial.positions");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 1, "initial": {"type": "points", "positions": [[0,0,0], [1,1,1]]}})"),
                      "agents.initial.positions");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 2, "initial": {"type": "points", "positions": [[0,0,0], [1,1]]}})"),
                      "agents.initial.positions[1]");
    EXPECT_PATH_ERROR(scenario("", R"({"count": 2, "initial": {"type": "points"}})"), "agents.initial.positions");
    // Obstacles need a field model.
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "obstacles": [{"type": "sphere", "center": [0,0,0], "radius": 0.1}]})",
                      "obstacles");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": [{"type": "sphere", "center": [0,0,0], "radius": 0.1}])", R"({"count": 1})",
                               R"({"type": "ballistic"})"),
                      "obstacles");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": {"type": "sphere"})"), "obstacles");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": [{"type": "sphere", "center": [0,0,0]}])"), "obstacles[0].radius");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": [{"center": [0,0,0], "radius": 1}])"), "obstacles[0].type");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": [{"type": "torus"}])"), "obstacles[0].type");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": [{"type": "box", "center": [0,0,0], "half_extents": [1, 0, 1]}])"),
                      "obstacles[0].half_extents");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": [{"type": "plane", "normal": [0, 0, 0]}])"), "obstacles[0].normal");
    EXPECT_PATH_ERROR(scenario(R"("obstacles": [{"type": "sphere", "center": [0,0,0], "radius": 1}, 3])"), "obstacles[1]");
}

TEST(ScenarioErrors, NameMustBeUsableAsAFileName) {
    // The name names the output files: a name the recorder refuses must be
    // caught when the scenario is validated, not after the simulation ran.
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "name": ""})", "name");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "name": "../escape"})", "name");
    EXPECT_PATH_ERROR(R"({"agents": {"count": 1}, "name": "a/b"})", "name");
}

TEST(ScenarioErrors, DeepNestingIsAnErrorNotACrash) {
    const std::string deep = R"({"agents": {"count": 1}, "x": )" + std::string(100000, '[') + std::string(100000, ']') + "}";
    EXPECT_PATH_ERROR(deep, "x");
    const std::string open = std::string(200000, '[');
    const std::string msg = parse_error(open);
    EXPECT_EQ(msg.rfind("malformed JSON", 0), 0u) << msg.substr(0, 200);
}

// ---- initial placement ---------------------------------------------------------------

TEST(ScenarioInitial, UniformBoxIsInsideAndFillsIt) {
    const Scenario s = parse_scenario(scenario(
        "", R"({"count": 4000, "initial": {"type": "uniform", "min": [1, 0.5, 0.2], "max": [3, 1.5, 0.4]}})"));
    const auto p = s.initial_positions();
    ASSERT_EQ(p.size(), 3u * 4000u);
    const float lo[3] = {1, 0.5f, 0.2f}, hi[3] = {3, 1.5f, 0.4f};
    double mean[3] = {0, 0, 0};
    int below_mid[3] = {0, 0, 0};
    for (size_t i = 0; i < 4000; ++i)
        for (int a = 0; a < 3; ++a) {
            const float x = p[3 * i + a];
            ASSERT_TRUE(x >= lo[a] && x <= hi[a]) << "agent " << i << " axis " << a << ": " << x;
            mean[a] += x / 4000.0;
            below_mid[a] += x < 0.5f * (lo[a] + hi[a]);
        }
    for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(mean[a], 0.5 * (lo[a] + hi[a]), 0.03 * (hi[a] - lo[a])) << a;
        EXPECT_NEAR(below_mid[a], 2000, 150) << a;
    }
}

TEST(ScenarioInitial, UniformDefaultsToTheDomain) {
    const Scenario s = parse_scenario(scenario("", R"({"count": 2000})"));  // domain [0,4]x[0,2]x[0,1]
    const auto p = s.initial_positions();
    const float hi[3] = {4, 2, 1};
    float maxv[3] = {0, 0, 0};
    for (size_t i = 0; i < 2000; ++i)
        for (int a = 0; a < 3; ++a) {
            ASSERT_TRUE(p[3 * i + a] >= 0.0f && p[3 * i + a] <= hi[a]);
            maxv[a] = std::max(maxv[a], p[3 * i + a]);
        }
    for (int a = 0; a < 3; ++a) EXPECT_GT(maxv[a], 0.95f * hi[a]) << "spans axis " << a;
}

TEST(ScenarioInitial, SphereIsAUniformBall) {
    const Scenario s = parse_scenario(
        scenario("", R"({"count": 8000, "initial": {"type": "sphere", "center": [2, 1, 0.5], "radius": 0.4}})"));
    const auto p = s.initial_positions();
    ASSERT_EQ(p.size(), 3u * 8000u);
    int inner = 0;
    double mean[3] = {0, 0, 0};
    for (size_t i = 0; i < 8000; ++i) {
        const double dx = p[3 * i] - 2.0, dy = p[3 * i + 1] - 1.0, dz = p[3 * i + 2] - 0.5;
        const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
        ASSERT_LE(r, 0.4 * (1 + 1e-5)) << "agent " << i;
        inner += r < 0.2;
        mean[0] += dx / 8000, mean[1] += dy / 8000, mean[2] += dz / 8000;
    }
    // Uniform in volume: (1/2)^3 of the agents inside half the radius.
    EXPECT_NEAR(inner / 8000.0, 0.125, 0.02);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(mean[a], 0.0, 0.02) << a;
}

TEST(ScenarioInitial, PointsAreTakenAsGiven) {
    const Scenario s = parse_scenario(scenario(
        "", R"({"count": 3, "velocity": [0.5, -1, 2], "initial": {"type": "points", "positions": [[0.1, 0.2, 0.3], [3.9, 1.9, 0.9], [2, 1, 0.5]]}})"));
    EXPECT_EQ(s.initial_positions(), (std::vector<float>{0.1f, 0.2f, 0.3f, 3.9f, 1.9f, 0.9f, 2, 1, 0.5f}));
    EXPECT_EQ(s.initial.velocity, (std::array<float, 3>{0.5f, -1, 2}));
    // Zero agents with an empty list is fine.
    const Scenario e = parse_scenario(scenario("", R"({"count": 0, "initial": {"type": "points", "positions": []}})"));
    EXPECT_TRUE(e.initial_positions().empty());
}

TEST(ScenarioInitial, DeterministicForTheSeedAndIndependentOfTheCount) {
    for (const char* init : {R"({"type": "uniform"})", R"({"type": "sphere", "center": [1, 1, 0.5], "radius": 0.5})"}) {
        SCOPED_TRACE(init);
        const auto text = [&](int seed, int count) {
            return R"({"seed": )" + std::to_string(seed) + R"(, "agents": {"count": )" + std::to_string(count) +
                   R"(, "initial": )" + init + "}}";
        };
        const auto a = parse_scenario(text(5, 100)).initial_positions();
        const auto b = parse_scenario(text(5, 100)).initial_positions();
        ASSERT_EQ(a.size(), 300u);
        EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
        const auto c = parse_scenario(text(6, 100)).initial_positions();
        size_t same = 0;
        for (size_t i = 0; i < a.size(); ++i) same += a[i] == c[i];
        EXPECT_LT(same, 10u) << "another seed, other positions";
        // Keyed by (seed, agent id): the first 50 agents of 100 are the 50 agents of 50.
        const auto d = parse_scenario(text(5, 50)).initial_positions();
        EXPECT_EQ(std::memcmp(a.data(), d.data(), d.size() * sizeof(float)), 0);
        // Distinct agents are at distinct places.
        std::vector<std::array<float, 3>> pts;
        for (size_t i = 0; i < 100; ++i) pts.push_back({a[3 * i], a[3 * i + 1], a[3 * i + 2]});
        std::sort(pts.begin(), pts.end());
        EXPECT_EQ(std::unique(pts.begin(), pts.end()), pts.end());
    }
}

// ---- fuzzing ---------------------------------------------------------------------------

// Parses `text`; anything but success or swarmcl::Error fails the test.
// Returns true when it parsed.
bool survives(const std::string& text, int* errors_of_other_type) {
    try {
        const Scenario s = parse_scenario(text);
        // What a successful parse promises.
        EXPECT_TRUE(std::isfinite(s.swarm.dt) && s.swarm.dt > 0) << text;
        EXPECT_TRUE(std::isfinite(s.swarm.interaction_radius) && s.swarm.interaction_radius > 0) << text;
        for (int a = 0; a < 3; ++a) {
            EXPECT_TRUE(std::isfinite(s.swarm.domain_min[a]) && std::isfinite(s.swarm.domain_max[a])) << text;
            EXPECT_LT(s.swarm.domain_min[a], s.swarm.domain_max[a]) << text;
            EXPECT_TRUE(std::isfinite(s.initial.velocity[a])) << text;
        }
        EXPECT_LE(s.swarm.agent_count, s.swarm.capacity) << text;
        EXPECT_GE(s.output_every, 1u);
        if (s.swarm.agent_count <= 100000) {
            const auto p = s.initial_positions();
            EXPECT_EQ(p.size(), 3u * s.swarm.agent_count);
            for (float x : p)
                if (!std::isfinite(x)) {
                    ADD_FAILURE() << "non-finite initial position for: " << text;
                    break;
                }
        }
        return true;
    } catch (const Error& e) {
        if (e.status() != Status::Parse) {
            ++*errors_of_other_type;
            ADD_FAILURE() << "status " << int(e.status()) << ": " << e.what() << "\nfor: " << text;
        }
        return false;
    } catch (const std::exception& e) {
        ++*errors_of_other_type;
        ADD_FAILURE() << "non-swarmcl exception " << e.what() << "\nfor: " << text;
        return false;
    } catch (...) {
        ++*errors_of_other_type;
        ADD_FAILURE() << "unknown exception for: " << text;
        return false;
    }
}

TEST(ScenarioFuzz, RandomBytes) {
    std::mt19937 rng(20240601);
    int others = 0;
    const std::string alphabet = "{}[]\":,.-+eE0123456789 \n\ttruefalsnl\\u";
    for (int it = 0; it < 3000 && others < 5; ++it) {
        std::string s(rng() % 200, '\0');
        if (it % 2) {
            for (auto& c : s) c = char(rng() & 0xFF);  // any byte
        } else {
            for (auto& c : s) c = alphabet[rng() % alphabet.size()];  // JSON-ish bytes
        }
        survives(s, &others);
    }
    EXPECT_EQ(others, 0);
}

TEST(ScenarioFuzz, MutatedExamples) {
    std::vector<std::string> seeds;
    for (const auto& f : example_files()) seeds.push_back(read_bytes(f));
    seeds.push_back(scenario(R"("obstacles": [{"type": "box", "center": [1,1,0.5], "half_extents": [0.1,0.1,0.1]},
        {"type": "plane", "normal": [0,0,1], "offset": 0.1}], "output": {"dir": "o", "formats": ["npy"], "every": 3})",
                             R"({"count": 3, "capacity": 8, "velocity": [1,0,0], "initial": {"type": "points", "positions": [[1,1,0.5],[2,1,0.5],[3,1,0.5]]}})",
                             R"({"noise": {"type": "perlin", "baked": true, "bake_resolution": [8, 9, 10]}, "goal": {"center": [1,1,1]}})"));
    ASSERT_GE(seeds.size(), 3u);
    // Replacements that stress the values rather than the syntax.
    const std::vector<std::string> tokens = {"-1", "0", "-0", "1e309", "-1e309", "1e39", "-3.5e38", "4294967296",
                                             "18446744073709551616", "1e-320", "0.5", "true", "null", "\"x\"",
                                             "[]", "{}", "[1,2,3]", "[0,0,0]", "\"\"", "1.5", "99999999999"};
    std::mt19937 rng(77);
    int others = 0, parsed = 0, total = 0;
    for (const auto& seed : seeds) {
        for (int it = 0; it < 2500 && others < 5; ++it) {
            std::string s = seed;
            const int mutations = 1 + int(rng() % 3);
            for (int m = 0; m < mutations && !s.empty(); ++m) {
                const size_t at = rng() % s.size();
                switch (rng() % 7) {
                    case 0: s[at] = char(rng() & 0xFF); break;               // byte
                    case 1: s[at] = char(s[at] ^ (1 << (rng() % 8))); break; // bit
                    case 2: s.resize(at); break;                             // truncation
                    case 3: {                                                // duplication
                        const size_t len = 1 + rng() % std::min<size_t>(64, s.size() - at);
                        s.insert(rng() % (s.size() + 1), s.substr(at, len));
                        break;
                    }
                    case 4: s.erase(at, 1 + rng() % 16); break;  // deletion
                    default: {                                   // a number replaced by a nasty value
                        size_t b = s.find_first_of("-0123456789", at);
                        if (b == std::string::npos) b = s.find_first_of("-0123456789");
                        if (b == std::string::npos) break;
                        size_t e = s.find_first_not_of("-+.eE0123456789", b);
                        if (e == std::string::npos) e = s.size();
                        s.replace(b, e - b, tokens[rng() % tokens.size()]);
                    }
                }
            }
            parsed += survives(s, &others);
            ++total;
        }
    }
    EXPECT_EQ(others, 0);
    // Some mutations keep the file valid (e.g. a changed digit), most do not:
    // both paths were exercised.
    EXPECT_GT(parsed, total / 50) << parsed << " of " << total;
    EXPECT_LT(parsed, total) << parsed << " of " << total;
}

// ---- the C API -------------------------------------------------------------------------

class ScenarioCApi : public ::testing::Test {
protected:
    void SetUp() override {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override { swcl_context_destroy(ctx); }

    swcl_scenario parse_ok(const std::string& text) {
        swcl_scenario s{};
        EXPECT_EQ(swcl_scenario_parse(text.data(), text.size(), &s), SWCL_OK) << swcl_last_error();
        return s;
    }
    static std::vector<float> read(swcl_swarm sw, swcl_attribute attr) {
        uint32_t n = 0;
        EXPECT_EQ(swcl_swarm_agent_count(sw, &n), SWCL_OK);
        std::vector<float> v(3 * size_t(n));
        EXPECT_EQ(swcl_swarm_read(sw, attr, v.data(), n), SWCL_OK) << swcl_last_error();
        return v;
    }

    swcl_context ctx{};
};

TEST_F(ScenarioCApi, LoadErrors) {
    TempDir dir;
    swcl_scenario s{};
    EXPECT_EQ(swcl_scenario_load((dir / "missing.json").c_str(), &s), SWCL_ERROR_IO);
    EXPECT_NE(std::string(swcl_last_error()).find("missing.json"), std::string::npos) << swcl_last_error();

    write_text(dir / "bad.json", "{\n  \"agents\": {\"count\": 1},\n  \"dt\": 0.1 \"steps\": 3\n}");
    EXPECT_EQ(swcl_scenario_load((dir / "bad.json").c_str(), &s), SWCL_ERROR_PARSE);
    std::string err = swcl_last_error();
    EXPECT_AT_TOKEN(err, 3, 13, 19);  // the string "steps" where a ',' or '}' belongs
    EXPECT_NE(err.find("bad.json"), std::string::npos) << err;

    write_text(dir / "value.json", R"({"agents": {"count": 1}, "model": {"noise": {"scale": 0}}})");
    EXPECT_EQ(swcl_scenario_load((dir / "value.json").c_str(), &s), SWCL_ERROR_PARSE);
    err = swcl_last_error();
    EXPECT_NE(err.find("model.noise.scale: expected a number > 0"), std::string::npos) << err;

    const std::string text = "{\"agents\": {\"count\": }}";
    EXPECT_EQ(swcl_scenario_parse(text.data(), text.size(), &s), SWCL_ERROR_PARSE);
    EXPECT_NE(std::string(swcl_last_error()).find("line 1, column 22"), std::string::npos) << swcl_last_error();

    EXPECT_EQ(swcl_scenario_load(nullptr, &s), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_scenario_load((dir / "value.json").c_str(), nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_scenario_parse(nullptr, 5, &s), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_scenario_parse(nullptr, 0, &s), SWCL_ERROR_PARSE);  // empty text is malformed JSON
    // `length` is honoured: trailing bytes beyond it are not read.
    const std::string padded = R"({"agents": {"count": 2}}garbage)";
    ASSERT_EQ(swcl_scenario_parse(padded.data(), padded.size() - 7, &s), SWCL_OK) << swcl_last_error();
    swcl_scenario_destroy(s);
}

TEST_F(ScenarioCApi, Info) {
    const swcl_scenario s = parse_ok(scenario(R"("output": {"dir": "results/x", "formats": ["npy", "vtp"], "every": 4})"));
    swcl_scenario_info info;
    std::memset(&info, 0xAB, sizeof info);
    info.struct_size = sizeof(info);
    ASSERT_EQ(swcl_scenario_get_info(s, &info), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(info.struct_size, sizeof(info));
    EXPECT_EQ(info.agents, 10u);
    EXPECT_EQ(info.steps, 10u);
    EXPECT_EQ(info.output_every, 4u);
    EXPECT_EQ(info.output_formats, uint32_t(SWCL_EXPORT_NPY | SWCL_EXPORT_VTP));
    EXPECT_EQ(info.dt, 0.02f);
    EXPECT_EQ(info.seed, 5u);
    EXPECT_STREQ(info.name, "t");
    EXPECT_STREQ(info.output_dir, "results/x");
    EXPECT_STREQ(info.model, "field");
    swcl_scenario_destroy(s);

    const swcl_scenario b = parse_ok(R"({"name": "plain", "agents": {"count": 2}, "model": {"type": "ballistic"}})");
    ASSERT_EQ(swcl_scenario_get_info(b, &info), SWCL_OK);
    EXPECT_STREQ(info.model, "ballistic");
    EXPECT_STREQ(info.output_dir, "out");
    // The struct size is checked.
    swcl_scenario_info small;
    small.struct_size = 8;
    EXPECT_EQ(swcl_scenario_get_info(b, &small), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_scenario_get_info(b, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    swcl_scenario_destroy(b);
}

TEST_F(ScenarioCApi, CreateSwarmPlacesTheAgentsAsTheScenarioSays) {
    const std::string text = scenario("", R"({"count": 300, "capacity": 400, "velocity": [0.25, -0.5, 1],
        "initial": {"type": "sphere", "center": [2, 1, 0.5], "radius": 0.3}})");
    const Scenario cpp = parse_scenario(text);
    const swcl_scenario s = parse_ok(text);
    swcl_swarm a{}, b{};
    ASSERT_EQ(swcl_scenario_create_swarm(s, ctx, &a), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_scenario_create_swarm(s, ctx, &b), SWCL_OK) << swcl_last_error();
    uint32_t n = 0;
    ASSERT_EQ(swcl_swarm_agent_count(a, &n), SWCL_OK);
    EXPECT_EQ(n, 300u);
    const auto pa = read(a, SWCL_ATTRIBUTE_POSITION), pb = read(b, SWCL_ATTRIBUTE_POSITION);
    const auto expected = cpp.initial_positions();
    ASSERT_EQ(pa.size(), expected.size());
    EXPECT_EQ(std::memcmp(pa.data(), expected.data(), pa.size() * sizeof(float)), 0);
    EXPECT_EQ(std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(float)), 0);
    const auto va = read(a, SWCL_ATTRIBUTE_VELOCITY);
    for (size_t i = 0; i < 300; ++i) {
        EXPECT_EQ(va[3 * i], 0.25f);
        EXPECT_EQ(va[3 * i + 1], -0.5f);
        EXPECT_EQ(va[3 * i + 2], 1.0f);
    }
    // Two swarms of one scenario step to bitwise the same state.
    ASSERT_EQ(swcl_swarm_step(a, 3), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(b, 3), SWCL_OK) << swcl_last_error();
    const auto qa = read(a, SWCL_ATTRIBUTE_POSITION), qb = read(b, SWCL_ATTRIBUTE_POSITION);
    EXPECT_EQ(std::memcmp(qa.data(), qb.data(), qa.size() * sizeof(float)), 0);
    EXPECT_NE(std::memcmp(qa.data(), pa.data(), qa.size() * sizeof(float)), 0) << "the swarm moved";
    swcl_swarm_destroy(a);
    swcl_swarm_destroy(b);
    swcl_scenario_destroy(s);
}

// A scenario as worlds each in a domain of its own: world k is the scenario
// alone with that domain (placed in it, walls its own); bad domains and the
// path model's one domain are refused, naming them, with nothing created.
TEST_F(ScenarioCApi, WorldSwarmInDomainsIsEachScenarioAloneInItsDomain) {
    const std::string base = R"({"seed": 3, "dt": 0.02, "steps": 5, "agents": {"count": 40},
        "model": {"type": "field", "noise": {"scale": 0.4, "domain_walls": true}},
        "domain": {"min": [0, 0, 0], "max": [DX, 1, 1]}})";
    auto with = [&](const std::string& dx) {
        std::string t = base;
        t.replace(t.find("DX"), 2, dx);
        return t;
    };
    swcl_scenario s = parse_ok(with("1"));
    const float domains[12] = {0, 0, 0, 1, 1, 1, 0, 0, 0, 2.5f, 1, 1};
    const uint64_t seeds[2] = {3, 3};
    swcl_swarm all{};
    ASSERT_EQ(swcl_scenario_create_world_swarm_in_domains(s, ctx, 2, seeds, domains, &all), SWCL_OK)
        << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(all, 5), SWCL_OK) << swcl_last_error();
    std::vector<float> both(2 * 40 * 3);
    ASSERT_EQ(swcl_swarm_read(all, SWCL_ATTRIBUTE_POSITION, both.data(), 80), SWCL_OK) << swcl_last_error();
    for (int k = 0; k < 2; ++k) {
        swcl_scenario one = parse_ok(with(k == 0 ? "1" : "2.5"));
        swcl_swarm alone{};
        ASSERT_EQ(swcl_scenario_create_swarm(one, ctx, &alone), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(swcl_swarm_step(alone, 5), SWCL_OK) << swcl_last_error();
        const std::vector<float> mine = read(alone, SWCL_ATTRIBUTE_POSITION);
        EXPECT_EQ(std::vector<float>(both.begin() + k * 120, both.begin() + (k + 1) * 120), mine) << "world " << k;
        swcl_swarm_destroy(alone);
        swcl_scenario_destroy(one);
    }
    float x_max = 0.0f;
    for (size_t i = 120; i < both.size(); i += 3) x_max = std::max(x_max, both[i]);
    EXPECT_GT(x_max, 1.0f);  // world 1 placed in its wider box
    // Bad input: a domain with max below min (world 1, axis 0), no output.
    float bad[12];
    std::copy(domains, domains + 12, bad);
    bad[9] = -1.0f;
    swcl_swarm out{12345};
    EXPECT_EQ(swcl_scenario_create_world_swarm_in_domains(s, ctx, 2, seeds, bad, &out), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("world 1 domain min[0]"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(out.id, 12345u);
    EXPECT_EQ(swcl_scenario_create_world_swarm_in_domains(s, ctx, 0, seeds, domains, &out),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_scenario_create_world_swarm_in_domains(s, ctx, 2, seeds, domains, nullptr),
              SWCL_ERROR_INVALID_ARGUMENT);
    // A uniform box given only its max: its min is each world's domain's,
    // here above that max in world 1.
    swcl_scenario boxed = parse_ok(R"({"agents": {"count": 4, "initial": {"type": "uniform", "max": [0.8, 1, 1]}},
        "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}})");
    float shifted[12];
    std::copy(domains, domains + 12, shifted);
    shifted[6] = 0.9f;
    EXPECT_EQ(swcl_scenario_create_world_swarm_in_domains(boxed, ctx, 2, nullptr, shifted, &out),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("world 1: agents.initial.min[0]"), std::string::npos)
        << swcl_last_error();
    EXPECT_EQ(out.id, 12345u);
    swcl_scenario_destroy(boxed);
    swcl_swarm_destroy(all);
    swcl_scenario_destroy(s);
}

TEST_F(ScenarioCApi, CreateSwarmFromPointsAndFromExamples) {
    const swcl_scenario s = parse_ok(scenario(
        "", R"({"count": 2, "initial": {"type": "points", "positions": [[1, 1.5, 0.25], [3, 0.5, 0.75]]}})"));
    swcl_swarm sw{};
    ASSERT_EQ(swcl_scenario_create_swarm(s, ctx, &sw), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(read(sw, SWCL_ATTRIBUTE_POSITION), (std::vector<float>{1, 1.5f, 0.25f, 3, 0.5f, 0.75f}));
    swcl_swarm_destroy(sw);
    swcl_scenario_destroy(s);
    for (const auto& f : example_files()) {
        SCOPED_TRACE(f);
        swcl_scenario e{};
        ASSERT_EQ(swcl_scenario_load(f.c_str(), &e), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(swcl_scenario_create_swarm(e, ctx, &sw), SWCL_OK) << swcl_last_error();
        uint32_t n = 0;
        swcl_swarm_agent_count(sw, &n);
        EXPECT_EQ(n, load_scenario(f).swarm.agent_count);
        swcl_swarm_destroy(sw);
        swcl_scenario_destroy(e);
    }
}

TEST_F(ScenarioCApi, DestroyedAndForeignHandles) {
    const swcl_scenario s = parse_ok(scenario());
    swcl_swarm sw{};
    ASSERT_EQ(swcl_scenario_create_swarm(s, ctx, &sw), SWCL_OK);
    TempDir dir;
    swcl_recorder rec{};
    ASSERT_EQ(swcl_recorder_create(dir.path().c_str(), "r", SWCL_EXPORT_CSV, &rec), SWCL_OK) << swcl_last_error();

    // Foreign: a recorder's id where a scenario is expected and vice versa, and zero.
    swcl_scenario as_scenario{rec.id};
    swcl_recorder as_recorder{s.id};
    swcl_scenario_info info;
    info.struct_size = sizeof(info);
    EXPECT_EQ(swcl_scenario_get_info(as_scenario, &info), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_recorder_finish(as_recorder), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_scenario_get_info(swcl_scenario{0}, &info), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_recorder_add_frame(rec, swcl_swarm{s.id}, 0, 0.0), SWCL_ERROR_INVALID_HANDLE);

    EXPECT_EQ(swcl_scenario_destroy(s), SWCL_OK);
    EXPECT_EQ(swcl_scenario_destroy(s), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_scenario_get_info(s, &info), SWCL_ERROR_INVALID_HANDLE);
    swcl_swarm other{};
    EXPECT_EQ(swcl_scenario_create_swarm(s, ctx, &other), SWCL_ERROR_INVALID_HANDLE);

    EXPECT_EQ(swcl_recorder_destroy(rec), SWCL_OK);
    EXPECT_EQ(swcl_recorder_destroy(rec), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_recorder_add_frame(rec, sw, 0, 0.0), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_recorder_finish(rec), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_TRUE(list_dir(dir.path()).empty()) << "destroyed unfinished: nothing left";

    // A destroyed swarm or context.
    const swcl_scenario s2 = parse_ok(scenario());
    ASSERT_EQ(swcl_recorder_create(dir.path().c_str(), "r", SWCL_EXPORT_CSV, &rec), SWCL_OK);
    swcl_swarm_destroy(sw);
    EXPECT_EQ(swcl_recorder_add_frame(rec, sw, 0, 0.0), SWCL_ERROR_INVALID_HANDLE);
    swcl_context dead{};
    swcl_context_desc d = swcl_context_desc_default();
    ASSERT_EQ(swcl_context_create(&d, &dead), SWCL_OK);
    swcl_context_destroy(dead);
    EXPECT_EQ(swcl_scenario_create_swarm(s2, dead, &other), SWCL_ERROR_INVALID_HANDLE);
    swcl_recorder_destroy(rec);
    swcl_scenario_destroy(s2);
}

TEST_F(ScenarioCApi, RecorderWritesWhatTheSwarmHolds) {
    TempDir dir;
    const swcl_scenario s = parse_ok(scenario("", R"({"count": 25})"));
    swcl_swarm sw{};
    ASSERT_EQ(swcl_scenario_create_swarm(s, ctx, &sw), SWCL_OK) << swcl_last_error();
    swcl_recorder rec{};
    ASSERT_EQ(swcl_recorder_create((dir / "sub").c_str(), "capi", SWCL_EXPORT_CSV | SWCL_EXPORT_NPY | SWCL_EXPORT_VTP,
                                   &rec),
              SWCL_OK)
        << swcl_last_error();
    std::vector<std::vector<float>> pos, vel;
    for (uint32_t k = 0; k < 3; ++k) {
        if (k) ASSERT_EQ(swcl_swarm_step(sw, 2), SWCL_OK);
        pos.push_back(read(sw, SWCL_ATTRIBUTE_POSITION));
        vel.push_back(read(sw, SWCL_ATTRIBUTE_VELOCITY));
        ASSERT_EQ(swcl_recorder_add_frame(rec, sw, 2 * k, 2 * k * 0.02), SWCL_OK) << swcl_last_error();
    }
    ASSERT_EQ(swcl_recorder_finish(rec), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(swcl_recorder_finish(rec), SWCL_ERROR_INVALID_ARGUMENT) << "finish twice";
    EXPECT_EQ(swcl_recorder_destroy(rec), SWCL_OK);
    EXPECT_EQ(list_dir(dir / "sub"),
              (std::set<std::string>{"capi.csv", "capi_positions.npy", "capi_velocities.npy", "capi_000000.vtp",
                                     "capi_000002.vtp", "capi_000004.vtp", "capi.pvd"}));
    const auto rows = parse_trajectory_csv(read_bytes(dir / "sub/capi.csv"));
    ASSERT_EQ(rows.size(), 75u);
    for (size_t r = 0; r < rows.size(); ++r) {
        const size_t k = r / 25, i = r % 25;
        EXPECT_EQ(rows[r].frame, 2 * k);
        EXPECT_EQ(rows[r].id, i);
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(rows[r].p[a], pos[k][3 * i + a]);
            EXPECT_EQ(rows[r].v[a], vel[k][3 * i + a]);
        }
    }
    const Npy npy = read_npy(dir / "sub/capi_velocities.npy");
    EXPECT_EQ(npy.shape, (std::vector<uint64_t>{3, 25, 3}));
    ASSERT_EQ(npy.data.size(), 3u * 25u * 12u);
    EXPECT_EQ(std::memcmp(npy.data.data() + 2 * 25 * 12, vel[2].data(), 25 * 12), 0);
    const auto pvd = read_pvd(dir / "sub/capi.pvd");
    ASSERT_EQ(pvd.size(), 3u);
    EXPECT_EQ(pvd[2].first, "capi_000004.vtp");
    EXPECT_NEAR(pvd[2].second, 0.08, 1e-9);
    swcl_swarm_destroy(sw);
    swcl_scenario_destroy(s);
}

TEST_F(ScenarioCApi, RecorderBadArguments) {
    TempDir dir;
    swcl_recorder rec{};
    EXPECT_EQ(swcl_recorder_create(dir.path().c_str(), "x", 0, &rec), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_recorder_create(dir.path().c_str(), "x", 8, &rec), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_recorder_create(nullptr, "x", SWCL_EXPORT_CSV, &rec), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_recorder_create("", "x", SWCL_EXPORT_CSV, &rec), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_recorder_create(dir.path().c_str(), nullptr, SWCL_EXPORT_CSV, &rec), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_recorder_create(dir.path().c_str(), "a/b", SWCL_EXPORT_CSV, &rec), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_recorder_create(dir.path().c_str(), "x", SWCL_EXPORT_CSV, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    write_text(dir / "file", "x");
    EXPECT_EQ(swcl_recorder_create((dir / "file/sub").c_str(), "x", SWCL_EXPORT_CSV, &rec), SWCL_ERROR_IO);
    EXPECT_NE(std::string(swcl_last_error()).find("file/sub"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(list_dir(dir.path()), std::set<std::string>{"file"});
}

TEST_F(ScenarioCApi, RecorderRejectsAChangedAgentCountForNpyAndStaysUsable) {
    TempDir dir;
    swcl_swarm_desc d = swcl_swarm_desc_default();
    d.capacity = 16;
    d.agent_count = 4;
    swcl_swarm sw{};
    ASSERT_EQ(swcl_swarm_create(ctx, &d, &sw), SWCL_OK) << swcl_last_error();
    swcl_recorder rec{};
    ASSERT_EQ(swcl_recorder_create(dir.path().c_str(), "n", SWCL_EXPORT_NPY, &rec), SWCL_OK);
    ASSERT_EQ(swcl_recorder_add_frame(rec, sw, 0, 0.0), SWCL_OK) << swcl_last_error();
    std::vector<float> six(18, 0.0f);
    ASSERT_EQ(swcl_swarm_write(sw, SWCL_ATTRIBUTE_POSITION, six.data(), 6), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(swcl_recorder_add_frame(rec, sw, 1, 0.1), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find(".npy"), std::string::npos) << swcl_last_error();
    ASSERT_EQ(swcl_recorder_finish(rec), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(read_npy(dir / "n_positions.npy").shape, (std::vector<uint64_t>{1, 4, 3}));
    swcl_recorder_destroy(rec);
    swcl_swarm_destroy(sw);
}

}  // namespace

// The force model's noise term may be any noise type (the noise paper's
// study of noise functions, docs/evaluation.md): read, validated, used.
TEST(ScenarioForceNoise, NoiseTypeIsReadAndChangesTheRunDeterministically) {
    auto text = [](const char* type, const char* extra = "") {
        return std::string(R"({"name": "fn", "seed": 3, "dt": 0.02, "steps": 10, "interaction_radius": 0.5,
            "domain": {"min": [-3, -3, -3], "max": [3, 3, 3]},
            "agents": {"count": 40, "initial": {"type": "uniform", "min": [-1, -1, -1], "max": [1, 1, 1]}},
            "model": {"type": "force", "r_rep": 0.1, "r_ali": 0.5, "r_att": 2, "eta": 0.3, "rho": 0.5,
                      "noise_type": ")") + type + "\"" + extra + "}}";
    };
    const Scenario white = parse_scenario(text("white"));
    ASSERT_TRUE(std::holds_alternative<ForceModelConfig>(white.model));
    EXPECT_EQ(std::get<ForceModelConfig>(white.model).noise.type, NoiseType::White);
    EXPECT_EQ(std::get<ForceModelConfig>(parse_scenario(text("curl")).model).noise.type, NoiseType::Curl);
    EXPECT_EQ(std::get<ForceModelConfig>(parse_scenario(text("curl", R"(, "noise_time_scale": 2)")).model)
                  .noise.time_scale, 2.0f);
    try {
        parse_scenario(text("pink"));
        FAIL() << "pink noise accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("model.noise_type"), std::string::npos) << e.what();
    }
    auto run = [&](const char* type) {
        const std::string t = text(type);
        swcl_scenario scn{};
        EXPECT_EQ(swcl_scenario_parse(t.c_str(), t.size(), &scn), SWCL_OK) << swcl_last_error();
        swcl_context_desc cd = swcl_context_desc_default();
        swcl_context ctx{};
        EXPECT_EQ(swcl_context_create(&cd, &ctx), SWCL_OK);
        swcl_swarm s{};
        EXPECT_EQ(swcl_scenario_create_swarm(scn, ctx, &s), SWCL_OK) << swcl_last_error();
        EXPECT_EQ(swcl_swarm_step(s, 10), SWCL_OK) << swcl_last_error();
        std::vector<float> p(3 * 40);
        EXPECT_EQ(swcl_swarm_read(s, SWCL_ATTRIBUTE_POSITION, p.data(), 40), SWCL_OK);
        swcl_swarm_destroy(s);
        swcl_context_destroy(ctx);
        swcl_scenario_destroy(scn);
        for (float x : p) EXPECT_TRUE(std::isfinite(x));
        return p;
    };
    const auto w1 = run("white"), w2 = run("white"), g = run("gaussian"), c = run("curl"), pe = run("perlin");
    EXPECT_EQ(w1, w2);
    EXPECT_NE(w1, g);
    EXPECT_NE(w1, c);
    EXPECT_NE(c, pe);
}
