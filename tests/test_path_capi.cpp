// The path model through the C API and scenario files: defaults from the
// paper, a run on a mesh given as arrays, moving goals, and bad input
// (NaN vertices, bad OBJ files, goals outside the grid or inside an
// obstacle, grids of 0 cells) that leaves the swarm with its previous model.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "scenario/scenario.hpp"
#include "capi_fixture.hpp"
#include "swarmcl/swarmcl.h"

namespace {

class PathCApi : public swarmcl::test::CApiSwarmTest {
protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(create([](swcl_swarm_desc& s) {
            s.capacity = 64;
            s.agent_count = 64;
            s.seed = 3;
        }));
    }
    // A unit cube mesh as arrays, and a goal beside it (the default domain is [-1, 1]^3).
    swcl_path_model_desc desc() {
        swcl_path_model_desc d = swcl_path_model_desc_default();
        d.resolution[0] = d.resolution[1] = d.resolution[2] = 24;
        obstacle = swcl_obstacle{};
        obstacle.type = SWCL_OBSTACLE_MESH;
        obstacle.vertices = cube_xyz;
        obstacle.vertex_count = 8;
        obstacle.indices = cube_idx;
        obstacle.triangle_count = 12;
        d.obstacles = &obstacle;
        d.obstacle_count = 1;
        goal = swcl_goal{};
        goal.type = SWCL_GOAL_SPHERE;
        goal.center[0] = 0.8f;
        goal.radius = 0.15f;
        d.goals = &goal;
        d.goal_count = 1;
        return d;
    }
    swcl_obstacle obstacle{};
    swcl_goal goal{};
    float cube_xyz[24] = {-.2f, -.2f, -.2f, .2f, -.2f, -.2f, -.2f, .2f, -.2f, .2f, .2f, -.2f,
                          -.2f, -.2f, .2f,  .2f, -.2f, .2f,  -.2f, .2f, .2f,  .2f, .2f, .2f};
    uint32_t cube_idx[36] = {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                             2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5};
};

}  // namespace

TEST_F(PathCApi, DefaultsAreThePapers) {
    const swcl_path_model_desc d = swcl_path_model_desc_default();
    EXPECT_EQ(d.struct_size, sizeof(d));
    EXPECT_FLOAT_EQ(d.cost_a, 0.6f);   // §5
    EXPECT_FLOAT_EQ(d.cost_b, 0.4f);
    EXPECT_FLOAT_EQ(d.speed, 1.5f);    // Table 1
    EXPECT_FLOAT_EQ(d.noise.scale, 0.4f);
    EXPECT_FLOAT_EQ(d.noise.gain, 0.25f);
    EXPECT_EQ(d.second_order, 0);
    EXPECT_EQ(d.resolution[0], 64u);
}

TEST_F(PathCApi, RunsMovesGoalsAndReportsStats) {
    swcl_path_model_desc d = desc();
    d.min_distance = 0.01f;
    ASSERT_EQ(swcl_swarm_path_set_model(swarm, &d), SWCL_OK) << swcl_last_error();
    swcl_path_info info{};
    info.struct_size = sizeof(info);
    ASSERT_EQ(swcl_swarm_path_get_info(swarm, &info), SWCL_OK);
    EXPECT_EQ(info.grid[0], 24u);
    EXPECT_NEAR(info.cell, 2.0f / 24, 1e-6);
    EXPECT_GT(info.preprocess_seconds, 0.0);
    ASSERT_EQ(swcl_swarm_step(swarm, 20), SWCL_OK);
    swcl_step_stats st{};
    st.struct_size = sizeof(st);
    ASSERT_EQ(swcl_swarm_take_step_stats(swarm, &st), SWCL_OK);
    EXPECT_EQ(st.steps, 20u);
    swcl_goal g{};
    g.type = SWCL_GOAL_POINT;
    g.center[0] = -0.8f;
    double seconds = -1;
    ASSERT_EQ(swcl_swarm_path_set_goals(swarm, 0, &g, 1, &seconds), SWCL_OK) << swcl_last_error();
    EXPECT_GT(seconds, 0.0);
    ASSERT_EQ(swcl_swarm_path_get_info(swarm, &info), SWCL_OK);
    EXPECT_EQ(info.recomputes, 1u);
    g.center[0] = 5.0f;  // outside the grid
    EXPECT_EQ(swcl_swarm_path_set_goals(swarm, 0, &g, 1, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("outside the grid"), std::string::npos);
    EXPECT_EQ(swcl_swarm_path_set_goals(swarm, 1, &g, 1, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    std::vector<float> p(3 * 64);
    ASSERT_EQ(swcl_swarm_step(swarm, 5), SWCL_OK);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 64), SWCL_OK);
    for (float v : p) EXPECT_TRUE(std::isfinite(v));
}

TEST_F(PathCApi, BadInputKeepsThePreviousModel) {
    swcl_path_model_desc good = desc();
    ASSERT_EQ(swcl_swarm_path_set_model(swarm, &good), SWCL_OK) << swcl_last_error();
    auto refused = [&](swcl_path_model_desc d, swcl_status want, const char* words) {
        EXPECT_EQ(swcl_swarm_path_set_model(swarm, &d), want) << words;
        EXPECT_NE(std::string(swcl_last_error()).find(words), std::string::npos) << swcl_last_error();
        swcl_path_info info{};
        info.struct_size = sizeof(info);
        EXPECT_EQ(swcl_swarm_path_get_info(swarm, &info), SWCL_OK);
        EXPECT_EQ(info.grid[0], 24u);  // still the first model
    };
    {
        swcl_path_model_desc d = desc();
        cube_xyz[4] = NAN;
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "vertex 1");
        cube_xyz[4] = -.2f;
    }
    {
        swcl_path_model_desc d = desc();
        cube_idx[7] = 99;
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "index 99");
        cube_idx[7] = 5;
    }
    {
        swcl_path_model_desc d = desc();
        obstacle.triangle_count = 0;
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "no triangles");
    }
    {
        swcl_path_model_desc d = desc();
        d.noise.baked = 1;
        d.noise.time_scale = 1.0f;  // a time-varying noise cannot be baked
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "baked");
    }
    {
        swcl_path_model_desc d = desc();
        goal.center[0] = 0.0f;  // inside the cube
        goal.radius = 0.05f;
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "inside an obstacle");
    }
    {
        swcl_path_model_desc d = desc();
        goal.center[0] = 3.0f;
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "outside the grid");
    }
    {
        swcl_path_model_desc d = desc();
        d.resolution[1] = 0;
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "resolution");
        d.resolution[1] = 100000;
        d.resolution[0] = 100000;
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "limit");
    }
    {
        swcl_path_model_desc d = desc();
        d.goal_count = 0;
        refused(d, SWCL_ERROR_INVALID_ARGUMENT, "goal");
    }
    {
        swcl_path_model_desc d = desc();
        obstacle.type = SWCL_OBSTACLE_OBJ;
        obstacle.path = "/nonexistent/mesh.obj";
        refused(d, SWCL_ERROR_IO, "/nonexistent/mesh.obj");
    }
    {
        const std::string path = ::testing::TempDir() + "swarmcl_bad.obj";
        std::ofstream(path) << "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n";
        swcl_path_model_desc d = desc();
        obstacle.type = SWCL_OBSTACLE_OBJ;
        obstacle.path = path.c_str();
        refused(d, SWCL_ERROR_PARSE, ":4:");
        std::remove(path.c_str());
    }
    swcl_swarm none{};
    swcl_path_model_desc d = desc();
    EXPECT_EQ(swcl_swarm_path_set_model(none, &d), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_swarm_path_set_model(swarm, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
}

TEST(PathScenario, ExamplesBuildAndKeysAreChecked) {
    using namespace swarmcl;
    const std::string dir = std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios/";
    for (const char* name : {"path_two_blocks", "path_chasing", "path_aggregation", "path_phototaxis", "path_locusts"}) {
        SCOPED_TRACE(name);
        const Scenario s = load_scenario(dir + name + ".json");
        ASSERT_TRUE(std::holds_alternative<PathModelConfig>(s.model));
        EXPECT_FALSE(std::get<PathModelConfig>(s.model).groups.empty());
    }
    EXPECT_EQ(std::get<PathModelConfig>(load_scenario(dir + "path_locusts.json").model).obstacles.size(), 2u);  // the OBJ hamlet and the ground
    const std::string head = R"({"name": "t", "domain": {"min": [0,0,0], "max": [4,2,1]}, "agents": {"count": 4},)";
    auto error = [&](const std::string& tail) -> std::string {
        try {
            parse_scenario(head + tail);
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(error(R"("model": {"type": "path", "goals": [{"center": [1,1,0.5]}]}})"), "");
    EXPECT_NE(error(R"("model": {"type": "path"}})").find("model.goals: missing"), std::string::npos);
    EXPECT_NE(error(R"("model": {"type": "path", "goals": [{"type": "cone", "center": [1,1,1]}]}})").find("model.goals[0].type"),
              std::string::npos);
    EXPECT_NE(error(R"("obstacles": [{"type": "mesh"}], "model": {"type": "path", "goals": [{"center": [1,1,1]}]}})")
                  .find("obstacles[0].file: missing"),
              std::string::npos);
    EXPECT_NE(error(R"("obstacles": [{"type": "mesh", "file": "/nonexistent.obj"}], "model": {"type": "path", "goals": [{"center": [1,1,1]}]}})")
                  .find("obstacles[0]"),
              std::string::npos);
    EXPECT_NE(error(R"("model": {"type": "path", "grid": {"resolution": [0, 4, 4]}, "goals": [{"center": [1,1,1]}]}})")
                  .find("model.grid.resolution"),
              std::string::npos);
    EXPECT_NE(error(R"("model": {"type": "path", "goals": [{"center": [1,1,1]}], "groups": [{"goals": [{"center": [1,1,1]}]}]}})")
                  .find("model.goals"),
              std::string::npos);
    EXPECT_NE(error(R"("model": {"type": "path", "goals": [{"center": [1,1,1]}], "speeed": 1}})").find("model.speeed: unknown key"),
              std::string::npos);
}

// Chasing (§7) through the C API: a target added to the model, its group's
// goals cleared so the ball is the only goal, then dragged step by step
// along a path round the cube as a user would; the swarm ends near it.  Bad
// targets and lamps: an error naming the problem, nothing changed.
TEST_F(PathCApi, ChasesATargetDrivenThroughTheCApi) {
    swcl_path_model_desc d = desc();
    d.goal_falloff = 0.2f;
    ASSERT_EQ(swcl_swarm_path_set_model(swarm, &d), SWCL_OK) << swcl_last_error();
    swcl_path_target t{};
    t.group = 0;
    t.center[0] = 0.6f;
    t.center[2] = 0.4f;
    t.radius = 0.1f;
    uint32_t index = 9;
    ASSERT_EQ(swcl_swarm_path_add_target(swarm, &t, &index), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(index, 0u);
    ASSERT_EQ(swcl_swarm_path_set_goals(swarm, 0, nullptr, 0, nullptr), SWCL_OK) << swcl_last_error();
    float c[3] = {0, 0, 0.4f};
    for (int leg = 0; leg <= 24; ++leg) {  // round the cube, one step of the path every 10 steps
        const float a = 2.0f * 3.14159265f * float(leg) / 24.0f;
        c[0] = 0.6f * std::cos(a);
        c[1] = 0.6f * std::sin(a);
        double seconds = -1;
        ASSERT_EQ(swcl_swarm_path_set_target(swarm, 0, c, &seconds), SWCL_OK) << swcl_last_error();
        if (leg > 0) EXPECT_GT(seconds, 0.0);
        ASSERT_EQ(swcl_swarm_step(swarm, 10), SWCL_OK);
    }
    ASSERT_EQ(swcl_swarm_step(swarm, 60), SWCL_OK);
    std::vector<float> p(3 * 64);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 64), SWCL_OK);
    double mean = 0;
    for (int i = 0; i < 64; ++i)
        mean += std::sqrt((p[3 * i] - c[0]) * (p[3 * i] - c[0]) + (p[3 * i + 1] - c[1]) * (p[3 * i + 1] - c[1]) +
                          (p[3 * i + 2] - c[2]) * (p[3 * i + 2] - c[2])) / 64;
    EXPECT_LT(mean, 0.3);
    swcl_path_info info{};
    info.struct_size = sizeof(info);
    ASSERT_EQ(swcl_swarm_path_get_info(swarm, &info), SWCL_OK);
    EXPECT_EQ(info.recomputes, 26u);  // add_target, set_goals, 24 moves (the first set_target did not move it)

    const float inside[3] = {0.0f, 0.05f, 0.0f}, outside[3] = {0.0f, 0.0f, 1.5f};
    EXPECT_EQ(swcl_swarm_path_set_target(swarm, 0, inside, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("inside an obstacle"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_swarm_path_set_target(swarm, 0, outside, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("outside the path grid"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_swarm_path_set_target(swarm, 1, c, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_path_set_target(swarm, 0, nullptr, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    swcl_path_target got{};
    ASSERT_EQ(swcl_swarm_path_get_target(swarm, 0, &got), SWCL_OK);
    EXPECT_EQ(got.center[0], c[0]);
    EXPECT_EQ(got.center[1], c[1]);
    EXPECT_EQ(got.radius, 0.1f);
    uint32_t count = 0;
    ASSERT_EQ(swcl_swarm_path_target_count(swarm, &count), SWCL_OK);
    EXPECT_EQ(count, 1u);
    ASSERT_EQ(swcl_swarm_path_get_info(swarm, &info), SWCL_OK);
    EXPECT_EQ(info.recomputes, 26u);

    swcl_path_lamp lamp = swcl_path_lamp_default();
    lamp.enabled = 1;
    lamp.radius = 0.01f;
    lamp.keep_out = 0.01f;  // in the cube's middle: no free cell within 0.19 m
    EXPECT_EQ(swcl_swarm_path_set_lamp(swarm, &lamp), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("no free space around it"), std::string::npos) << swcl_last_error();
    lamp.center[0] = 0.7f;
    ASSERT_EQ(swcl_swarm_path_set_lamp(swarm, &lamp), SWCL_OK) << swcl_last_error();
    lamp.struct_size = 4;
    EXPECT_EQ(swcl_swarm_path_set_lamp(swarm, &lamp), SWCL_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(swcl_swarm_step(swarm, 5), SWCL_OK);
}
