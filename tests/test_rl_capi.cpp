// The RL environment through the C API (issue 15): whole arrays, the
// rule-based baseline loop, determinism, and every bad input as a status
// with a message that names the problem.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "swarmcl/swarmcl.h"

namespace {

class RlCApi : public ::testing::Test {
protected:
    void SetUp() override {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override { swcl_context_destroy(ctx); }
    swcl_context ctx{};
};

bool error_mentions(const char* needle) { return std::string(swcl_last_error()).find(needle) != std::string::npos; }

}  // namespace

TEST_F(RlCApi, RuleBasedBaselineLoopWithWholeArrays) {
    swcl_rl_env_desc d = swcl_rl_env_desc_default();
    EXPECT_EQ(d.w_leader, 4.9f);  // Table 1
    EXPECT_EQ(d.dq_max_deg, 4.0f);
    d.worlds = 3;
    d.agents = 20;
    d.scenario = "stairway";
    d.max_steps = 30;
    swcl_rl_env env{};
    ASSERT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_OK) << swcl_last_error();
    uint32_t W = 0, N = 0, D = 0;
    ASSERT_EQ(swcl_rl_env_get_info(env, &W, &N, &D), SWCL_OK);
    EXPECT_EQ(W, 3u);
    EXPECT_EQ(N, 20u);
    EXPECT_EQ(D, 54u);
    const size_t n = size_t(W) * N;
    std::vector<float> obs(n * D), obs2(n * D), act(4 * n), rew(n);
    std::vector<uint8_t> term(W), trunc(W);
    ASSERT_EQ(swcl_rl_env_reset(env, 42, obs.data(), obs.size()), SWCL_OK) << swcl_last_error();
    for (int t = 0; t < 30; ++t) {
        ASSERT_EQ(swcl_rl_env_rag_actions(env, act.data(), act.size()), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(swcl_rl_env_step(env, act.data(), act.size(), obs.data(), obs.size(), rew.data(), rew.size(),
                                   term.data(), trunc.data(), W),
                  SWCL_OK)
            << swcl_last_error();
        for (float r : rew) ASSERT_TRUE(std::isfinite(r));
        for (float o : obs) ASSERT_TRUE(std::isfinite(o));
    }
    for (uint32_t w = 0; w < W; ++w) EXPECT_EQ(trunc[w], 1);
    // Same seed: the same bits.
    ASSERT_EQ(swcl_rl_env_reset(env, 42, obs2.data(), obs2.size()), SWCL_OK);
    ASSERT_EQ(swcl_rl_env_reset(env, 42, obs.data(), obs.size()), SWCL_OK);
    EXPECT_EQ(0, std::memcmp(obs.data(), obs2.data(), obs.size() * sizeof(float)));
    // Masked reset of world 1 only.
    const uint8_t mask[3] = {0, 1, 0};
    EXPECT_EQ(swcl_rl_env_reset_worlds(env, mask, 3, nullptr, 0), SWCL_OK) << swcl_last_error();
    std::vector<float> pos(4 * n), lpos(4 * W);
    EXPECT_EQ(swcl_rl_env_read_state(env, pos.data(), pos.size(), nullptr, 0, lpos.data(), nullptr, lpos.size()),
              SWCL_OK)
        << swcl_last_error();
    EXPECT_EQ(lpos[4], -20.0f);  // stairway's first waypoint
    EXPECT_EQ(swcl_rl_env_destroy(env), SWCL_OK);
}

TEST_F(RlCApi, ResetWithASeedPerWorld) {
    // World w of reset_seeds(seeds) gets the bits world w gets from
    // reset(seeds[w]); a wrong count is refused and changes nothing.
    swcl_rl_env_desc d = swcl_rl_env_desc_default();
    d.worlds = 3;
    d.agents = 5;
    swcl_rl_env env{};
    ASSERT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_OK) << swcl_last_error();
    const size_t per = 5 * 54, all = 3 * per;
    std::vector<float> mixed(all), a(all), b(all), again(all);
    const uint64_t seeds[3] = {7, 9, 7};
    ASSERT_EQ(swcl_rl_env_reset_seeds(env, seeds, 3, mixed.data(), all), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_rl_env_reset(env, 7, a.data(), all), SWCL_OK);
    ASSERT_EQ(swcl_rl_env_reset(env, 9, b.data(), all), SWCL_OK);
    EXPECT_EQ(0, std::memcmp(mixed.data(), a.data(), per * sizeof(float)));                  // world 0: seed 7
    EXPECT_EQ(0, std::memcmp(mixed.data() + per, b.data() + per, per * sizeof(float)));      // world 1: seed 9
    EXPECT_EQ(0, std::memcmp(mixed.data() + 2 * per, a.data() + 2 * per, per * sizeof(float)));  // world 2: seed 7
    EXPECT_NE(0, std::memcmp(mixed.data() + per, a.data() + per, per * sizeof(float)));
    EXPECT_EQ(swcl_rl_env_reset_seeds(env, seeds, 2, again.data(), all), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("worlds = 3 entries (2 given)")) << swcl_last_error();
    EXPECT_EQ(swcl_rl_env_reset_seeds(env, nullptr, 3, nullptr, 0), SWCL_ERROR_INVALID_ARGUMENT);
    std::vector<float> act(4 * 15, 0.0f), o1(all), o2(all);
    ASSERT_EQ(swcl_rl_env_step(env, act.data(), act.size(), o1.data(), all, nullptr, 0, nullptr, nullptr, 0), SWCL_OK);
    ASSERT_EQ(swcl_rl_env_reset(env, 9, nullptr, 0), SWCL_OK);  // the refused calls left the seed-9 state
    ASSERT_EQ(swcl_rl_env_step(env, act.data(), act.size(), o2.data(), all, nullptr, 0, nullptr, nullptr, 0), SWCL_OK);
    EXPECT_EQ(0, std::memcmp(o1.data(), o2.data(), all * sizeof(float)));
    EXPECT_EQ(swcl_rl_env_destroy(env), SWCL_OK);
}

TEST_F(RlCApi, BadInputGivesAStatusAndAMessage) {
    swcl_rl_env_desc d = swcl_rl_env_desc_default();
    swcl_rl_env env{};
    d.worlds = 0;
    EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("worlds must be >= 1")) << swcl_last_error();
    d.worlds = 2;
    d.agents = 0;
    EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_ERROR_INVALID_ARGUMENT);
    d.agents = 1u << 30;
    EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("exceeds")) << swcl_last_error();
    d.agents = 10;
    d.scenario = "labyrinth";
    EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("labyrinth")) << swcl_last_error();
    d.scenario = nullptr;
    const float one_wp[4] = {0, 0, 0, 1};
    d.waypoints = one_wp;
    d.waypoint_count = 1;
    EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("at least 2 waypoints")) << swcl_last_error();
    d.waypoints = nullptr;
    d.waypoint_count = 0;
    d.rag_leader_kd = -1.0f;
    EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("rag_leader_kd = -1")) << swcl_last_error();
    d.rag_leader_kd = 1.0f;
    d.rag_leader_kp = NAN;
    EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("rag_leader_kp = nan")) << swcl_last_error();
    d.rag_leader_kp = 0.25f;
    d.struct_size = 4;
    EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_ERROR_INVALID_ARGUMENT);
    d = swcl_rl_env_desc_default();
    d.worlds = 2;
    d.agents = 10;
    ASSERT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_OK) << swcl_last_error();
    std::vector<float> act(80, 0.0f), obs(54 * 20), rew(20);
    uint8_t term[2], trunc[2];
    EXPECT_EQ(swcl_rl_env_step(env, act.data(), act.size(), nullptr, 0, nullptr, 0, nullptr, nullptr, 0),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("reset")) << swcl_last_error();
    ASSERT_EQ(swcl_rl_env_reset(env, 1, nullptr, 0), SWCL_OK);
    EXPECT_EQ(swcl_rl_env_step(env, act.data(), 79, nullptr, 0, nullptr, 0, nullptr, nullptr, 0),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("80 floats (79 given)")) << swcl_last_error();
    EXPECT_EQ(swcl_rl_env_step(env, act.data(), 80, obs.data(), obs.size() - 1, nullptr, 0, nullptr, nullptr, 0),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_rl_env_step(env, act.data(), 80, nullptr, 0, rew.data(), rew.size(), term, trunc, 1),
              SWCL_ERROR_INVALID_ARGUMENT);
    act[5] = NAN;
    EXPECT_EQ(swcl_rl_env_step(env, act.data(), 80, nullptr, 0, nullptr, 0, nullptr, nullptr, 0),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("not finite")) << swcl_last_error();
    act[5] = 0;
    const float bad_ctl[8] = {0, 0, 0, INFINITY, 0, 0, 0, 0};
    EXPECT_EQ(swcl_rl_env_set_leader_controls(env, bad_ctl, 8), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_rl_env_set_leader_controls(env, bad_ctl, 4), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_rl_env_rag_actions(env, act.data(), 3), SWCL_ERROR_INVALID_ARGUMENT);
    // Still usable.
    EXPECT_EQ(swcl_rl_env_step(env, act.data(), 80, obs.data(), obs.size(), rew.data(), rew.size(), term, trunc, 2),
              SWCL_OK)
        << swcl_last_error();
    EXPECT_EQ(swcl_rl_env_destroy(env), SWCL_OK);
    EXPECT_EQ(swcl_rl_env_destroy(env), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_rl_env_step(env, act.data(), 80, nullptr, 0, nullptr, 0, nullptr, nullptr, 0),
              SWCL_ERROR_INVALID_HANDLE);
}

// The RAG's leader coupling through the C API: the defaults (PD, 0.25, 1);
// a caller built before the coupling's fields (the smaller struct, garbage
// after it) gets the defaults: the same actions as a default desc.
TEST_F(RlCApi, LeaderCouplingFieldsAndTheFirstVersionOfTheDesc) {
    const swcl_rl_env_desc def = swcl_rl_env_desc_default();
    EXPECT_EQ(def.rag_leader_pd, 1);
    EXPECT_EQ(def.rag_leader_kp, 0.25f);
    EXPECT_EQ(def.rag_leader_kd, 1.0f);
    auto rag_after_reset = [&](const swcl_rl_env_desc& d) {
        swcl_rl_env env{};
        EXPECT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_OK) << swcl_last_error();
        std::vector<float> a(4 * d.worlds * d.agents);
        EXPECT_EQ(swcl_rl_env_reset(env, 5, nullptr, 0), SWCL_OK);
        EXPECT_EQ(swcl_rl_env_rag_actions(env, a.data(), a.size()), SWCL_OK) << swcl_last_error();
        swcl_rl_env_destroy(env);
        return a;
    };
    swcl_rl_env_desc d = def;
    d.worlds = 2;
    d.agents = 30;
    const std::vector<float> pd = rag_after_reset(d);
    swcl_rl_env_desc old = d;
    old.struct_size = uint32_t(offsetof(swcl_rl_env_desc, rag_leader_pd));
    old.rag_leader_pd = 0;
    old.rag_leader_kp = -7.0f;  // beyond the caller's struct: never read
    old.rag_leader_kd = NAN;
    EXPECT_EQ(rag_after_reset(old), pd);
    swcl_rl_env_desc zones = d;
    zones.rag_leader_pd = 0;
    EXPECT_NE(rag_after_reset(zones), pd);
}

// The layout: the stairway's path and steps as the scenario made them; a
// joystick leader has no waypoints; too small an array is refused unwritten.
TEST_F(RlCApi, LayoutGivesTheScenariosWaypointsAndBoxes) {
    swcl_rl_env_desc d = swcl_rl_env_desc_default();
    d.worlds = 1;
    d.agents = 4;
    d.scenario = "stairway";
    swcl_rl_env env{};
    ASSERT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_OK) << swcl_last_error();
    uint32_t nw = 0, nb = 0;
    ASSERT_EQ(swcl_rl_env_get_layout(env, nullptr, 0, &nw, nullptr, 0, &nb), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(nw, 6u);
    EXPECT_EQ(nb, 4u);
    std::vector<float> wp(4 * nw, -1.0f), ob(6 * nb, -1.0f);
    ASSERT_EQ(swcl_rl_env_get_layout(env, wp.data(), nw, nullptr, ob.data(), nb, nullptr), SWCL_OK);
    EXPECT_EQ(wp[0], -20.0f);     // the first waypoint (-20, 0, 6)
    EXPECT_EQ(wp[2], 6.0f);
    EXPECT_EQ(wp[3], 0.5f);       // speeds start at 0.5 (§IV-B)
    EXPECT_EQ(wp[4 * 5], 56.0f);  // the last (56, 0, 18)
    // Step 3: x in [36, 48], z in [-4, 12]: centre (42, 0, 4), half (6, 15, 8).
    const float step3[6] = {42, 0, 4, 6, 15, 8};
    for (int k = 0; k < 6; ++k) EXPECT_EQ(ob[18 + k], step3[k]) << k;
    std::vector<float> small(4 * 2, 7.0f);
    EXPECT_EQ(swcl_rl_env_get_layout(env, small.data(), 2, nullptr, nullptr, 0, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_TRUE(error_mentions("out_waypoints needs 6 rows")) << swcl_last_error();
    for (float v : small) EXPECT_EQ(v, 7.0f);
    EXPECT_EQ(swcl_rl_env_get_layout(swcl_rl_env{}, nullptr, 0, &nw, nullptr, 0, &nb), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_rl_env_destroy(env), SWCL_OK);

    d.scenario = "roaming";
    ASSERT_EQ(swcl_rl_env_create(ctx, &d, &env), SWCL_OK);
    ASSERT_EQ(swcl_rl_env_get_layout(env, nullptr, 0, &nw, nullptr, 0, &nb), SWCL_OK);
    EXPECT_EQ(nw, 0u);
    EXPECT_EQ(nb, 0u);
    EXPECT_EQ(swcl_rl_env_destroy(env), SWCL_OK);
}
