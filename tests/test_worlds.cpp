// Worlds (issue 25; docs/architecture.md, "Worlds"): a swarm of W worlds
// stepped by the same launches gives, world by world, bitwise the runs of
// the same swarms alone (positions, velocities, neighbour queries, step
// statistics), with per-world seeds and model parameters; and bad input
// (0 worlds, wrong counts, NaN and out-of-range values, unknown names,
// models without worlds) gets a status naming what is wrong and changes
// nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstddef>
#include <cstring>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "swarmcl/swarmcl.h"
#include "worlds_test_support.hpp"

namespace {

using worlds_test::expect_world_equal;

constexpr uint32_t kWorlds = 4;
constexpr uint32_t kAgents = 301;  // not a multiple of any lane count: worlds straddle work-items
const uint64_t kSeeds[kWorlds] = {11, 22, 33, 0x1234567890ull};

// Per world: noise.scale, noise.seed, goal.speed, min_distance, max_speed.
const double kScale[kWorlds] = {0.3, 0.4, 0.5, 0.6};
const double kNoiseSeed[kWorlds] = {1, 2, 3, 4000000000.0};
const double kGoalSpeed[kWorlds] = {0.5, 0.8, 1.1, 0.2};
const double kMinDistance[kWorlds] = {0.04, 0.02, 0.0, 0.05};
const double kMaxSpeed[kWorlds] = {0.0, 0.9, 0.7, 0.0};

class Worlds : public worlds_test::WorldsFixture {
protected:
    static swcl_swarm_desc desc(uint32_t worlds, uint64_t seed, const uint64_t* seeds, uint32_t agents = kAgents) {
        return cube_desc(worlds, seed, seeds, agents, 512, 1.0f, 0.1f, 0.02f);
    }
    swcl_field_model_desc model(uint32_t k) const {
        swcl_field_model_desc m = swcl_field_model_desc_default();
        m.noise.domain_walls = walls_;  // at the domain: each world's own
        if (box_) {
            // A box boundary of radius 0: its edges rounded by noise.scale / 8,
            // which differs per world.
            static swcl_obstacle box{};
            box.type = SWCL_OBSTACLE_BOX;
            box.center[0] = 0.2f;
            box.half_extents[0] = box.half_extents[1] = box.half_extents[2] = 0.25f;
            m.noise.boundaries = &box;
            m.noise.boundary_count = 1;
        }
        m.noise.scale = float(kScale[k]);
        m.noise.seed = uint64_t(kNoiseSeed[k]);
        m.has_goal = 1;
        m.goal[0] = 0.3f;
        m.goal[1] = -0.2f;
        m.goal[2] = 0.1f;
        m.goal_radius = 0.2f;
        m.goal_speed = float(kGoalSpeed[k]);
        m.min_distance = float(kMinDistance[k]);
        m.max_speed = float(kMaxSpeed[k]);
        return m;
    }
    // The ensemble: world k gets model(k) through the per-world setters.
    swcl_swarm ensemble(uint32_t agents = kAgents, uint32_t worlds = kWorlds) {
        swcl_swarm s = make(in_own_domains(desc(worlds, 0, kSeeds, agents)));
        const swcl_field_model_desc m0 = model(0);
        EXPECT_EQ(swcl_swarm_field_set_model(s, &m0), SWCL_OK) << swcl_last_error();
        set(s, "noise.scale", kScale, worlds);
        set(s, "noise.seed", kNoiseSeed, worlds);
        set(s, "goal.speed", kGoalSpeed, worlds);
        set(s, "min_distance", kMinDistance, worlds);
        set(s, "max_speed", kMaxSpeed, worlds);
        return s;
    }
    swcl_swarm alone(uint32_t k, uint32_t agents = kAgents) {
        swcl_swarm s = make(in_own_domains(desc(1, kSeeds[k], nullptr, agents), int(k)));
        const swcl_field_model_desc m = model(k);
        EXPECT_EQ(swcl_swarm_field_set_model(s, &m), SWCL_OK) << swcl_last_error();
        return s;
    }

    void check_bitwise(uint32_t agents, uint32_t steps, bool expect_mde);
    void check_step_frames(uint32_t agents, uint32_t frames, uint32_t every);
    int32_t walls_ = 0;
    bool box_ = false;
    void check_world_metrics(uint32_t agents, uint32_t worlds, uint32_t samples);
};

// Every world of the ensemble against its swarm alone after `steps` steps.
void Worlds::check_bitwise(uint32_t n, uint32_t steps, bool expect_mde) {
    swcl_swarm all = ensemble(n);
    uint32_t worlds = 0, agents = 0;
    ASSERT_EQ(swcl_swarm_worlds(all, &worlds), SWCL_OK);
    ASSERT_EQ(swcl_swarm_agent_count(all, &agents), SWCL_OK);
    EXPECT_EQ(worlds, kWorlds);
    EXPECT_EQ(agents, n);
    const size_t total = size_t(kWorlds) * n;
    ASSERT_EQ(swcl_swarm_step(all, steps), SWCL_OK) << swcl_last_error();
    const std::vector<float> pos = read(all, SWCL_ATTRIBUTE_POSITION, total);
    const std::vector<float> vel = read(all, SWCL_ATTRIBUTE_VELOCITY, total);
    std::vector<uint32_t> counts(total), nearest_ids(total);
    std::vector<float> nearest(total);
    ASSERT_EQ(swcl_swarm_neighbor_count(all, 0.15f, counts.data(), total), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_nearest_neighbor(all, nearest.data(), nearest_ids.data(), total), SWCL_OK);
    constexpr uint32_t kCap = 6;
    std::vector<uint32_t> lists(total * kCap), list_counts(total);
    ASSERT_EQ(swcl_swarm_neighbor_lists(all, 0.15f, kCap, lists.data(), list_counts.data(), total, nullptr), SWCL_OK)
        << swcl_last_error();
    std::vector<swcl_step_stats> st(kWorlds);
    for (auto& s : st) s.struct_size = sizeof(swcl_step_stats);
    ASSERT_EQ(swcl_swarm_take_world_step_stats(all, st.data(), kWorlds), SWCL_OK) << swcl_last_error();

    uint64_t moved_somewhere = 0;
    for (uint32_t k = 0; k < kWorlds; ++k) {
        swcl_swarm one = alone(k, n);
        ASSERT_EQ(swcl_swarm_step(one, steps), SWCL_OK) << swcl_last_error();
        expect_world_equal(pos, read(one, SWCL_ATTRIBUTE_POSITION, n), k, kWorlds, "positions");
        expect_world_equal(vel, read(one, SWCL_ATTRIBUTE_VELOCITY, n), k, kWorlds, "velocities");
        std::vector<uint32_t> c(n), ids(n);
        std::vector<float> d(n);
        ASSERT_EQ(swcl_swarm_neighbor_count(one, 0.15f, c.data(), n), SWCL_OK);
        ASSERT_EQ(swcl_swarm_nearest_neighbor(one, d.data(), ids.data(), n), SWCL_OK);
        expect_world_equal(counts, c, k, kWorlds, "neighbour counts");
        expect_world_equal(nearest, d, k, kWorlds, "nearest distances");
        expect_world_equal(nearest_ids, ids, k, kWorlds, "nearest ids");
        std::vector<uint32_t> l(size_t(n) * kCap), lc(n);
        ASSERT_EQ(swcl_swarm_neighbor_lists(one, 0.15f, kCap, l.data(), lc.data(), n, nullptr), SWCL_OK);
        expect_world_equal(lists, l, k, kWorlds, "neighbour lists");
        expect_world_equal(list_counts, lc, k, kWorlds, "neighbour list counts");
        swcl_step_stats s1{};
        s1.struct_size = sizeof(s1);
        ASSERT_EQ(swcl_swarm_take_step_stats(one, &s1), SWCL_OK);
        EXPECT_EQ(st[k].mde_moved_total, s1.mde_moved_total) << "world " << k;
        EXPECT_EQ(st[k].mde_moved_last, s1.mde_moved_last) << "world " << k;
        EXPECT_EQ(st[k].steps, s1.steps);
        moved_somewhere += s1.mde_moved_total;
    }
    // The comparison covers the MDE stage: it moved agents (and in world 2,
    // min_distance 0, none).
    if (expect_mde) EXPECT_GT(moved_somewhere, 0u);
    EXPECT_EQ(st[2].mde_moved_total, 0u);
    // The worlds differ from each other (their parameters and seeds do).
    EXPECT_NE(std::memcmp(pos.data(), pos.data() + 3 * n, 3 * size_t(n) * sizeof(float)), 0);
}

TEST_F(Worlds, FieldModelWorldsAreBitwiseTheSwarmsAlone) { check_bitwise(kAgents, 40, true); }

// Worlds each in a box of its own (its placement, its grid: origin, cell
// edge and cells per axis, and the noise's walls at its box): each world is
// its swarm alone in that box.
TEST_F(Worlds, WorldsOfTheirOwnDomainsAreBitwiseTheSwarmsAlone) {
    boxes_ = own_domains(kWorlds, 1.0f);
    walls_ = 1;
    check_bitwise(kAgents, 40, true);
    // Each world was placed in its own box.
    swcl_swarm all = ensemble();
    const std::vector<float> pos = read(all, SWCL_ATTRIBUTE_POSITION, size_t(kWorlds) * kAgents);
    std::vector<float> boxes(6 * kWorlds);
    ASSERT_EQ(swcl_swarm_world_domains(all, boxes.data(), kWorlds), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(boxes, boxes_);
    for (uint32_t k = 0; k < kWorlds; ++k)
        for (uint32_t i = 0; i < kAgents; ++i)
            for (int a = 0; a < 3; ++a) {
                const float x = pos[(size_t(k) * kAgents + i) * 3 + a];
                ASSERT_GE(x, boxes_[6 * k + a]) << "world " << k;
                ASSERT_LT(x, boxes_[6 * k + 3 + a]) << "world " << k;
            }
    float one[6] = {};
    EXPECT_EQ(swcl_swarm_world_domains(all, one, 1), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("4 worlds"), std::string::npos) << swcl_last_error();
}

// Each world's noise boundaries are its own: a box's rounding follows the
// world's noise.scale (before, every world had world 0's primitives).
TEST_F(Worlds, WorldsWithABoxBoundaryAreBitwiseTheSwarmsAlone) {
    box_ = true;
    check_bitwise(kAgents, 20, true);
}

TEST_F(Worlds, WorldsOfTheirOwnDomainsResumeFromACheckpoint) {
    boxes_ = own_domains(kWorlds, 1.0f);
    walls_ = 1;
    swcl_swarm resumed = expect_checkpoint_resumes(ensemble(), ensemble(), kWorlds, kAgents, 12, 18,
                                                   "swarmcl_world_domains_checkpoint.swcl");
    std::vector<float> boxes(6 * kWorlds);
    ASSERT_EQ(swcl_swarm_world_domains(resumed, boxes.data(), kWorlds), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(boxes, boxes_);
}

TEST_F(Worlds, BadWorldDomainsAreRefusedNamingTheWorld) {
    std::vector<float> boxes = own_domains(kWorlds, 1.0f);
    boxes[6 * 2 + 4] = boxes[6 * 2 + 1] - 0.5f;  // world 2: max y below min y
    swcl_swarm_desc d = desc(kWorlds, 0, kSeeds);
    d.world_domains = boxes.data();
    swcl_swarm s{12345};
    EXPECT_EQ(swcl_swarm_create(ctx_, &d, &s), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("world 2 domain min[1]"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(s.id, 12345u);
    boxes = own_domains(kWorlds, 1.0f);
    boxes[6 * 3 + 2] = NAN;
    d.world_domains = boxes.data();
    EXPECT_EQ(swcl_swarm_create(ctx_, &d, &s), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("world 3 domain bounds must be finite"), std::string::npos)
        << swcl_last_error();
    // A baked noise without a region would cover world 0's domain (one
    // grid for every world): refused, and with a region it runs.
    boxes = own_domains(kWorlds, 1.0f);
    d.world_domains = boxes.data();
    swcl_swarm all = make(d);
    {
        swcl_field_model_desc m = model(0);
        m.noise.baked = 1;
        m.noise.bake_resolution[0] = m.noise.bake_resolution[1] = m.noise.bake_resolution[2] = 8;
        EXPECT_EQ(swcl_swarm_field_set_model(all, &m), SWCL_ERROR_INVALID_ARGUMENT);
        EXPECT_NE(std::string(swcl_last_error()).find("a baked noise without region_min/max"), std::string::npos)
            << swcl_last_error();
        EXPECT_NE(std::string(swcl_last_error()).find("give the noise a region"), std::string::npos);
        for (int a = 0; a < 3; ++a) {
            m.noise.region_min[a] = -2.0f;
            m.noise.region_max[a] = 2.0f;
        }
        EXPECT_EQ(swcl_swarm_field_set_model(all, &m), SWCL_OK) << swcl_last_error();
        EXPECT_EQ(swcl_swarm_step(all, 2), SWCL_OK) << swcl_last_error();
    }
}

// Small, for the Oclgrind check (scripts/oclgrind_check.py): every world
// kernel at a few dozen agents.
TEST_F(Worlds, SmallWorldsAreBitwiseTheSwarmsAlone) { check_bitwise(37, 3, false); }

TEST_F(Worlds, BallisticWorldsAreSeededSeedPlusK) {
    swcl_swarm all = make(desc(3, 100, nullptr));
    const size_t total = 3 * size_t(kAgents);
    std::vector<float> v(3 * total);
    for (size_t i = 0; i < v.size(); ++i) v[i] = float(int(i % 7) - 3) * 0.1f;
    ASSERT_EQ(swcl_swarm_write(all, SWCL_ATTRIBUTE_VELOCITY, v.data(), total), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(all, 5), SWCL_OK);
    const std::vector<float> pos = read(all, SWCL_ATTRIBUTE_POSITION, total);
    for (uint32_t k = 0; k < 3; ++k) {
        swcl_swarm one = make(desc(1, 100 + k, nullptr));
        ASSERT_EQ(swcl_swarm_write(one, SWCL_ATTRIBUTE_VELOCITY, v.data() + 3 * size_t(k) * kAgents, kAgents),
                  SWCL_OK);
        ASSERT_EQ(swcl_swarm_step(one, 5), SWCL_OK);
        const std::vector<float> p1 = read(one, SWCL_ATTRIBUTE_POSITION, kAgents);
        EXPECT_EQ(std::memcmp(pos.data() + 3 * size_t(k) * kAgents, p1.data(), p1.size() * sizeof(float)), 0)
            << "world " << k;
    }
}

TEST_F(Worlds, WritingPositionsSetsEveryWorldsCount) {
    swcl_swarm all = make(desc(3, 5, nullptr));
    std::vector<float> p(3 * 3 * 10);
    for (size_t i = 0; i < p.size(); ++i) p[i] = float(i % 17) * 0.05f - 0.4f;
    ASSERT_EQ(swcl_swarm_write(all, SWCL_ATTRIBUTE_POSITION, p.data(), 30), SWCL_OK) << swcl_last_error();
    uint32_t agents = 0;
    ASSERT_EQ(swcl_swarm_agent_count(all, &agents), SWCL_OK);
    EXPECT_EQ(agents, 10u);
    EXPECT_EQ(read(all, SWCL_ATTRIBUTE_POSITION, 30), p);
    // 31 agents cannot be shared by 3 worlds; 3 x 513 exceed the capacity.
    std::vector<float> q(3 * 3 * 513, 0.0f);
    EXPECT_EQ(swcl_swarm_write(all, SWCL_ATTRIBUTE_POSITION, q.data(), 31), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("multiple"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_swarm_write(all, SWCL_ATTRIBUTE_POSITION, q.data(), 3 * 513), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(read(all, SWCL_ATTRIBUTE_POSITION, 30), p);  // nothing changed
}

TEST_F(Worlds, BadInputNamesTheParameterAndWorldAndChangesNothing) {
    swcl_swarm_desc d = desc(0, 1, nullptr);
    swcl_swarm s{};
    EXPECT_EQ(swcl_swarm_create(ctx_, &d, &s), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("worlds"), std::string::npos) << swcl_last_error();

    swcl_swarm all = ensemble();
    const auto expect_error = [&](const char* name, const std::vector<double>& v, const char* says) {
        EXPECT_EQ(swcl_swarm_set_world_param(all, name, v.data(), v.size()), SWCL_ERROR_INVALID_ARGUMENT) << name;
        EXPECT_NE(std::string(swcl_last_error()).find(says), std::string::npos) << swcl_last_error();
    };
    expect_error("noise.scale", {0.1, 0.2, 0.3}, "3 values given for 4 worlds");
    expect_error("noise.scale", {0.1, 0.2, std::nan(""), 0.3}, "in world 2");
    expect_error("goal.speed", {0.1, -1.0, 0.2, 0.3}, "goal.speed = -1 in world 1 is outside [0, inf)");
    expect_error("no_such_parameter", {1, 2, 3, 4}, "no parameter 'no_such_parameter'");
    expect_error("noise.type", {0, 1, 0, 0}, "selects the noise kernel");
    // Nothing half-applied: the values are those set before.
    std::vector<double> scale(kWorlds), speed(kWorlds);
    size_t count = 0;
    ASSERT_EQ(swcl_swarm_get_world_param(all, "noise.scale", nullptr, 0, &count), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(count, size_t(kWorlds));
    ASSERT_EQ(swcl_swarm_get_world_param(all, "noise.scale", scale.data(), kWorlds, nullptr), SWCL_OK)
        << swcl_last_error();
    ASSERT_EQ(swcl_swarm_get_world_param(all, "goal_speed", speed.data(), kWorlds, nullptr), SWCL_OK)
        << swcl_last_error();
    for (uint32_t k = 0; k < kWorlds; ++k) {
        EXPECT_EQ(float(scale[k]), float(kScale[k]));
        EXPECT_EQ(float(speed[k]), float(kGoalSpeed[k]));
    }
    // A vector: three values a world.
    std::vector<double> goals(3 * kWorlds, 0.25);
    set(all, "goal.center", goals.data(), goals.size());
    ASSERT_EQ(swcl_swarm_get_world_param(all, "goal.center", nullptr, 0, &count), SWCL_OK);
    EXPECT_EQ(count, size_t(3 * kWorlds));
    EXPECT_EQ(swcl_swarm_set_world_param(all, "goal.center", goals.data(), kWorlds), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("3 per world"), std::string::npos) << swcl_last_error();

    // What does not run worlds yet (a recorder) says so.
    swcl_recorder rec{};
    ASSERT_EQ(swcl_recorder_create(::testing::TempDir().c_str(), "swarmcl_worlds_refused", SWCL_EXPORT_CSV, &rec),
              SWCL_OK)
        << swcl_last_error();
    EXPECT_EQ(swcl_recorder_add_frame(rec, all, 0, 0.0), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("several worlds"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_recorder_destroy(rec), SWCL_OK);
    // The field model is still in place and steps.
    EXPECT_EQ(swcl_swarm_step(all, 1), SWCL_OK) << swcl_last_error();

    // A swarm without a model has no per-world parameters.
    swcl_swarm bare = make(desc(2, 1, nullptr));
    double v[2] = {1, 2};
    EXPECT_EQ(swcl_swarm_set_world_param(bare, "noise.scale", v, 2), SWCL_ERROR_INVALID_ARGUMENT);
}

TEST_F(Worlds, ACheckpointHoldsTheWorldsAndResumesBitwise) {
    swcl_swarm resumed = expect_checkpoint_resumes(ensemble(), ensemble(), kWorlds, kAgents, 12, 18,
                                                   "swarmcl_worlds_checkpoint.swcl");
    uint32_t worlds = 0;
    ASSERT_EQ(swcl_swarm_worlds(resumed, &worlds), SWCL_OK);
    EXPECT_EQ(worlds, kWorlds);
    std::vector<double> scale(kWorlds);
    ASSERT_EQ(swcl_swarm_get_world_param(resumed, "noise.scale", scale.data(), kWorlds, nullptr), SWCL_OK);
    for (uint32_t k = 0; k < kWorlds; ++k) EXPECT_EQ(float(scale[k]), float(kScale[k]));
}

// Metrics of every world from the same launches (issue 25: "metrics
// accumulated per world on the device") against each world's swarm alone
// with its own attached metrics: counts, moments, median, MAD and the PDFs of
// all seven metrics bitwise.
void Worlds::check_world_metrics(uint32_t n, uint32_t worlds, uint32_t samples) {
    swcl_swarm all = ensemble(n, worlds);
    swcl_metrics m_all{};
    const double sample_dt = 2 * 0.02;
    ASSERT_EQ(swcl_metrics_attach(all, sample_dt, &m_all), SWCL_OK) << swcl_last_error();
    std::vector<swcl_swarm> ones;
    std::vector<swcl_metrics> m_ones(worlds);
    for (uint32_t k = 0; k < worlds; ++k) {
        ones.push_back(alone(k, n));
        ASSERT_EQ(swcl_metrics_attach(ones[k], sample_dt, &m_ones[k]), SWCL_OK) << swcl_last_error();
    }
    for (uint32_t s = 0; s < samples; ++s) {
        ASSERT_EQ(swcl_metrics_sample(m_all), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(swcl_swarm_step(all, 2), SWCL_OK);
        for (uint32_t k = 0; k < worlds; ++k) {
            ASSERT_EQ(swcl_metrics_sample(m_ones[k]), SWCL_OK);
            ASSERT_EQ(swcl_swarm_step(ones[k], 2), SWCL_OK);
        }
    }
    // The ensemble's metrics hold every world: read one at a time.
    swcl_metric_info info{};
    info.struct_size = sizeof(info);
    EXPECT_EQ(swcl_metrics_get_info(m_all, SWCL_METRIC_SPEED, &info), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("swcl_metrics_world"), std::string::npos) << swcl_last_error();
    swcl_metrics none{12345};
    EXPECT_EQ(swcl_metrics_world(m_all, worlds, &none), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("no world " + std::to_string(worlds)), std::string::npos)
        << swcl_last_error();
    EXPECT_EQ(none.id, 12345u);

    const swcl_pdf_options o = swcl_pdf_options_default();
    double means[kWorlds] = {};
    for (uint32_t k = 0; k < worlds; ++k) {
        swcl_metrics w{};
        ASSERT_EQ(swcl_metrics_world(m_all, k, &w), SWCL_OK) << swcl_last_error();
        for (int m = 0; m < SWCL_METRIC_COUNT; ++m) {
            swcl_metric_info a{}, b{};
            a.struct_size = b.struct_size = sizeof(a);
            ASSERT_EQ(swcl_metrics_get_info(w, swcl_metric(m), &a), SWCL_OK) << swcl_last_error();
            ASSERT_EQ(swcl_metrics_get_info(m_ones[k], swcl_metric(m), &b), SWCL_OK) << swcl_last_error();
            EXPECT_GT(a.count, 0u) << swcl_metric_name(swcl_metric(m));
            EXPECT_EQ(a.count, b.count) << swcl_metric_name(swcl_metric(m)) << " world " << k;
            for (auto [x, y, what] : {std::tuple{a.mean, b.mean, "mean"}, std::tuple{a.sigma, b.sigma, "sigma"},
                                      std::tuple{a.median, b.median, "median"}, std::tuple{a.mad, b.mad, "mad"}})
                EXPECT_EQ(std::memcmp(&x, &y, sizeof(double)), 0)
                    << swcl_metric_name(swcl_metric(m)) << " " << what << " of world " << k << ": " << x << " vs " << y;
            std::vector<double> qa(o.bins), qb(o.bins);
            ASSERT_EQ(swcl_metrics_pdf(w, swcl_metric(m), &o, qa.data(), qa.size()), SWCL_OK) << swcl_last_error();
            ASSERT_EQ(swcl_metrics_pdf(m_ones[k], swcl_metric(m), &o, qb.data(), qb.size()), SWCL_OK);
            EXPECT_EQ(qa, qb) << swcl_metric_name(swcl_metric(m)) << " PDF of world " << k;
            if (m == SWCL_METRIC_SPEED) means[k] = a.mean;
        }
        swcl_metrics_destroy(w);
    }
    // The worlds differ (so a mix-up of worlds would show).
    for (uint32_t k = 1; k < worlds; ++k) EXPECT_NE(means[k - 1], means[k]);
    swcl_metrics_destroy(m_all);
    for (swcl_metrics m : m_ones) swcl_metrics_destroy(m);
}

TEST_F(Worlds, MetricsOfEachWorldAreBitwiseThoseOfTheSwarmAlone) { check_world_metrics(kAgents, kWorlds, 12); }

// Small, for the Oclgrind check.
TEST_F(Worlds, SmallWorldsMetricsAreBitwiseThoseOfTheSwarmAlone) { check_world_metrics(9, 2, 4); }

TEST_F(Worlds, WorldMetricsRefuseTracksAndWorldsTooSmall) {
    // Metrics from frames have no worlds.
    const float xyz[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    swcl_metrics frames{}, out{7};
    ASSERT_EQ(swcl_metrics_from_frames(xyz, 2, 2, 0.1, &frames), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(swcl_metrics_world(frames, 0, &out), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(out.id, 7u);
    swcl_metrics_destroy(frames);
    // One agent a world: no nearest neighbour.
    swcl_swarm tiny = make(desc(3, 1, nullptr, 1));
    EXPECT_EQ(swcl_metrics_attach(tiny, 0.1, &out), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("each world needs at least 2 agents"), std::string::npos)
        << swcl_last_error();
}

// swcl_swarm_step_frames: the frames of step(every) then read, bitwise, for
// worlds and for one; bad input changes nothing (no step taken).
void Worlds::check_step_frames(uint32_t agents, uint32_t n_frames, uint32_t every) {
    for (uint32_t worlds : {kWorlds, 1u}) {
        swcl_swarm a = ensemble(agents, worlds), b = ensemble(agents, worlds);
        const size_t total = size_t(worlds) * agents;
        std::vector<float> frames(n_frames * total * 3, -1.0f);
        ASSERT_EQ(swcl_swarm_step_frames(a, n_frames, every, frames.data(), n_frames * total), SWCL_OK)
            << swcl_last_error();
        for (uint32_t f = 0; f < n_frames; ++f) {
            ASSERT_EQ(swcl_swarm_step(b, every), SWCL_OK);
            const std::vector<float> one = read(b, SWCL_ATTRIBUTE_POSITION, total);
            EXPECT_EQ(std::memcmp(one.data(), frames.data() + f * total * 3, one.size() * sizeof(float)), 0)
                << "frame " << f << " of " << worlds << " worlds";
        }
        uint64_t steps = 0;
        ASSERT_EQ(swcl_swarm_step_count(a, &steps), SWCL_OK);
        EXPECT_EQ(steps, uint64_t(n_frames) * every);
        EXPECT_EQ(swcl_swarm_step_frames(a, 2, 0, frames.data(), 2 * total), SWCL_ERROR_INVALID_ARGUMENT);
        EXPECT_NE(std::string(swcl_last_error()).find("every must be >= 1"), std::string::npos) << swcl_last_error();
        EXPECT_EQ(swcl_swarm_step_frames(a, 2, 1, frames.data(), 2 * total - 1), SWCL_ERROR_INVALID_ARGUMENT);
        EXPECT_NE(std::string(swcl_last_error()).find("2 frames of " + std::to_string(total) + " agents"),
                  std::string::npos)
            << swcl_last_error();
        EXPECT_EQ(swcl_swarm_step_frames(a, 2, 1, nullptr, 2 * total), SWCL_ERROR_INVALID_ARGUMENT);
        ASSERT_EQ(swcl_swarm_step_count(a, &steps), SWCL_OK);
        EXPECT_EQ(steps, uint64_t(n_frames) * every);  // nothing stepped
        EXPECT_EQ(swcl_swarm_step_frames(a, 0, 1, nullptr, 0), SWCL_OK);
        destroy_swarms();
    }
}

TEST_F(Worlds, StepFramesAreTheFramesOfStepThenRead) { check_step_frames(kAgents, 7, 3); }
// Small, for the Oclgrind check (frame_xyz): 4 worlds of 37 agents, 2 frames.
TEST_F(Worlds, SmallStepFramesAreTheFramesOfStepThenRead) { check_step_frames(37, 2, 1); }

TEST_F(Worlds, OlderDescriptorsAreOneWorld) {
    swcl_swarm_desc d = desc(7, 3, nullptr);
    d.struct_size = uint32_t(offsetof(swcl_swarm_desc, worlds));  // a caller built before worlds
    swcl_swarm s = make(d);
    uint32_t worlds = 0;
    ASSERT_EQ(swcl_swarm_worlds(s, &worlds), SWCL_OK);
    EXPECT_EQ(worlds, 1u);
    // A caller built before world_domains: its memory there is not read.
    const float garbage[12] = {5, 5, 5, -5, -5, -5, 5, 5, 5, -5, -5, -5};
    d = desc(2, 3, nullptr);
    d.world_domains = garbage;
    d.struct_size = uint32_t(offsetof(swcl_swarm_desc, world_domains));
    s = make(d);
    std::vector<float> boxes(12);
    ASSERT_EQ(swcl_swarm_world_domains(s, boxes.data(), 2), SWCL_OK) << swcl_last_error();
    for (uint32_t k = 0; k < 2; ++k)
        for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(boxes[6 * k + a], -1.0f);
            EXPECT_EQ(boxes[6 * k + 3 + a], 1.0f);
        }
}

}  // namespace
