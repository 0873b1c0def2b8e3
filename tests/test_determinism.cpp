// Determinism across paths (issue 16 item 4): one step call of k steps equals
// k calls of one step; two contexts on the same device agree; the CLI's
// recorded frames equal a run through the C API (swcl_scenario_* + step +
// read) — all bitwise, for every model type.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "io_test_support.hpp"
#include "scenario_runs.hpp"

#ifndef SWARMCL_CLI
#error "SWARMCL_CLI must name the swarmcl binary"
#endif

namespace {

using namespace swarmcl::test;
using namespace swarmcl::iotest;

class Determinism : public ::testing::TestWithParam<ModelCase> {
protected:
    void SetUp() override {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override { swcl_context_destroy(ctx); }
    swcl_context ctx{};
};

TEST_P(Determinism, StepTenEqualsTenSingleSteps) {
    const std::string text = scenario_text(GetParam(), 30);
    swcl_swarm a, b;
    ASSERT_EQ(scenario_swarm(text, ctx, &a), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(scenario_swarm(text, ctx, &b), SWCL_OK) << swcl_last_error();
    State sa, sb, start;
    ASSERT_EQ(read_state(a, &start), SWCL_OK);
    for (int round = 0; round < 3; ++round) {
        ASSERT_EQ(swcl_swarm_step(a, 10), SWCL_OK) << swcl_last_error();
        for (int i = 0; i < 10; ++i) ASSERT_EQ(swcl_swarm_step(b, 1), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(read_state(a, &sa), SWCL_OK);
        ASSERT_EQ(read_state(b, &sb), SWCL_OK);
        EXPECT_TRUE(sa == sb) << GetParam().model << ": step(10) differs from ten step(1) in round " << round;
    }
    EXPECT_FALSE(sa == start) << "the swarm must have moved";
    swcl_swarm_destroy(a);
    swcl_swarm_destroy(b);
}

TEST_P(Determinism, TwoContextsOnOneDeviceAgree) {
    swcl_context_desc d = swcl_context_desc_default();
    swcl_context other;
    ASSERT_EQ(swcl_context_create(&d, &other), SWCL_OK) << swcl_last_error();
    const std::string text = scenario_text(GetParam(), 25);
    swcl_status s1, s2;
    const State a = run_scenario(text, ctx, 25, 5, &s1);
    const State b = run_scenario(text, other, 25, 5, &s2);
    ASSERT_EQ(s1, SWCL_OK);
    ASSERT_EQ(s2, SWCL_OK);
    EXPECT_TRUE(a == b) << GetParam().model;
    swcl_context_destroy(other);
}

TEST_P(Determinism, CliFramesEqualTheCApiRun) {
    const uint32_t steps = 20, every = 5;
    TempDir dir;
    write_text(dir / "s.json", scenario_text(GetParam(), steps, every));
    const std::string cmd = "cd '" + dir.path() + "' && '" + SWARMCL_CLI +
                            "' run s.json --out o --format npy --quiet >/dev/null 2>cli.err </dev/null";
    const int raw = std::system(cmd.c_str());
    ASSERT_TRUE(raw != -1 && WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << read_bytes(dir / "cli.err");
    std::string base;
    for (const auto& f : list_dir(dir / "o"))
        if (f.size() > 14 && f.compare(f.size() - 14, 14, "_positions.npy") == 0) base = f.substr(0, f.size() - 14);
    ASSERT_FALSE(base.empty());
    const Npy pos = read_npy(dir / ("o/" + base + "_positions.npy"));
    const Npy vel = read_npy(dir / ("o/" + base + "_velocities.npy"));
    const uint32_t n = GetParam().agents, frames = steps / every + 1;
    ASSERT_EQ(pos.shape, (std::vector<uint64_t>{frames, n, 3}));
    ASSERT_EQ(vel.shape, pos.shape);
    const auto p = as_vector<float>(pos.data), v = as_vector<float>(vel.data);

    swcl_swarm s;
    ASSERT_EQ(scenario_swarm(scenario_text(GetParam(), steps, every), ctx, &s), SWCL_OK) << swcl_last_error();
    for (uint32_t f = 0; f < frames; ++f) {
        if (f > 0) ASSERT_EQ(swcl_swarm_step(s, every), SWCL_OK);
        State st;
        ASSERT_EQ(read_state(s, &st), SWCL_OK);
        EXPECT_EQ(std::memcmp(st.p.data(), p.data() + size_t(f) * n * 3, n * 3 * sizeof(float)), 0)
            << GetParam().model << ": positions differ at frame " << f;
        EXPECT_EQ(std::memcmp(st.v.data(), v.data() + size_t(f) * n * 3, n * 3 * sizeof(float)), 0)
            << GetParam().model << ": velocities differ at frame " << f;
    }
    swcl_swarm_destroy(s);
}

INSTANTIATE_TEST_SUITE_P(EveryModel, Determinism, ::testing::ValuesIn(model_cases()),
                         [](const ::testing::TestParamInfo<ModelCase>& i) { return std::string(i.param.model); });

}  // namespace
