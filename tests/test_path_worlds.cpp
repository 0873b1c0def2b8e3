// The path model on a swarm of worlds (issue 25; docs/architecture.md,
// "Worlds"): W worlds stepped by the same launches give, world by world,
// bitwise the runs of the same path-model swarms alone (positions,
// velocities, MDE counts), with per-world seeds, parameters (the noise, s0,
// the goal ramp, MDE, the lamp) and goals (each world's own cost field); a
// checkpoint resumes them bitwise; bad input gets a status naming the
// parameter and world and changes nothing; what does not run in worlds
// (set_goals, set_lamp, the grid per world) is refused by name.  Moving
// goals and chasing targets on worlds: tests/python/test_worlds.py.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "swarmcl/swarmcl.h"
#include "worlds_test_support.hpp"

namespace {

using worlds_test::expect_world_equal;

constexpr uint32_t kWorlds = 4;
constexpr uint32_t kAgents = 301;  // not a multiple of any lane count
const uint64_t kSeeds[kWorlds] = {7, 19, 31, 0x1122334455ull};

// Per world: noise.scale, noise.seed, s0, goal_falloff, min_distance (0: no
// MDE in world 2), the goal's radius and centre's x, the lamp's pull.
const double kScale[kWorlds] = {0.3, 0.45, 0.5, 0.35};
const double kNoiseSeed[kWorlds] = {1, 2, 3, 4000000000.0};
const double kSpeed[kWorlds] = {0.6, 0.9, 0.4, 1.2};
const double kFalloff[kWorlds] = {0.5, 0.0, 1.0, 0.3};
const double kMinDistance[kWorlds] = {0.03, 0.05, 0.0, 0.04};
const double kGoalRadius[kWorlds] = {0.2, 0.15, 0.3, 0.25};
const double kGoalX[kWorlds] = {0.4, -0.3, 0.0, 0.5};
const double kLampProbability[kWorlds] = {0.5, 0.2, 0.0, 0.8};
const double kLampAngle[kWorlds] = {0.0, 0.5, 1.0, 1.5};

class PathWorlds : public worlds_test::WorldsFixture {
protected:
    static swcl_swarm_desc desc(uint32_t worlds, uint64_t seed, const uint64_t* seeds, uint32_t agents = kAgents) {
        return cube_desc(worlds, seed, seeds, agents, 512, 1.0f, 0.1f, 0.02f);
    }
    // A 16^3 path grid over the domain, one sphere goal; with box_ a box
    // boundary of the noise of radius 0, its edges rounded by noise.scale /
    // 8, which differs per world.
    swcl_path_model_desc model(uint32_t k, swcl_goal* goal) const {
        *goal = swcl_goal{};
        goal->type = SWCL_GOAL_SPHERE;
        goal->center[0] = float(kGoalX[k]);
        goal->center[1] = 0.2f;
        goal->center[2] = -0.1f;
        goal->radius = float(kGoalRadius[k]);
        swcl_path_model_desc m = swcl_path_model_desc_default();
        if (box_) {
            static swcl_obstacle box{};
            box.type = SWCL_OBSTACLE_BOX;
            box.center[0] = -0.2f;
            box.half_extents[0] = box.half_extents[1] = box.half_extents[2] = 0.25f;
            m.noise.boundaries = &box;
            m.noise.boundary_count = 1;
        }
        m.noise.scale = float(kScale[k]);
        m.noise.seed = uint64_t(kNoiseSeed[k]);
        for (int a = 0; a < 3; ++a) m.resolution[a] = 16;
        m.speed = float(kSpeed[k]);
        m.goal_falloff = float(kFalloff[k]);
        m.min_distance = float(kMinDistance[k]);
        m.goals = goal;
        m.goal_count = 1;
        return m;
    }
    static swcl_path_lamp lamp(uint32_t k) {
        swcl_path_lamp l = swcl_path_lamp_default();
        l.enabled = 1;
        l.center[0] = -0.5f;
        l.center[1] = 0.5f;
        l.center[2] = 0.0f;
        l.probability = float(kLampProbability[k]);
        l.angle = float(kLampAngle[k]);
        return l;
    }
    swcl_swarm ensemble(uint32_t agents = kAgents) {
        swcl_swarm s = make(desc(kWorlds, 0, kSeeds, agents));
        swcl_goal goal;
        const swcl_path_model_desc m0 = model(0, &goal);
        EXPECT_EQ(swcl_swarm_path_set_model(s, &m0), SWCL_OK) << swcl_last_error();
        set(s, "noise.scale", kScale, kWorlds);
        set(s, "noise.seed", kNoiseSeed, kWorlds);
        set(s, "speed", kSpeed, kWorlds);
        set(s, "goal_falloff", kFalloff, kWorlds);
        set(s, "min_distance", kMinDistance, kWorlds);
        set(s, "goals.0.radius", kGoalRadius, kWorlds);
        std::vector<double> centre;
        for (uint32_t k = 0; k < kWorlds; ++k) centre.insert(centre.end(), {kGoalX[k], 0.2, -0.1});
        set(s, "groups.0.goals.0.center", centre.data(), centre.size());
        const swcl_path_lamp l = lamp(0);
        std::vector<double> lamp_centre, on(kWorlds, 1.0);
        for (uint32_t k = 0; k < kWorlds; ++k) lamp_centre.insert(lamp_centre.end(), {l.center[0], l.center[1], l.center[2]});
        set(s, "lamp.center", lamp_centre.data(), lamp_centre.size());
        set(s, "lamp.enabled", on.data(), kWorlds);
        set(s, "lamp.probability", kLampProbability, kWorlds);
        set(s, "lamp.angle", kLampAngle, kWorlds);
        return s;
    }
    swcl_swarm alone(uint32_t k, uint32_t agents = kAgents) {
        swcl_swarm s = make(desc(1, kSeeds[k], nullptr, agents));
        swcl_goal goal;
        const swcl_path_model_desc m = model(k, &goal);
        EXPECT_EQ(swcl_swarm_path_set_model(s, &m), SWCL_OK) << swcl_last_error();
        const swcl_path_lamp l = lamp(k);
        EXPECT_EQ(swcl_swarm_path_set_lamp(s, &l), SWCL_OK) << swcl_last_error();
        return s;
    }

    void check_bitwise(uint32_t agents, uint32_t steps, bool expect_mde);
    bool box_ = false;
};

// Every world of the ensemble against its swarm alone after `steps` steps
// (world 2 has no MDE).
void PathWorlds::check_bitwise(uint32_t n, uint32_t steps, bool expect_mde) {
    swcl_swarm all = ensemble(n);
    const std::vector<swcl_step_stats> st = worlds_test::expect_worlds_are_their_swarms_alone(
        all, kWorlds, n, steps, [&](uint32_t k) { return alone(k, n); });
    uint64_t moved = 0;
    for (const swcl_step_stats& s : st) moved += s.mde_moved_total;
    if (expect_mde) EXPECT_GT(moved, 0u);  // MDE ran and moved agents
    EXPECT_EQ(st[2].mde_moved_total, 0u);  // min_distance 0
}

TEST_F(PathWorlds, WorldsAreBitwiseTheSwarmsAlone) { check_bitwise(kAgents, 30, true); }

// Each world's noise boundaries are its own (the box's rounding follows its
// noise.scale), as the field model's (test_worlds.cpp).
TEST_F(PathWorlds, WorldsWithABoxBoundaryAreBitwiseTheSwarmsAlone) {
    box_ = true;
    check_bitwise(kAgents, 20, true);
}

// Small, for the Oclgrind check (scripts/oclgrind_check.py).
TEST_F(PathWorlds, SmallWorldsAreBitwiseTheSwarmsAlone) { check_bitwise(37, 3, false); }

// Worlds with the same goals share one set of cost fields; the run is the
// same either way.
TEST_F(PathWorlds, WorldsWithTheSameGoalsAreBitwiseTheSwarmsAloneToo) {
    swcl_swarm all = make(desc(2, 0, kSeeds));
    swcl_goal goal;
    const swcl_path_model_desc m0 = model(0, &goal);
    ASSERT_EQ(swcl_swarm_path_set_model(all, &m0), SWCL_OK) << swcl_last_error();
    const double speed[2] = {kSpeed[0], kSpeed[1]};
    set(all, "speed", speed, 2);
    ASSERT_EQ(swcl_swarm_step(all, 20), SWCL_OK) << swcl_last_error();
    const std::vector<float> pos = read(all, SWCL_ATTRIBUTE_POSITION, 2 * kAgents);
    for (uint32_t k = 0; k < 2; ++k) {
        swcl_swarm one = make(desc(1, kSeeds[k], nullptr));
        swcl_path_model_desc m = m0;
        m.speed = float(kSpeed[k]);
        ASSERT_EQ(swcl_swarm_path_set_model(one, &m), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(swcl_swarm_step(one, 20), SWCL_OK) << swcl_last_error();
        expect_world_equal(pos, read(one, SWCL_ATTRIBUTE_POSITION, kAgents), k, 2, "positions");
    }
}

TEST_F(PathWorlds, ACheckpointResumesBitwise) {
    swcl_swarm resumed = expect_checkpoint_resumes(ensemble(), ensemble(), kWorlds, kAgents, 8, 12,
                                                   "swarmcl_path_worlds_checkpoint.swcl");
    std::vector<double> radius(kWorlds);
    ASSERT_EQ(swcl_swarm_get_world_param(resumed, "goals.0.radius", radius.data(), kWorlds, nullptr), SWCL_OK)
        << swcl_last_error();
    for (uint32_t k = 0; k < kWorlds; ++k) EXPECT_EQ(float(radius[k]), float(kGoalRadius[k]));
}

TEST_F(PathWorlds, BadInputNamesTheParameterAndWorldAndChangesNothing) {
    swcl_swarm all = ensemble();
    const auto expect_error = [&](const char* name, const std::vector<double>& v, const char* says) {
        EXPECT_EQ(swcl_swarm_set_world_param(all, name, v.data(), v.size()), SWCL_ERROR_INVALID_ARGUMENT) << name;
        EXPECT_NE(std::string(swcl_last_error()).find(says), std::string::npos) << swcl_last_error();
    };
    expect_error("speed", {0.1, 0.2, 0.3}, "3 values given for 4 worlds");
    expect_error("speed", {0.1, 0.2, std::nan(""), 0.3}, "in world 2");
    expect_error("goals.0.radius", {0.1, 0.2, 0.3}, "3 values given for 4 worlds");
    expect_error("goals.0.radius", {0.1, -0.2, 0.3, 0.1}, "groups.0.goals.0.radius = -0.2 in world 1 is outside");
    expect_error("goals.0.radius", {0.1, 0.2, std::nan(""), 0.1}, "in world 2");
    expect_error("goals.0.center", {0, 0, 0, 0, 0, 0, 5, 0, 0, 0, 0, 0}, "world 2: path model group 0: goal 0 is outside");
    expect_error("goals.1.radius", {0.1, 0.1, 0.1, 0.1}, "group 0 has 1 goals");
    expect_error("groups.3.goals.0.radius", {0.1, 0.1, 0.1, 0.1}, "group 3 does not exist");
    expect_error("goals.0.half_extents", std::vector<double>(12, 0.1), "not a box");
    expect_error("grid.resolution", std::vector<double>(12, 8), "the path grid is built once");
    expect_error("lamp.center", {0, 0, 0, 0, 0, 0, 9, 0, 0, 0, 0, 0}, "world 2: path model lamp: center is outside");
    expect_error("noise.type", {0, 1, 0, 0}, "selects the noise kernel");
    expect_error("no_such_parameter", {1, 2, 3, 4}, "no parameter 'no_such_parameter'");
    // Nothing half-applied.
    std::vector<double> radius(kWorlds), speed(kWorlds);
    ASSERT_EQ(swcl_swarm_get_world_param(all, "groups.0.goals.0.radius", radius.data(), kWorlds, nullptr), SWCL_OK)
        << swcl_last_error();
    ASSERT_EQ(swcl_swarm_get_world_param(all, "speed", speed.data(), kWorlds, nullptr), SWCL_OK);
    for (uint32_t k = 0; k < kWorlds; ++k) {
        EXPECT_EQ(float(radius[k]), float(kGoalRadius[k]));
        EXPECT_EQ(float(speed[k]), float(kSpeed[k]));
    }
    // Chasing and moving goals are one world's host work: refused by name.
    swcl_path_lamp l = lamp(0);
    EXPECT_EQ(swcl_swarm_path_set_lamp(all, &l), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("several worlds"), std::string::npos) << swcl_last_error();
    swcl_goal g{};
    g.type = SWCL_GOAL_POINT;
    EXPECT_EQ(swcl_swarm_path_set_goals(all, 0, &g, 1, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("several worlds"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_swarm_step(all, 2), SWCL_OK) << swcl_last_error();
}

}  // namespace
