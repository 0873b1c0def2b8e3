// The field model (curl-noise paper §4, §6) through the C API: determinism,
// walls keep insects in, the goal pull gathers them, minimum distance
// enforcement (MDE) and its counters, one step against a plain C++ reference,
// and refused bad input leaving the previous model in place.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/philox.hpp"
#include "swarmcl/swarmcl.h"
#include "test_support.hpp"

namespace {

class FieldModelTest : public ::testing::Test {
protected:
    void SetUp() override {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx_), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override {
        for (swcl_swarm s : swarms_) swcl_swarm_destroy(s);
        swcl_context_destroy(ctx_);
    }
    swcl_swarm make_swarm(const swcl_swarm_desc& d) {
        swcl_swarm s{};
        EXPECT_EQ(swcl_swarm_create(ctx_, &d, &s), SWCL_OK) << swcl_last_error();
        swarms_.push_back(s);
        return s;
    }
    static swcl_swarm_desc swarm_desc(float lo, float hi, uint32_t agents, uint64_t seed, float dt) {
        swcl_swarm_desc d = swcl_swarm_desc_default();
        d.capacity = 1024;
        d.agent_count = agents;
        d.seed = seed;
        for (int a = 0; a < 3; ++a) { d.domain_min[a] = lo; d.domain_max[a] = hi; }
        d.interaction_radius = 0.1f;
        d.dt = dt;
        return d;
    }
    static std::vector<float> read(swcl_swarm s, swcl_attribute what = SWCL_ATTRIBUTE_POSITION) {
        uint32_t n = 0;
        EXPECT_EQ(swcl_swarm_agent_count(s, &n), SWCL_OK);
        std::vector<float> p(3 * size_t(n));
        EXPECT_EQ(swcl_swarm_read(s, what, p.data(), n), SWCL_OK) << swcl_last_error();
        return p;
    }
    static void write(swcl_swarm s, const std::vector<float>& p) {
        ASSERT_EQ(swcl_swarm_write(s, SWCL_ATTRIBUTE_POSITION, p.data(), p.size() / 3), SWCL_OK) << swcl_last_error();
    }
    static void set_model(swcl_swarm s, const swcl_field_model_desc& m) {
        ASSERT_EQ(swcl_swarm_field_set_model(s, &m), SWCL_OK) << swcl_last_error();
    }
    static void step(swcl_swarm s, uint32_t n) { ASSERT_EQ(swcl_swarm_step(s, n), SWCL_OK) << swcl_last_error(); }
    static swcl_step_stats stats(swcl_swarm s) {
        swcl_step_stats st{};
        st.struct_size = sizeof(st);
        EXPECT_EQ(swcl_swarm_take_step_stats(s, &st), SWCL_OK) << swcl_last_error();
        return st;
    }
    // A model that moves nothing by itself: zero-gain noise, no goal.
    static swcl_field_model_desc still_model(float min_distance) {
        swcl_field_model_desc m = swcl_field_model_desc_default();
        m.noise.gain = 0.0f;
        m.min_distance = min_distance;
        return m;
    }
    static double dist(const float* a, const float* b) {
        double s = 0;
        for (int k = 0; k < 3; ++k) s += (double(a[k]) - b[k]) * (double(a[k]) - b[k]);
        return std::sqrt(s);
    }

    swcl_context ctx_{};
    std::vector<swcl_swarm> swarms_;
};

TEST_F(FieldModelTest, SameSeedGivesBitwiseSamePositions) {
    swcl_field_model_desc m = swcl_field_model_desc_default();
    m.noise.seed = 11;
    m.noise.time_scale = 1.0f;
    m.has_goal = 1;
    m.goal[0] = 0.2f; m.goal[1] = -0.1f; m.goal[2] = 0.3f;
    m.goal_radius = 0.2f;
    m.goal_speed = 0.5f;
    m.min_distance = 0.04f;  // MDE on
    const auto d = swarm_desc(-1, 1, 300, 3, 1.0f / 30);
    swcl_swarm a = make_swarm(d), b = make_swarm(d);
    set_model(a, m);
    set_model(b, m);
    const auto p0 = read(a);
    step(a, 50);
    step(b, 20);
    step(b, 30);  // the same 50 steps in two calls
    const auto pa = read(a), pb = read(b);
    ASSERT_EQ(pa.size(), pb.size());
    EXPECT_EQ(std::memcmp(pa.data(), pb.data(), pa.size() * sizeof(float)), 0);
    double moved = 0;
    for (size_t i = 0; i < pa.size(); ++i) moved = std::max(moved, double(std::fabs(pa[i] - p0[i])));
    EXPECT_GT(moved, 0.1) << "the swarm moved";

    // Another noise seed gives another trajectory.
    swcl_swarm c = make_swarm(d);
    m.noise.seed = 12;
    set_model(c, m);
    step(c, 50);
    const auto pc = read(c);
    EXPECT_NE(std::memcmp(pa.data(), pc.data(), pa.size() * sizeof(float)), 0);
}

TEST_F(FieldModelTest, DomainWallsKeepAgentsInside) {
    const float lo = 0.0f, hi = 2.0f;
    swcl_swarm s = make_swarm(swarm_desc(lo, hi, 300, 5, 1.0f / 30));
    swcl_field_model_desc m = swcl_field_model_desc_default();
    m.noise.scale = 0.4f;
    m.noise.gain = 0.5f;
    m.noise.boundary_distance = 0.4f;
    m.noise.time_scale = 2.0f;
    m.noise.domain_walls = 1;  // region: the swarm's domain
    set_model(s, m);
    const auto p0 = read(s);
    double min_gap = 1e9, path = 0;
    auto prev = p0;
    for (int k = 0; k < 12; ++k) {
        step(s, 25);
        const auto p = read(s);
        for (size_t i = 0; i < p.size(); ++i) {
            min_gap = std::min({min_gap, double(p[i] - lo), double(hi - p[i])});
            path += std::fabs(p[i] - prev[i]);
        }
        prev = p;
    }
    EXPECT_GE(min_gap, 0.0) << "closest approach to the domain walls over 300 steps";
    EXPECT_GT(path / 300, 0.5) << "mean path length per agent (m, summed over axes, sampled every 25 steps)";
}

TEST_F(FieldModelTest, GoalPullGathersAgentsAtTheGoal) {
    swcl_swarm s = make_swarm(swarm_desc(-2, 2, 0, 1, 1.0f / 30));
    const float goal[3] = {0.1f, -0.2f, 0.15f}, R = 0.3f;
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> U(0, 1);
    std::vector<float> p;
    for (int i = 0; i < 200; ++i) {  // a shell 1.2 .. 1.8 m around the goal
        const double z = 2 * U(rng) - 1, ph = 6.283185307179586 * U(rng), r = 1.2 + 0.6 * U(rng);
        const double q = std::sqrt(1 - z * z);
        p.push_back(float(goal[0] + r * q * std::cos(ph)));
        p.push_back(float(goal[1] + r * q * std::sin(ph)));
        p.push_back(float(goal[2] + r * z));
    }
    write(s, p);
    swcl_field_model_desc m = swcl_field_model_desc_default();  // curl noise, gain 0.25
    m.noise.seed = 8;
    m.has_goal = 1;
    for (int a = 0; a < 3; ++a) m.goal[a] = goal[a];
    m.goal_radius = R;
    m.goal_speed = 1.5f;
    set_model(s, m);
    // The pull (1.5 m/s) beats the noise (|V| < 1 m/s at gain 0.25): 1.5 m in
    // at most 3 s; 150 steps = 5 s.
    step(s, 150);
    const auto q = read(s);
    double worst = 0;
    for (size_t i = 0; i < q.size() / 3; ++i) worst = std::max(worst, dist(&q[3 * i], goal));
    // Inside the goal sphere only the noise moves them; outside they come back
    // within a step, so the overshoot is at most ~|V| dt.
    EXPECT_LT(worst, R + 0.05) << "farthest agent from the goal";
}

TEST_F(FieldModelTest, MinimumDistanceSeparatesIsolatedPairsExactly) {
    const float dmin = 0.15f;
    swcl_swarm s = make_swarm(swarm_desc(-2, 2, 0, 1, 0.05f));
    // Five pairs 0.02 .. 0.14 m apart, pairs 0.8 m from each other.
    std::vector<float> p;
    std::mt19937 rng(12);
    std::uniform_real_distribution<float> U(-1, 1);
    for (int k = 0; k < 5; ++k) {
        const float c[3] = {-1.6f + 0.8f * k, 0.3f * U(rng), 0.3f * U(rng)};
        float dir[3] = {U(rng), U(rng), U(rng)};
        const float l = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        const float sep = 0.02f + 0.03f * k;
        for (int a = 0; a < 3; ++a) p.push_back(c[a] + 0.5f * sep * dir[a] / l);
        for (int a = 0; a < 3; ++a) p.push_back(c[a] - 0.5f * sep * dir[a] / l);
    }
    write(s, p);
    set_model(s, still_model(dmin));
    step(s, 1);
    const auto q = read(s);
    for (int k = 0; k < 5; ++k) {
        const float* a = &q[6 * k];
        const float* b = &q[6 * k + 3];
        EXPECT_NEAR(dist(a, b), dmin, 2e-6) << "pair " << k << ": each agent pushed by half the overlap";
        for (int c = 0; c < 3; ++c) {  // the pair's midpoint and direction stay
            EXPECT_NEAR(0.5 * (a[c] + b[c]), 0.5 * (p[6 * k + c] + p[6 * k + 3 + c]), 1e-6);
            const double before = (p[6 * k + c] - p[6 * k + 3 + c]) / dist(&p[6 * k], &p[6 * k + 3]);
            EXPECT_NEAR((a[c] - b[c]) / dist(a, b), before, 1e-4);
        }
    }
    const swcl_step_stats st = stats(s);
    EXPECT_EQ(st.agents, 10u);
    EXPECT_EQ(st.mde_moved_last, 10u);
    EXPECT_EQ(st.mde_moved_total, 10u);
    EXPECT_EQ(st.steps, 1u);
}

TEST_F(FieldModelTest, MinimumDistanceStatsCountAndReset) {
    const float dmin = 0.2f;
    swcl_swarm s = make_swarm(swarm_desc(-1, 1, 0, 1, 0.05f));
    write(s, {0.1f, 0.1f, 0.1f, 0.15f, 0.12f, 0.1f, -0.8f, -0.8f, -0.8f});  // a close pair and a loner
    set_model(s, still_model(dmin));
    step(s, 1);
    swcl_step_stats st = stats(s);
    EXPECT_EQ(st.agents, 3u);
    EXPECT_EQ(st.mde_moved_last, 2u);
    EXPECT_EQ(st.mde_moved_total, 2u);
    EXPECT_EQ(st.steps, 1u);
    st = stats(s);  // reset by the previous call
    EXPECT_EQ(st.mde_moved_last, 0u);
    EXPECT_EQ(st.mde_moved_total, 0u);
    EXPECT_EQ(st.steps, 0u);
    // Far apart: nobody moves; two close pairs: four move.
    write(s, {0.5f, 0.5f, 0.5f, -0.5f, -0.5f, -0.5f, 0.5f, -0.5f, 0.5f});
    step(s, 2);
    st = stats(s);
    EXPECT_EQ(st.mde_moved_last, 0u);
    EXPECT_EQ(st.mde_moved_total, 0u);
    EXPECT_EQ(st.steps, 2u);
    write(s, {0.5f, 0.5f, 0.5f, 0.55f, 0.5f, 0.5f, -0.5f, -0.5f, -0.5f, -0.5f, -0.45f, -0.5f});
    step(s, 1);
    st = stats(s);
    EXPECT_EQ(st.agents, 4u);
    EXPECT_EQ(st.mde_moved_last, 4u);
    EXPECT_EQ(st.mde_moved_total, 4u);
    // Without a model there is nothing to count.
    ASSERT_EQ(swcl_swarm_clear_model(s), SWCL_OK);
    step(s, 1);
    st = stats(s);
    EXPECT_EQ(st.mde_moved_last, 0u);
    EXPECT_EQ(st.steps, 0u);
    EXPECT_EQ(st.agents, 4u);
}

TEST_F(FieldModelTest, CoincidentAgentsSeparateDeterministically) {
    const float dmin = 0.1f;
    const std::vector<float> p = {0.2f, 0.3f, -0.4f, 0.2f, 0.3f, -0.4f, -0.6f, 0.6f, 0.0f, -0.6f, 0.6f, 0.0f};
    std::vector<float> results[2];
    for (int r = 0; r < 2; ++r) {
        swcl_swarm s = make_swarm(swarm_desc(-1, 1, 0, 1, 0.05f));
        write(s, p);
        set_model(s, still_model(dmin));
        step(s, 1);
        results[r] = read(s);
        for (int k = 0; k < 2; ++k) {
            const float* a = &results[r][6 * k];
            const float* b = &results[r][6 * k + 3];
            EXPECT_NEAR(dist(a, b), dmin, 2e-6) << "pair " << k;
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(0.5 * (a[c] + b[c]), p[6 * k + c], 1e-6);
        }
        EXPECT_EQ(stats(s).mde_moved_last, 4u);
    }
    EXPECT_EQ(std::memcmp(results[0].data(), results[1].data(), results[0].size() * sizeof(float)), 0);
    // The two pairs (different ids) separate along different directions.
    double dot = 0;
    for (int c = 0; c < 3; ++c) dot += (results[0][c] - results[0][3 + c]) * (results[0][6 + c] - results[0][9 + c]);
    EXPECT_LT(std::fabs(dot) / (dmin * dmin), 0.999);
}

// One step of the model against a plain C++ reference:
// v = noise(p0) + s0 (g - p0)/|g - p0| outside the goal sphere, scaled down
// to max_speed when faster (max_speed > 0); p1 = p0 + v dt.
class FieldModelReference : public FieldModelTest {
protected:
    // noise_at(positions, step) -> noise velocities (packed xyz, agent-id order)
    template <class NoiseAt>
    void check_steps(const swcl_field_model_desc& m, NoiseAt noise_at) {
        const float dt = 0.05f;
        swcl_swarm s = make_swarm(swarm_desc(-1, 1, 0, 9, dt));
        const size_t n = 200;
        write(s, swarmcl::test::random_points(n, -1, 1, 31));
        set_model(s, m);
        for (uint32_t k = 0; k < 2; ++k) {
            SCOPED_TRACE("step " + std::to_string(k));
            uint64_t steps = 0;
            ASSERT_EQ(swcl_swarm_step_count(s, &steps), SWCL_OK);
            ASSERT_EQ(steps, k);
            const auto p0 = read(s);
            const auto vn = noise_at(p0, k, float(double(k) * dt));
            std::vector<float> v(3 * n), p1(3 * n);
            for (size_t i = 0; i < n; ++i) {
                float to[3], l2 = 0;
                for (int a = 0; a < 3; ++a) {
                    to[a] = m.goal[a] - p0[3 * i + a];
                    l2 += to[a] * to[a];
                }
                const float l = std::sqrt(l2);
                for (int a = 0; a < 3; ++a)
                    v[3 * i + a] = vn[3 * i + a] + (m.has_goal && l > m.goal_radius ? m.goal_speed * to[a] / l : 0.0f);
                // max_speed > 0: a faster agent is slowed to it.
                const float speed = std::sqrt(v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2]);
                const float k = m.max_speed > 0.0f && speed > m.max_speed ? m.max_speed / speed : 1.0f;
                for (int a = 0; a < 3; ++a) {
                    v[3 * i + a] *= k;
                    p1[3 * i + a] = p0[3 * i + a] + v[3 * i + a] * dt;
                }
            }
            step(s, 1);
            const auto q = read(s), qv = read(s, SWCL_ATTRIBUTE_VELOCITY);
            double perr = 0, verr = 0;
            for (size_t i = 0; i < 3 * n; ++i) {
                perr = std::max(perr, double(std::fabs(q[i] - p1[i])));
                verr = std::max(verr, double(std::fabs(qv[i] - v[i])));
            }
            EXPECT_LT(perr, 1e-6) << "positions: max |device - reference|";
            EXPECT_LT(verr, 1e-5) << "velocities: max |device - reference|";
        }
    }
};

// White noise of gain 0.4 and a goal at 1.5 m/s with a 0.25 m sphere (some
// agents start inside: no pull there), and its reference noise:
// V = gain (2u - 1), u from Philox (seed, agent id, step, white-noise stream 0).
swcl_field_model_desc white_noise_and_goal(uint64_t seed) {
    swcl_field_model_desc m = swcl_field_model_desc_default();
    m.noise.type = SWCL_NOISE_WHITE;
    m.noise.gain = 0.4f;
    m.noise.seed = seed;
    m.has_goal = 1;
    m.goal[0] = 0.3f; m.goal[1] = -0.2f; m.goal[2] = 0.1f;
    m.goal_radius = 0.25f;
    m.goal_speed = 1.5f;
    return m;
}
std::vector<float> white_noise_at(const swcl_field_model_desc& m, const std::vector<float>& p, uint32_t step) {
    std::vector<float> v(p.size());
    for (size_t i = 0; i < p.size() / 3; ++i) {
        const auto r = swarmcl::philox_for(m.noise.seed, uint32_t(i), step, 0);
        for (int a = 0; a < 3; ++a) v[3 * i + a] = m.noise.gain * (2.0f * swarmcl::uniform01(r[a]) - 1.0f);
    }
    return v;
}

TEST_F(FieldModelReference, WhiteNoiseAndGoalOneStep) {
    const swcl_field_model_desc m = white_noise_and_goal(77);
    check_steps(m, [&](const std::vector<float>& p, uint32_t step, float) { return white_noise_at(m, p, step); });
}

// max_speed (a parameter added through the field model's table, issue 24):
// the pull (1.5 m/s) plus the noise, capped at 0.6 m/s for the agents
// outside the goal sphere, untouched for the slower ones inside.
TEST_F(FieldModelReference, MaxSpeedCapsTheVelocityOneStep) {
    swcl_field_model_desc m = white_noise_and_goal(78);
    m.max_speed = 0.6f;
    check_steps(m, [&](const std::vector<float>& p, uint32_t step, float) { return white_noise_at(m, p, step); });
}

TEST_F(FieldModelTest, MaxSpeedBoundsEveryAgentsSpeed) {
    swcl_swarm s = make_swarm(swarm_desc(-2, 2, 300, 5, 1.0f / 30));
    swcl_field_model_desc m = swcl_field_model_desc_default();
    m.noise.gain = 0.5f;
    m.has_goal = 1;
    m.goal_speed = 2.0f;
    m.max_speed = 0.7f;
    set_model(s, m);
    step(s, 20);
    const auto v = read(s, SWCL_ATTRIBUTE_VELOCITY);
    double fastest = 0;
    for (size_t i = 0; i < v.size() / 3; ++i)
        fastest = std::max(fastest, std::sqrt(double(v[3 * i]) * v[3 * i] + double(v[3 * i + 1]) * v[3 * i + 1] +
                                              double(v[3 * i + 2]) * v[3 * i + 2]));
    EXPECT_LE(fastest, 0.7 * (1 + 1e-6));
    EXPECT_GT(fastest, 0.69) << "the pull alone is 2 m/s: the cap should bind";
    m.max_speed = -0.1f;
    EXPECT_EQ(swcl_swarm_field_set_model(s, &m), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("max_speed = -0.1 is outside [0, inf) (m/s)"), std::string::npos)
        << swcl_last_error();
}

TEST_F(FieldModelReference, TimeVaryingCurlNoiseAndGoalOneStep) {
    swcl_field_model_desc m = swcl_field_model_desc_default();
    m.noise.type = SWCL_NOISE_CURL;
    m.noise.scale = 0.4f;
    m.noise.gain = 0.3f;
    m.noise.seed = 9;
    m.noise.time_scale = 0.5f;
    m.has_goal = 1;
    m.goal[0] = -0.3f; m.goal[1] = 0.2f; m.goal[2] = 0.0f;
    m.goal_radius = 0.2f;
    m.goal_speed = 1.0f;
    check_steps(m, [&](const std::vector<float>& p, uint32_t step, float t) {
        std::vector<float> v(p.size());
        EXPECT_EQ(swcl_noise_sample(ctx_, &m.noise, p.data(), p.size() / 3, t, step, v.data()), SWCL_OK)
            << swcl_last_error();
        return v;
    });
}

TEST_F(FieldModelTest, BadInputKeepsThePreviousModel) {
    const float dt = 0.1f;
    swcl_swarm s = make_swarm(swarm_desc(-1, 1, 0, 1, dt));
    const std::vector<float> p = {0.0f, 0.0f, 0.0f, 0.5f, 0.5f, 0.0f};
    write(s, p);
    // Model A: no noise, a pull at 1 m/s towards (10, 0, 0).
    swcl_field_model_desc a = still_model(0.0f);
    a.has_goal = 1;
    a.goal[0] = 10.0f;
    a.goal_speed = 1.0f;
    set_model(s, a);

    auto refused = [&](const swcl_field_model_desc& m, const char* name) {
        EXPECT_EQ(swcl_swarm_field_set_model(s, &m), SWCL_ERROR_INVALID_ARGUMENT) << name;
        const std::string msg = swcl_last_error();
        EXPECT_NE(msg.find(name), std::string::npos) << "message '" << msg << "' does not name '" << name << "'";
    };
    swcl_field_model_desc m = a;
    m.goal[1] = std::nanf("");
    refused(m, "goal");
    m = a;
    m.goal_speed = std::nanf("");
    refused(m, "goal_speed");
    m = a;
    m.goal_radius = -1.0f;
    refused(m, "goal_radius");
    m = a;
    m.min_distance = -0.1f;
    refused(m, "min_distance");
    m = a;
    m.min_distance = std::nanf("");
    refused(m, "min_distance");
    m = a;
    m.noise.scale = 0.0f;
    refused(m, "scale");
    m = a;
    m.noise.gain = std::nanf("");
    refused(m, "gain");
    m = a;
    m.noise.type = SWCL_NOISE_WHITE;
    m.noise.baked = 1;
    refused(m, "baked");
    m = a;
    m.noise.boundary_count = 1;  // boundaries NULL
    refused(m, "boundaries");
    m = a;
    m.noise.struct_size = 0;
    refused(m, "struct_size");
    EXPECT_EQ(swcl_swarm_field_set_model(s, nullptr), SWCL_ERROR_INVALID_ARGUMENT);

    // Still model A: each agent moves dt * 1 m/s towards the goal.
    step(s, 1);
    const auto q = read(s);
    for (int i = 0; i < 2; ++i) {
        const double to[3] = {10.0 - p[3 * i], -p[3 * i + 1], -p[3 * i + 2]};
        const double l = std::sqrt(to[0] * to[0] + to[1] * to[1] + to[2] * to[2]);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(q[3 * i + c], p[3 * i + c] + dt * to[c] / l, 1e-6);
    }
    EXPECT_EQ(stats(s).steps, 1u);
}

TEST_F(FieldModelTest, DestroyedSwarmIsAnInvalidHandle) {
    swcl_swarm_desc d = swarm_desc(-1, 1, 10, 1, 0.05f);
    swcl_swarm s{};
    ASSERT_EQ(swcl_swarm_create(ctx_, &d, &s), SWCL_OK);
    ASSERT_EQ(swcl_swarm_destroy(s), SWCL_OK);
    const swcl_field_model_desc m = swcl_field_model_desc_default();
    EXPECT_EQ(swcl_swarm_field_set_model(s, &m), SWCL_ERROR_INVALID_HANDLE);
    swcl_step_stats st{};
    st.struct_size = sizeof(st);
    EXPECT_EQ(swcl_swarm_take_step_stats(s, &st), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_swarm_clear_model(s), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_swarm_field_set_model(swcl_swarm{0xdeadbeefULL}, &m), SWCL_ERROR_INVALID_HANDLE);
}

}  // namespace
