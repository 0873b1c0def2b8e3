// The one seam between scenarios and models (docs/architecture.md, "How to add
// a model"): make_swarm gives the swarm the per-model construction gave, bit
// for bit; the model's name and MDE distance come from its spec; the section
// table knows every model once and refuses other types with the old message;
// obstacle and keyframe meshes are the same from the C API and from scenario
// files (shapes/obstacle_spec, shapes/keyframe_spec).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../capi/src/capi_common.hpp"
#include "../capi/src/capi_obstacle.hpp"
#include "core/error.hpp"
#include "models/model_spec.hpp"
#include "scenario/make_swarm.hpp"
#include "scenario/model_section.hpp"
#include "scenario/scenario.hpp"
#include "shapes/keyframe_spec.hpp"
#include "shapes/obstacle_spec.hpp"
#include "shapes/shape_library.hpp"
#include "swarmcl/swarmcl.h"
#include "test_support.hpp"

namespace {

using namespace swarmcl;
namespace fs = std::filesystem;

const std::string kExamples = std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios";

std::vector<std::string> example_files() {
    std::vector<std::string> files;
    for (const auto& e : fs::directory_iterator(kExamples))
        if (e.path().extension() == ".json") files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    return files;
}

// swcl_scenario_create_swarm as it was before make_swarm (issue 18): one
// branch per model.
std::shared_ptr<Swarm> old_construction(std::shared_ptr<Context> ctx, const Scenario& s) {
    SwarmConfig config = s.swarm;
    config.agent_count = 0;
    auto swarm = std::make_shared<Swarm>(ctx, config);
    const auto pos = s.initial_positions();
    const uint32_t n = s.swarm.agent_count;
    swarm->write(Attribute::Position, pos.data(), n);
    std::vector<float> vel(size_t(n) * 3);
    for (size_t i = 0; i < vel.size(); ++i) vel[i] = s.initial.velocity[i % 3];
    swarm->write(Attribute::Velocity, vel.data(), n);
    if (auto* c = std::get_if<FieldModelConfig>(&s.model)) swarm->set_behavior(std::make_shared<FieldModel>(*swarm, *c));
    if (auto* c = std::get_if<PathModelConfig>(&s.model)) swarm->set_behavior(std::make_shared<PathModel>(*swarm, *c));
    if (auto* e = std::get_if<EnergySpec>(&s.model))
        swarm->set_behavior(std::make_shared<EnergyModel>(*swarm, e->config, energy_spec_dataset(*e)));
    if (auto* c = std::get_if<ForceModelConfig>(&s.model)) swarm->set_behavior(std::make_shared<ForceModel>(*swarm, *c));
    // The policy model came after make_swarm: built here directly.
    if (auto* p = std::get_if<PolicySpec>(&s.model))
        swarm->set_behavior(std::make_shared<PolicyModel>(
            *swarm, p->config, std::make_shared<const std::string>(read_policy_file(p->weights_path))));
    return swarm;
}

std::vector<float> read_all(Swarm& s, Attribute a) {
    std::vector<float> v(size_t(s.agent_count()) * 3);
    s.read(a, v.data(), s.agent_count());
    return v;
}

// ---- make_swarm ---------------------------------------------------------------

TEST(MakeSwarm, EveryExampleRunsBitForBitAsThePerModelConstruction) {
    auto ctx = test::shared_context();
    const auto files = example_files();
    ASSERT_GE(files.size(), 20u);
    for (const std::string& f : files) {
        SCOPED_TRACE(f);
        Scenario s = load_scenario(f);
        // The force model's big swarms, smaller (the same for both).
        if (std::holds_alternative<ForceModelConfig>(s.model) && s.swarm.agent_count > 500)
            s.swarm.agent_count = s.swarm.capacity = 500;
        auto a = make_swarm(ctx, s);
        auto b = old_construction(ctx, s);
        ASSERT_EQ(a->agent_count(), s.swarm.agent_count);
        EXPECT_EQ(a->behavior() == nullptr, std::holds_alternative<Ballistic>(s.model));
        a->step(4);
        b->step(4);
        const auto pa = read_all(*a, Attribute::Position), pb = read_all(*b, Attribute::Position);
        const auto va = read_all(*a, Attribute::Velocity), vb = read_all(*b, Attribute::Velocity);
        ASSERT_EQ(pa.size(), pb.size());
        EXPECT_EQ(std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(float)), 0) << "positions differ";
        EXPECT_EQ(std::memcmp(va.data(), vb.data(), va.size() * sizeof(float)), 0) << "velocities differ";
    }
}

TEST(MakeSwarm, BallisticPlacesAndMovesTheAgentsWithoutABehavior) {
    const Scenario s = parse_scenario(R"({"agents": {"count": 3, "velocity": [1, 0, 0],
        "initial": {"type": "points", "positions": [[1, 1, 1], [2, 1, 1], [3, 1, 1]]}},
        "domain": {"min": [0, 0, 0], "max": [10, 10, 10]}, "model": {"type": "ballistic"}})");
    auto swarm = make_swarm(test::shared_context(), s);
    EXPECT_EQ(swarm->behavior(), nullptr);
    EXPECT_EQ(read_all(*swarm, Attribute::Position), (std::vector<float>{1, 1, 1, 2, 1, 1, 3, 1, 1}));
    EXPECT_EQ(read_all(*swarm, Attribute::Velocity), (std::vector<float>{1, 0, 0, 1, 0, 0, 1, 0, 0}));
}

// ---- ModelSpec ----------------------------------------------------------------

TEST(ModelSpec, NameAndMinDistanceComeFromTheSpec) {
    FieldModelConfig field;
    field.min_distance = 0.25f;
    PathModelConfig path;
    path.min_distance = 0.5f;
    ForceModelConfig force;
    force.min_distance = 0.75f;
    EXPECT_STREQ(model_name(Ballistic{}), "ballistic");
    EXPECT_STREQ(model_name(field), "field");
    EXPECT_STREQ(model_name(path), "path");
    EXPECT_STREQ(model_name(force), "force");
    EXPECT_STREQ(model_name(EnergySpec{}), "energy");
    EXPECT_EQ(model_min_distance(Ballistic{}), 0.0f);
    EXPECT_EQ(model_min_distance(field), 0.25f);
    EXPECT_EQ(model_min_distance(path), 0.5f);
    EXPECT_EQ(model_min_distance(force), 0.75f);
    EXPECT_EQ(model_min_distance(EnergySpec{}), 0.0f);
}

TEST(ModelSpec, ScenarioInfoNamesEveryExamplesModelAndDistance) {
    for (const std::string& f : example_files()) {
        SCOPED_TRACE(f);
        std::ifstream in(f);
        const nlohmann::json j = nlohmann::json::parse(in);
        const std::string type = j.contains("model") ? j["model"].value("type", "field") : "ballistic";
        const float d = j.contains("model") ? j["model"].value("min_distance", 0.0f) : 0.0f;
        swcl_scenario sc{};
        ASSERT_EQ(swcl_scenario_load(f.c_str(), &sc), SWCL_OK) << swcl_last_error();
        swcl_scenario_info info{};
        info.struct_size = sizeof(info);
        ASSERT_EQ(swcl_scenario_get_info(sc, &info), SWCL_OK) << swcl_last_error();
        EXPECT_EQ(std::string(info.model), type);
        EXPECT_EQ(info.min_distance, type == "energy" ? 0.0f : d);
        swcl_scenario_destroy(sc);
    }
}

TEST(ModelSpec, MakeBehaviorBuildsTheSpecsModel) {
    const std::string head = R"({"agents": {"count": 20}, "domain": {"min": [0, 0, 0], "max": [4, 4, 4]}, "model": )";
    auto swarm_for = [&](const std::string& model) {
        const Scenario s = parse_scenario(head + model + "}");
        auto swarm = std::make_shared<Swarm>(test::shared_context(), s.swarm);
        return std::make_pair(swarm, make_behavior(*swarm, s.model));
    };
    EXPECT_EQ(swarm_for(R"({"type": "ballistic"})").second, nullptr);
    EXPECT_NE(dynamic_cast<FieldModel*>(swarm_for(R"({"type": "field"})").second.get()), nullptr);
    EXPECT_NE(dynamic_cast<PathModel*>(swarm_for(R"({"type": "path", "grid": {"resolution": [8, 8, 8]},
        "goals": [{"type": "point", "center": [2, 2, 2]}]})").second.get()), nullptr);
    EXPECT_NE(dynamic_cast<ForceModel*>(swarm_for(R"({"type": "force"})").second.get()), nullptr);
    EXPECT_NE(dynamic_cast<EnergyModel*>(
                  swarm_for(R"({"type": "energy", "dataset": {"type": "synthetic", "k": 20, "groups": 2}})").second.get()),
              nullptr);
}

// ---- the section table --------------------------------------------------------

TEST(ModelSections, OneSectionPerModelSpecAlternative) {
    const auto& table = model_sections();
    std::vector<std::string> types;
    for (const ModelSection& s : table) types.push_back(s.type);
    EXPECT_EQ(types, (std::vector<std::string>{"field", "path", "force", "energy", "policy", "ballistic"}));
    EXPECT_EQ(table.size(), std::variant_size_v<ModelSpec>);
    for (const ModelSection& s : table) EXPECT_EQ(find_model_section(s.type), &s);
    EXPECT_EQ(find_model_section("swarmy"), nullptr);
    // Each section reads its own alternative.
    const std::string head = R"({"agents": {"count": 5}, "model": )";
    const std::vector<std::pair<std::string, std::string>> models{
        {"field", R"({})"},
        {"path", R"({"type": "path", "goals": [{"center": [1, 1, 1]}]})"},
        {"force", R"({"type": "force"})"},
        {"energy", R"({"type": "energy"})"},
        {"policy", R"({"type": "policy", "weights": "w.safetensors"})"},
        {"ballistic", R"({"type": "ballistic"})"},
    };
    for (const auto& [name, model] : models) EXPECT_STREQ(model_name(parse_scenario(head + model + "}").model), name.c_str());
    EXPECT_TRUE(std::holds_alternative<Ballistic>(parse_scenario(R"({"agents": {"count": 5}})").model));
}

std::string error_of(const std::string& text) {
    try {
        parse_scenario(text);
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Parse);
        return e.what();
    }
    ADD_FAILURE() << "parsed: " << text;
    return {};
}

TEST(ModelSections, UnknownTypesGetTheSameMessagesAsBefore) {
    const std::string head = R"({"agents": {"count": 5}, "model": )";
    EXPECT_EQ(error_of(head + R"({"type": "swarmy"}})"),
              R"(model.type: expected "field", "path", "force", "energy", "policy" or "ballistic")");
    EXPECT_EQ(error_of(head + R"({"type": 3}})"), "model.type: expected a string");
    EXPECT_EQ(error_of(head + R"([1, 2]})"), "model: expected an object");
    // Obstacles are read before the model's type, as they were.
    EXPECT_EQ(error_of(R"({"agents": {"count": 5}, "obstacles": [{"type": "torus"}], "model": {"type": "swarmy"}})"),
              R"(obstacles[0].type: expected "sphere", "box" or "plane" (mesh obstacles come with the path-field model))");
    EXPECT_EQ(error_of(R"({"agents": {"count": 5}, "obstacles": [{"type": "sphere", "center": [0,0,0], "radius": 1}]})"),
              R"(obstacles: obstacles need a model ("model": {"type": "field"}))");
    EXPECT_EQ(error_of(head + R"({"type": "ballistic", "noise": {}}})"), "model.noise: unknown key");
    // The domain check runs after the whole file (unknown top-level keys first).
    const std::string white_baked = head + R"({"noise": {"type": "white", "baked": true}})";
    EXPECT_EQ(error_of(white_baked + "}").rfind("model.noise: ", 0), 0u);
    EXPECT_EQ(error_of(white_baked + R"(, "x": 1})"), "x: unknown key");
}

// ---- obstacle and keyframe specs ----------------------------------------------

void expect_same_mesh(const TriangleMesh& a, const TriangleMesh& b) {
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.triangles.size(), b.triangles.size());
    EXPECT_EQ(std::memcmp(a.vertices.data(), b.vertices.data(), a.vertices.size() * sizeof(a.vertices[0])), 0);
    EXPECT_EQ(a.triangles, b.triangles);
}

const char* kBoxObj =
    "v -0.3 -0.6 -0.6\nv 0.3 -0.6 -0.6\nv 0.3 0.6 -0.6\nv -0.3 0.6 -0.6\n"
    "v -0.3 -0.6 0.6\nv 0.3 -0.6 0.6\nv 0.3 0.6 0.6\nv -0.3 0.6 0.6\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

TEST(ObstacleSpec, CApiAndScenarioObstaclesAreTheSameMeshes) {
    const std::string obj = ::testing::TempDir() + "swarmcl_seam_box.obj";
    std::ofstream(obj, std::ios::binary) << kBoxObj;
    const Scenario s = parse_scenario(R"({"agents": {"count": 5}, "domain": {"min": [0, 0, 0], "max": [4, 4, 4]},
        "obstacles": [{"type": "box", "center": [1, 1.5, 2], "half_extents": [0.5, 0.25, 0.75]},
                      {"type": "sphere", "center": [2, 2, 1], "radius": 0.4},
                      {"type": "cylinder", "base": [3, 1, 0], "radius": 0.3, "height": 1.5},
                      {"type": "mesh", "file": ")" + obj + R"("}],
        "model": {"type": "path", "goals": [{"center": [1, 1, 1]}]}})");
    const auto& meshes = std::get<PathModelConfig>(s.model).obstacles;
    ASSERT_EQ(meshes.size(), 4u);
    swcl_obstacle o[4];
    std::memset(o, 0, sizeof(o));
    o[0].type = SWCL_OBSTACLE_BOX;
    std::copy_n(std::array<float, 3>{1, 1.5f, 2}.data(), 3, o[0].center);
    std::copy_n(std::array<float, 3>{0.5f, 0.25f, 0.75f}.data(), 3, o[0].half_extents);
    o[1].type = SWCL_OBSTACLE_SPHERE;
    std::copy_n(std::array<float, 3>{2, 2, 1}.data(), 3, o[1].center);
    o[1].radius = 0.4f;
    o[2].type = SWCL_OBSTACLE_CYLINDER;
    std::copy_n(std::array<float, 3>{3, 1, 0}.data(), 3, o[2].center);
    o[2].radius = 0.3f;
    o[2].height = 1.5f;
    o[3].type = SWCL_OBSTACLE_OBJ;
    o[3].path = obj.c_str();
    for (int i = 0; i < 4; ++i) {
        SCOPED_TRACE(i);
        expect_same_mesh(capi::obstacle_mesh(o[i], "obstacle"), meshes[size_t(i)]);
    }
    // And they are the primitives' tessellations (not, say, empty meshes).
    expect_same_mesh(meshes[1], sphere_mesh({2, 2, 1}, 0.4f, 24, 48));
    expect_same_mesh(meshes[2], cylinder_mesh({3, 1, 0}, 0.3f, 1.5f, 48));
    EXPECT_EQ(meshes[3].triangle_count(), 12u);
}

TEST(KeyframeSpec, CApiAndScenarioKeyframesAreTheSameMeshes) {
    // A generated shape and an explicit tetrahedron, scaled and moved.
    const Scenario s = parse_scenario(R"({"agents": {"count": 30}, "model": {"type": "force", "keyframes": [
        {"frame": 0, "shape": "sphere", "scale": 2, "offset": [1, -1, 0.5]},
        {"frame": 40, "mesh": {"vertices": [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
                                "triangles": [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]},
         "scale": 0.5, "offset": [0, 0, 2]}]}})");
    const auto& from_scenario = std::get<ForceModelConfig>(s.model).keyframes;
    ASSERT_EQ(from_scenario.size(), 2u);

    const float tet[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t tri[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    swcl_keyframe kf[2];
    std::memset(kf, 0, sizeof(kf));
    kf[0].frame = 0;
    kf[0].shape = "sphere";
    kf[0].scale = 2;
    kf[0].offset[0] = 1, kf[0].offset[1] = -1, kf[0].offset[2] = 0.5f;
    kf[1].frame = 40;
    kf[1].vertices = tet;
    kf[1].vertex_count = 4;
    kf[1].triangles = tri;
    kf[1].triangle_count = 4;
    kf[1].scale = 0.5f;
    kf[1].offset[2] = 2;
    swcl_context ctx{};
    const swcl_context_desc cd = swcl_context_desc_default();
    ASSERT_EQ(swcl_context_create(&cd, &ctx), SWCL_OK) << swcl_last_error();
    swcl_swarm_desc sd = swcl_swarm_desc_default();
    sd.capacity = 30;
    sd.agent_count = 30;
    swcl_swarm swarm{};
    ASSERT_EQ(swcl_swarm_create(ctx, &sd, &swarm), SWCL_OK) << swcl_last_error();
    swcl_force_model_desc d = swcl_force_model_desc_default();
    d.keyframes = kf;
    d.keyframe_count = 2;
    ASSERT_EQ(swcl_swarm_force_set_model(swarm, &d), SWCL_OK) << swcl_last_error();
    auto* model = dynamic_cast<ForceModel*>(capi::swarms().get(swarm.id)->behavior());
    ASSERT_NE(model, nullptr);
    const auto& from_capi = model->config().keyframes;
    ASSERT_EQ(from_capi.size(), 2u);
    for (size_t i = 0; i < 2; ++i) {
        SCOPED_TRACE(i);
        EXPECT_EQ(from_capi[i].frame, from_scenario[i].frame);
        expect_same_mesh(from_capi[i].mesh, from_scenario[i].mesh);
    }
    // The placement is scale, then offset.
    expect_same_mesh(from_scenario[0].mesh, transformed(generated_shape("sphere"), {2, 2, 2}, {1, -1, 0.5f}));
    EXPECT_EQ(swcl_swarm_destroy(swarm), SWCL_OK);
    EXPECT_EQ(swcl_context_destroy(ctx), SWCL_OK);
}

}  // namespace
