// The C API names before 0.2 (kept until 1.0, swarmcl.h "deprecated names"):
// each old name does exactly what its swcl_swarm_<model>_<verb> successor
// does — two identical swarms, one driven through the old names and one
// through the new, end bitwise equal.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "swarmcl/swarmcl.h"

#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif

namespace {

class DeprecatedNames : public ::testing::Test {
protected:
    void SetUp() override {
        swcl_context_desc cd = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&cd, &ctx), SWCL_OK) << swcl_last_error();
        swcl_swarm_desc sd = swcl_swarm_desc_default();
        sd.capacity = sd.agent_count = kAgents;
        sd.seed = 11;
        for (swcl_swarm* s : {&old_, &new_}) ASSERT_EQ(swcl_swarm_create(ctx, &sd, s), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override {
        swcl_swarm_destroy(old_);
        swcl_swarm_destroy(new_);
        swcl_context_destroy(ctx);
    }
    // Steps both and compares their positions bitwise.
    void expect_same_after(uint32_t steps) {
        ASSERT_EQ(swcl_swarm_step(old_, steps), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(swcl_swarm_step(new_, steps), SWCL_OK) << swcl_last_error();
        std::vector<float> a(3 * kAgents), b(3 * kAgents);
        ASSERT_EQ(swcl_swarm_read(old_, SWCL_ATTRIBUTE_POSITION, a.data(), kAgents), SWCL_OK);
        ASSERT_EQ(swcl_swarm_read(new_, SWCL_ATTRIBUTE_POSITION, b.data(), kAgents), SWCL_OK);
        EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
    }
    static constexpr uint32_t kAgents = 200;
    swcl_context ctx{};
    swcl_swarm old_{}, new_{};
};

TEST_F(DeprecatedNames, FieldModel) {
    swcl_field_model_desc d = swcl_field_model_desc_default();
    d.min_distance = 0.05f;
    ASSERT_EQ(swcl_swarm_set_field_model(old_, &d), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_field_set_model(new_, &d), SWCL_OK) << swcl_last_error();
    expect_same_after(5);
}

TEST_F(DeprecatedNames, ForceModelKeyframesPathAndTargets) {
    swcl_force_model_desc d = swcl_force_model_desc_default();
    swcl_keyframe k{};
    k.shape = "sphere";
    d.keyframes = &k;
    d.keyframe_count = 1;
    ASSERT_EQ(swcl_swarm_set_force_model(old_, &d), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_force_set_model(new_, &d), SWCL_OK) << swcl_last_error();
    k.shape = "heart";
    ASSERT_EQ(swcl_swarm_set_force_keyframes(old_, &k, 1, 0), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_force_set_keyframes(new_, &k, 1, 0), SWCL_OK) << swcl_last_error();
    const float path[] = {0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0};
    ASSERT_EQ(swcl_swarm_set_force_path(old_, path, 4, 0.5f), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_force_set_path(new_, path, 4, 0.5f), SWCL_OK) << swcl_last_error();
    expect_same_after(3);
    std::vector<float> a(3 * kAgents), b(3 * kAgents);
    ASSERT_EQ(swcl_swarm_get_force_targets(old_, a.data(), kAgents), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_force_get_targets(new_, b.data(), kAgents), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0);
}

TEST_F(DeprecatedNames, PathModelGoalsAndInfo) {
    swcl_path_model_desc d = swcl_path_model_desc_default();
    for (uint32_t a = 0; a < 3; ++a) d.resolution[a] = 16;
    swcl_goal g{};
    g.type = SWCL_GOAL_SPHERE;
    g.radius = 0.2f;
    d.goals = &g;
    d.goal_count = 1;
    ASSERT_EQ(swcl_swarm_set_path_model(old_, &d), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_path_set_model(new_, &d), SWCL_OK) << swcl_last_error();
    g.center[0] = 0.5f;
    ASSERT_EQ(swcl_swarm_set_path_goals(old_, 0, &g, 1, nullptr), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_path_set_goals(new_, 0, &g, 1, nullptr), SWCL_OK) << swcl_last_error();
    expect_same_after(4);
    swcl_path_info a{}, b{};
    a.struct_size = b.struct_size = sizeof(swcl_path_info);
    ASSERT_EQ(swcl_swarm_get_path_info(old_, &a), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_path_get_info(new_, &b), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(a.recomputes, 1u);
    EXPECT_EQ(b.recomputes, 1u);
    EXPECT_EQ(a.cell, b.cell);
}

TEST_F(DeprecatedNames, EnergyModelAndGoals) {
    swcl_dataset_desc dd = swcl_dataset_desc_default();
    swcl_dataset data{};
    ASSERT_EQ(swcl_dataset_synthetic(&dd, &data), SWCL_OK) << swcl_last_error();
    swcl_energy_model_desc d = swcl_energy_model_desc_default();
    const float keypoints[] = {-0.5f, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0};
    d.keypoints = keypoints;
    d.keypoint_count = 3;
    ASSERT_EQ(swcl_swarm_set_energy_model(old_, data, &d), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_energy_set_model(new_, data, &d), SWCL_OK) << swcl_last_error();
    swcl_dataset_destroy(data);
    expect_same_after(5);
    std::vector<int32_t> a(kAgents), b(kAgents);
    ASSERT_EQ(swcl_swarm_energy_goals(old_, a.data(), kAgents), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_energy_get_goals(new_, b.data(), kAgents), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(a, b);
    EXPECT_GE(b[0], 0);
}

}  // namespace
