// The FASTSWARM energy model on a swarm of worlds (issue 25;
// docs/architecture.md, "Worlds"): W worlds stepped by the same launches
// give, world by world, bitwise the runs of the same energy-model swarms
// alone (positions, velocities), with per-world seeds and parameters (a
// weight, the repulsion radius, the noise's seed, the fixed centre), with
// the swarm centre (each world's own) and with a fixed one; a checkpoint
// resumes them bitwise; bad input gets a status naming the parameter and
// world and changes nothing.  Keypoints are one curve for every world, each
// world's agents keeping their goals (compared too, and resumed).
#include <gtest/gtest.h>

#include <algorithm>
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
constexpr uint32_t kAgents = 203;  // not a multiple of any lane count
const uint64_t kSeeds[kWorlds] = {5, 17, 29, 0x9876543210ull};

// Per world: w_cos, d_rep (m), w_dir, noise.seed, the fixed centre's x.
// d_rep 0.02-0.06 m in a 0.6 m cube of 203 agents: each agent repels
// several neighbours, so the sums' order matters.
const double kWCos[kWorlds] = {0.05, 0.5, 0.0, 1.0};
const double kDRep[kWorlds] = {0.04, 0.02, 0.06, 0.05};
const double kWDir[kWorlds] = {1.0, 0.5, 2.0, 1.5};
const double kNoiseSeed[kWorlds] = {1, 2, 3, 4000000000.0};
const double kCentreX[kWorlds] = {0.0, 0.1, -0.2, 0.05};
// A loop of keypoints in the 0.6 m cube, reached within 0.12 m (f_CD,
// Eq. 15; the user weight makes it count): goals move within a few steps.
const float kKeypoints[12] = {0.2f, 0, 0, 0, 0.2f, 0, -0.2f, 0, 0, 0, -0.2f, 0};

class EnergyWorlds : public worlds_test::WorldsFixture {
protected:
    void SetUp() override {
        WorldsFixture::SetUp();
        swcl_dataset_desc dd = swcl_dataset_desc_default();  // shared by every world and swarm
        ASSERT_EQ(swcl_dataset_synthetic(&dd, &data_), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override {
        destroy_swarms();
        swcl_dataset_destroy(data_);
        WorldsFixture::TearDown();
    }
    static swcl_swarm_desc desc(uint32_t worlds, uint64_t seed, const uint64_t* seeds) {
        return cube_desc(worlds, seed, seeds, kAgents, 256, 0.3f, 0.2f, 0.01f);
    }
    static swcl_energy_model_desc model(uint32_t k, bool fixed, bool keypoints = false) {
        swcl_energy_model_desc m = swcl_energy_model_desc_default();
        if (keypoints) {
            m.keypoints = kKeypoints;
            m.keypoint_count = 4;
            m.keypoint_reach = 0.12f;
            m.weights.user = 2.0f;
        }
        m.weights.cos = float(kWCos[k]);
        m.d_rep = float(kDRep[k]);
        m.weights.dir = float(kWDir[k]);
        m.noise.seed = uint64_t(kNoiseSeed[k]);
        m.has_fixed_centre = fixed ? 1 : 0;
        m.fixed_centre[0] = float(kCentreX[k]);
        m.fixed_centre[1] = 0.05f;
        return m;
    }
    swcl_swarm ensemble(bool fixed, bool keypoints = false) {
        swcl_swarm s = make(in_own_domains(desc(kWorlds, 0, kSeeds)));
        const swcl_energy_model_desc m0 = model(0, fixed, keypoints);
        EXPECT_EQ(swcl_swarm_energy_set_model(s, data_, &m0), SWCL_OK) << swcl_last_error();
        set(s, "weights.cos", kWCos, kWorlds);
        set(s, "d_rep", kDRep, kWorlds);
        set(s, "weights.dir", kWDir, kWorlds);
        set(s, "noise.seed", kNoiseSeed, kWorlds);
        std::vector<double> centre;
        for (uint32_t k = 0; k < kWorlds; ++k) centre.insert(centre.end(), {kCentreX[k], 0.05, 0.0});
        set(s, "centre", centre.data(), centre.size());
        return s;
    }
    swcl_swarm alone(uint32_t k, bool fixed, bool keypoints = false) {
        swcl_swarm s = make(in_own_domains(desc(1, kSeeds[k], nullptr), int(k)));
        const swcl_energy_model_desc m = model(k, fixed, keypoints);
        EXPECT_EQ(swcl_swarm_energy_set_model(s, data_, &m), SWCL_OK) << swcl_last_error();
        return s;
    }
    void check_bitwise(bool fixed, uint32_t steps, bool keypoints = false);
    static std::vector<int32_t> goals(swcl_swarm s, size_t count) {
        std::vector<int32_t> g(count);
        EXPECT_EQ(swcl_swarm_energy_get_goals(s, g.data(), count), SWCL_OK) << swcl_last_error();
        return g;
    }

    swcl_dataset data_{};
};

void EnergyWorlds::check_bitwise(bool fixed, uint32_t steps, bool keypoints) {
    const size_t total = size_t(kWorlds) * kAgents;
    swcl_swarm all = ensemble(fixed, keypoints);
    ASSERT_EQ(swcl_swarm_step(all, steps), SWCL_OK) << swcl_last_error();
    const std::vector<float> pos = read(all, SWCL_ATTRIBUTE_POSITION, total);
    const std::vector<float> vel = read(all, SWCL_ATTRIBUTE_VELOCITY, total);
    const std::vector<int32_t> goal = goals(all, total);
    std::vector<int32_t> seen;
    for (uint32_t k = 0; k < kWorlds; ++k) {
        swcl_swarm one = alone(k, fixed, keypoints);
        ASSERT_EQ(swcl_swarm_step(one, steps), SWCL_OK) << swcl_last_error();
        expect_world_equal(pos, read(one, SWCL_ATTRIBUTE_POSITION, kAgents), k, kWorlds, "positions");
        expect_world_equal(vel, read(one, SWCL_ATTRIBUTE_VELOCITY, kAgents), k, kWorlds, "velocities");
        const std::vector<int32_t> g = goals(one, kAgents);
        expect_world_equal(goal, g, k, kWorlds, "keypoint goals");
        seen.insert(seen.end(), g.begin(), g.end());
    }
    if (keypoints) {  // the goals moved on from their first keypoint in some agents
        std::sort(seen.begin(), seen.end());
        EXPECT_GE(std::unique(seen.begin(), seen.end()) - seen.begin(), 3);
    }
    // The worlds are not copies of one another.
    EXPECT_NE(std::memcmp(pos.data(), pos.data() + 3 * kAgents, 3 * size_t(kAgents) * sizeof(float)), 0);
}

}  // namespace

TEST_F(EnergyWorlds, WorldsAreBitwiseTheSwarmsAloneWithTheSwarmCentre) { check_bitwise(false, 20); }
TEST_F(EnergyWorlds, WorldsAreBitwiseTheSwarmsAloneWithAFixedCentre) { check_bitwise(true, 20); }
TEST_F(EnergyWorlds, WorldsWithKeypointsAreBitwiseTheSwarmsAlone) { check_bitwise(false, 20, true); }
// Each world in a box of its own (placement, grid).
TEST_F(EnergyWorlds, WorldsOfTheirOwnDomainsAreBitwiseTheSwarmsAlone) {
    boxes_ = own_domains(kWorlds, 0.3f);
    check_bitwise(false, 20);
}

TEST_F(EnergyWorlds, ACheckpointResumesBitwise) {
    const size_t total = size_t(kWorlds) * kAgents;
    swcl_swarm straight = ensemble(false, true);
    ASSERT_EQ(swcl_swarm_step(straight, 12), SWCL_OK) << swcl_last_error();
    swcl_swarm first = ensemble(false, true);
    ASSERT_EQ(swcl_swarm_step(first, 5), SWCL_OK) << swcl_last_error();
    const std::string path = ::testing::TempDir() + "swarmcl_energy_worlds_checkpoint.swcl";
    ASSERT_EQ(swcl_swarm_save(first, path.c_str()), SWCL_OK) << swcl_last_error();
    swcl_swarm resumed{};
    ASSERT_EQ(swcl_swarm_load(ctx_, path.c_str(), &resumed), SWCL_OK) << swcl_last_error();
    swarms_.push_back(resumed);
    std::remove(path.c_str());
    std::vector<double> d_rep(kWorlds);
    ASSERT_EQ(swcl_swarm_get_world_param(resumed, "d_rep", d_rep.data(), kWorlds, nullptr), SWCL_OK)
        << swcl_last_error();
    for (uint32_t k = 0; k < kWorlds; ++k) EXPECT_EQ(float(d_rep[k]), float(kDRep[k]));
    ASSERT_EQ(swcl_swarm_step(resumed, 7), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(read(resumed, SWCL_ATTRIBUTE_POSITION, total), read(straight, SWCL_ATTRIBUTE_POSITION, total));
    EXPECT_EQ(read(resumed, SWCL_ATTRIBUTE_VELOCITY, total), read(straight, SWCL_ATTRIBUTE_VELOCITY, total));
    EXPECT_EQ(goals(resumed, total), goals(straight, total));
}

TEST_F(EnergyWorlds, BadInputNamesTheParameterAndWorldAndChangesNothing) {
    swcl_swarm all = ensemble(false);
    const auto expect_error = [&](const char* name, const std::vector<double>& v, const char* says) {
        EXPECT_EQ(swcl_swarm_set_world_param(all, name, v.data(), v.size()), SWCL_ERROR_INVALID_ARGUMENT) << name;
        EXPECT_NE(std::string(swcl_last_error()).find(says), std::string::npos) << swcl_last_error();
    };
    expect_error("d_rep", {0.01, 0.02, 0.03}, "3 values given for 4 worlds");
    expect_error("d_rep", {0.01, 0.02, std::nan(""), 0.03}, "in world 2");
    expect_error("weights.cos", {1.0, 1.0, 1.0, -1.0}, "in world 3");
    expect_error("rho", {2.5, 0.0, 2.5, 2.5}, "in world 1");
    // What the table's rows cannot say: d_rep <= d_att1 (0.1), per world.
    expect_error("d_rep", {0.04, 0.04, 0.5, 0.04}, "world 2");
    // What selects the kernels, or is used once for every world.
    expect_error("span", {1, 1, 2, 1}, "span cannot differ between worlds");
    expect_error("keep_out", {1, 0, 1, 1}, "keep_out cannot differ between worlds");
    expect_error("has_fixed_centre", {0, 0, 0, 1}, "has_fixed_centre cannot differ between worlds");
    expect_error("accel_time", {0, 0.02, 0, 0}, "accel_time cannot differ between worlds");
    expect_error("noise.type", {0, 1, 0, 0}, "selects the noise kernel");
    expect_error("no_such_parameter", {1, 2, 3, 4}, "no parameter 'no_such_parameter'");
    // Nothing half-applied.
    std::vector<double> d_rep(kWorlds), w_cos(kWorlds);
    ASSERT_EQ(swcl_swarm_get_world_param(all, "d_rep", d_rep.data(), kWorlds, nullptr), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_get_world_param(all, "weights.cos", w_cos.data(), kWorlds, nullptr), SWCL_OK);
    for (uint32_t k = 0; k < kWorlds; ++k) {
        EXPECT_EQ(float(d_rep[k]), float(kDRep[k]));
        EXPECT_EQ(float(w_cos[k]), float(kWCos[k]));
    }
    // The same value in every world is fine for a shared parameter.
    const double same[kWorlds] = {2, 2, 2, 2};
    set(all, "span", same, kWorlds);
    set(all, "span", std::vector<double>(kWorlds, 1.0).data(), kWorlds);

    // Keypoints set on a running swarm of worlds: every world's goals start
    // over; a bad curve or a goals buffer of one world's size is refused.
    const float kp[9] = {0.2f, 0, 0, 0, 0.2f, 0, -0.2f, 0, 0};
    EXPECT_EQ(swcl_swarm_energy_set_keypoints(all, kp, 3, 1), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(all, 2), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(swcl_swarm_energy_set_keypoints(all, kp, 1, 1), SWCL_ERROR_INVALID_ARGUMENT);
    std::vector<int32_t> one_world(kAgents);
    EXPECT_EQ(swcl_swarm_energy_get_goals(all, one_world.data(), kAgents), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("all its worlds"), std::string::npos) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(all, 2), SWCL_OK) << swcl_last_error();
}
