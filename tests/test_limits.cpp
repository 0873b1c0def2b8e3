// Limits (issue 16 item 6): capacities beyond the device's memory give
// SWCL_ERROR_OUT_OF_MEMORY (never a crash or an OpenCL abort) and leave the
// context usable; grids whose cell count would overflow 32-bit indices are
// refused up front; counts and sizes from files are checked before allocation.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "swarmcl/swarmcl.h"

namespace {

class Limits : public ::testing::Test {
protected:
    void SetUp() override {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override { swcl_context_destroy(ctx); }

    // A normal swarm on the same context is created, stepped and read.
    void expect_context_usable() {
        swcl_swarm_desc d = swcl_swarm_desc_default();
        d.agent_count = 100;
        d.capacity = 100;
        swcl_swarm s;
        ASSERT_EQ(swcl_swarm_create(ctx, &d, &s), SWCL_OK) << swcl_last_error();
        swcl_field_model_desc f = swcl_field_model_desc_default();
        ASSERT_EQ(swcl_swarm_field_set_model(s, &f), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(swcl_swarm_step(s, 5), SWCL_OK) << swcl_last_error();
        std::vector<float> p(300);
        ASSERT_EQ(swcl_swarm_read(s, SWCL_ATTRIBUTE_POSITION, p.data(), 100), SWCL_OK);
        for (float x : p) EXPECT_TRUE(std::isfinite(x));
        EXPECT_EQ(swcl_swarm_destroy(s), SWCL_OK);
    }
    swcl_context ctx{};
};

TEST_F(Limits, TwoToThe31AgentsIsOutOfMemoryAndTheContextStaysUsable) {
    for (uint32_t cap : {0x80000000u, 0xC0000000u, 0xFFFFFFFFu}) {
        swcl_swarm_desc d = swcl_swarm_desc_default();
        d.capacity = cap;
        swcl_swarm s{777};
        EXPECT_EQ(swcl_swarm_create(ctx, &d, &s), SWCL_ERROR_OUT_OF_MEMORY) << cap;
        EXPECT_NE(std::string(swcl_last_error()), "");
        EXPECT_EQ(s.id, 777u) << "out must be untouched on failure";
    }
    expect_context_usable();
}

TEST_F(Limits, AScenarioOfTwoToThe31AgentsIsRefusedNotACrash) {
    const std::string text = R"({"name": "huge", "seed": 1, "dt": 0.01, "steps": 1,
      "domain": {"min": [0, 0, 0], "max": [1, 1, 1]}, "interaction_radius": 0.1,
      "agents": {"count": 2147483648}, "model": {"type": "field"}})";
    swcl_scenario sc;
    const swcl_status parsed = swcl_scenario_parse(text.data(), text.size(), &sc);
    if (parsed == SWCL_OK) {
        swcl_swarm s;
        const swcl_status st = swcl_scenario_create_swarm(sc, ctx, &s);
        EXPECT_TRUE(st == SWCL_ERROR_OUT_OF_MEMORY || st == SWCL_ERROR_INVALID_ARGUMENT) << swcl_status_string(st);
        EXPECT_NE(std::string(swcl_last_error()), "");
        std::printf("scenario create_swarm: %s: %s\n", swcl_status_string(st), swcl_last_error());
        swcl_scenario_destroy(sc);
    } else {
        EXPECT_EQ(parsed, SWCL_ERROR_PARSE);
        EXPECT_NE(std::string(swcl_last_error()), "");
        std::printf("scenario parse: %s\n", swcl_last_error());
    }
    expect_context_usable();
}

TEST_F(Limits, A4096CubedPathGridIsRefusedUpFront) {
    swcl_swarm_desc d = swcl_swarm_desc_default();
    d.agent_count = 10;
    swcl_swarm s;
    ASSERT_EQ(swcl_swarm_create(ctx, &d, &s), SWCL_OK);
    swcl_path_model_desc p = swcl_path_model_desc_default();
    p.resolution[0] = p.resolution[1] = p.resolution[2] = 4096;
    swcl_goal goal{};
    goal.type = SWCL_GOAL_SPHERE;
    goal.radius = 0.2f;
    p.goals = &goal;
    p.goal_count = 1;
    EXPECT_EQ(swcl_swarm_path_set_model(s, &p), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("limit"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_swarm_destroy(s), SWCL_OK);
    expect_context_usable();
}

TEST_F(Limits, A4096CubedNoiseBakeIsRefusedUpFront) {
    swcl_noise_desc n = swcl_noise_desc_default();
    n.baked = 1;
    n.bake_resolution[0] = n.bake_resolution[1] = n.bake_resolution[2] = 4096;
    for (int a = 0; a < 3; ++a) n.region_min[a] = -1.f, n.region_max[a] = 1.f;
    const float pts[3] = {0.f, 0.f, 0.f};
    float out[3];
    const swcl_status st = swcl_noise_sample(ctx, &n, pts, 1, 0.0f, 0, out);
    EXPECT_EQ(st, SWCL_ERROR_INVALID_ARGUMENT) << swcl_last_error();
    expect_context_usable();
}

TEST_F(Limits, ATinyInteractionRadiusOverAHugeDomainStillWorks) {
    // 10^12 cells at face value: the neighbour grid widens its cells to its cap.
    swcl_swarm_desc d = swcl_swarm_desc_default();
    d.agent_count = 50;
    d.capacity = 50;
    for (int a = 0; a < 3; ++a) d.domain_min[a] = -1e4f, d.domain_max[a] = 1e4f;
    d.interaction_radius = 1e-3f;
    swcl_swarm s;
    ASSERT_EQ(swcl_swarm_create(ctx, &d, &s), SWCL_OK) << swcl_last_error();
    std::vector<uint32_t> counts(50);
    EXPECT_EQ(swcl_swarm_step(s, 2), SWCL_OK);
    EXPECT_EQ(swcl_swarm_neighbor_count(s, 1.0f, counts.data(), 50), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(swcl_swarm_destroy(s), SWCL_OK);
    expect_context_usable();
}

TEST_F(Limits, HugeNeighborListRequestsAreOutOfMemory) {
    swcl_swarm_desc d = swcl_swarm_desc_default();
    d.agent_count = 1000;
    d.capacity = 1000;
    swcl_swarm s;
    ASSERT_EQ(swcl_swarm_create(ctx, &d, &s), SWCL_OK);
    std::vector<uint32_t> ids(1), counts(1000);
    // 1000 agents x 2^31 neighbours each: 8 TB of ids.
    EXPECT_EQ(swcl_swarm_neighbor_lists(s, 0.1f, 0x80000000u, ids.data(), counts.data(), 1000, nullptr),
              SWCL_ERROR_OUT_OF_MEMORY)
        << swcl_last_error();
    EXPECT_EQ(swcl_swarm_destroy(s), SWCL_OK);
    expect_context_usable();
}

}  // namespace
