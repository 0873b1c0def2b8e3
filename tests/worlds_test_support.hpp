// Shared by the tests of swarms of worlds (test_worlds, test_force_worlds,
// test_energy_worlds): a context and the swarms a test makes (destroyed
// after it), a descriptor of W worlds in a cube, reads and per-world
// parameters through the C API, and the byte-for-byte comparison of one
// world with its swarm alone.
#pragma once
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

#include "swarmcl/swarmcl.h"

namespace worlds_test {

class WorldsFixture : public ::testing::Test {
protected:
    void SetUp() override {
        swcl_context_desc d = swcl_context_desc_default();
        ASSERT_EQ(swcl_context_create(&d, &ctx_), SWCL_OK) << swcl_last_error();
    }
    void TearDown() override {
        destroy_swarms();
        swcl_context_destroy(ctx_);
    }
    void destroy_swarms() {
        for (swcl_swarm s : swarms_) swcl_swarm_destroy(s);
        swarms_.clear();
    }
    // `worlds` worlds of `agents` agents in [-half, half]^3 (seeds: NULL for
    // seed + k).
    static swcl_swarm_desc cube_desc(uint32_t worlds, uint64_t seed, const uint64_t* seeds, uint32_t agents,
                                     uint32_t capacity, float half, float radius, float dt) {
        swcl_swarm_desc d = swcl_swarm_desc_default();
        d.capacity = capacity;
        d.agent_count = agents;
        d.seed = seed;
        for (int a = 0; a < 3; ++a) {
            d.domain_min[a] = -half;
            d.domain_max[a] = half;
        }
        d.interaction_radius = radius;
        d.dt = dt;
        d.worlds = worlds;
        d.world_seeds = seeds;
        return d;
    }
    // Boxes of their own for `worlds` worlds (6 floats each: min xyz, max
    // xyz) around [-half, half]^3, each of another size, shape and place, so
    // each world's grid differs in origin, cell edge and cells per axis.
    static std::vector<float> own_domains(uint32_t worlds, float half) {
        std::vector<float> boxes;
        for (uint32_t k = 0; k < worlds; ++k) {
            for (int a = 0; a < 3; ++a) boxes.push_back(-half * (1.0f + 0.25f * float((k + a) % 3)) + 0.1f * half * k);
            for (int a = 0; a < 3; ++a) boxes.push_back(half * (0.6f + 0.5f * float((2 * k + a) % 3)) + 0.1f * half * k);
        }
        return boxes;
    }
    // With boxes_ set (own_domains): an ensemble's descriptor (world = -1)
    // gets every world's box, world k's swarm alone box k as its domain.
    swcl_swarm_desc in_own_domains(swcl_swarm_desc d, int world = -1) const {
        if (boxes_.empty()) return d;
        if (world < 0) {
            d.world_domains = boxes_.data();
            return d;
        }
        for (int a = 0; a < 3; ++a) {
            d.domain_min[a] = boxes_[6 * size_t(world) + a];
            d.domain_max[a] = boxes_[6 * size_t(world) + 3 + a];
        }
        return d;
    }
    swcl_swarm make(const swcl_swarm_desc& d) {
        swcl_swarm s{};
        EXPECT_EQ(swcl_swarm_create(ctx_, &d, &s), SWCL_OK) << swcl_last_error();
        swarms_.push_back(s);
        return s;
    }
    static void set(swcl_swarm s, const char* name, const double* v, size_t count) {
        ASSERT_EQ(swcl_swarm_set_world_param(s, name, v, count), SWCL_OK) << swcl_last_error();
    }
    static std::vector<float> read(swcl_swarm s, swcl_attribute a, size_t agents) {
        std::vector<float> out(3 * agents);
        EXPECT_EQ(swcl_swarm_read(s, a, out.data(), agents), SWCL_OK) << swcl_last_error();
        return out;
    }
    // `first` stepped `before` steps, saved to `file` (under the test's
    // temporary folder), loaded and stepped `after` more must be bitwise
    // `straight` stepped before + after at once: positions, velocities and
    // each world's MDE and step counts.  Returns the loaded swarm (destroyed with the
    // test's others) for the caller's checks of what it holds.
    swcl_swarm expect_checkpoint_resumes(swcl_swarm straight, swcl_swarm first, uint32_t worlds, uint32_t n,
                                         uint32_t before, uint32_t after, const char* file) {
        const size_t total = size_t(worlds) * n;
        EXPECT_EQ(swcl_swarm_step(straight, before + after), SWCL_OK) << swcl_last_error();
        EXPECT_EQ(swcl_swarm_step(first, before), SWCL_OK) << swcl_last_error();
        const std::string path = ::testing::TempDir() + file;
        EXPECT_EQ(swcl_swarm_save(first, path.c_str()), SWCL_OK) << swcl_last_error();
        swcl_swarm resumed{};
        EXPECT_EQ(swcl_swarm_load(ctx_, path.c_str(), &resumed), SWCL_OK) << swcl_last_error();
        swarms_.push_back(resumed);
        std::remove(path.c_str());
        EXPECT_EQ(swcl_swarm_step(resumed, after), SWCL_OK) << swcl_last_error();
        EXPECT_EQ(read(resumed, SWCL_ATTRIBUTE_POSITION, total), read(straight, SWCL_ATTRIBUTE_POSITION, total));
        EXPECT_EQ(read(resumed, SWCL_ATTRIBUTE_VELOCITY, total), read(straight, SWCL_ATTRIBUTE_VELOCITY, total));
        std::vector<swcl_step_stats> a(worlds), b(worlds);
        for (uint32_t k = 0; k < worlds; ++k) a[k].struct_size = b[k].struct_size = sizeof(swcl_step_stats);
        EXPECT_EQ(swcl_swarm_take_world_step_stats(resumed, a.data(), worlds), SWCL_OK);
        EXPECT_EQ(swcl_swarm_take_world_step_stats(straight, b.data(), worlds), SWCL_OK);
        for (uint32_t k = 0; k < worlds; ++k) {
            EXPECT_EQ(a[k].mde_moved_total, b[k].mde_moved_total) << "world " << k;
            EXPECT_EQ(a[k].steps, b[k].steps) << "world " << k;
        }
        return resumed;
    }

    swcl_context ctx_{};
    std::vector<swcl_swarm> swarms_;
    std::vector<float> boxes_;  // in_own_domains
};

// Bitwise equality of world k's slice of `all` (`worlds` equal slices) with
// `one`, the same swarm run alone.
template <typename T>
void expect_world_equal(const std::vector<T>& all, const std::vector<T>& one, uint32_t k, uint32_t worlds,
                        const char* what) {
    ASSERT_EQ(all.size() % worlds, 0u);
    const size_t per = all.size() / worlds;
    ASSERT_EQ(per, one.size());
    size_t differ = 0;
    for (size_t i = 0; i < per; ++i) differ += std::memcmp(&all[k * per + i], &one[i], sizeof(T)) != 0;
    EXPECT_EQ(differ, 0u) << what << " of world " << k << " differ from the swarm alone in " << differ << " of "
                          << per << " values";
}

// Steps `all` (`worlds` worlds of n agents) and each world's swarm alone
// (`alone(k)`) `steps` steps, and compares them byte for byte: positions,
// velocities and the step statistics, and checks that world 0 and world 1
// differ (their parameters and seeds do).  Returns the ensemble's step
// statistics per world (taken here), so a test can say where MDE acted.
inline std::vector<swcl_step_stats> expect_worlds_are_their_swarms_alone(
    swcl_swarm all, uint32_t worlds, uint32_t n, uint32_t steps, const std::function<swcl_swarm(uint32_t)>& alone) {
    const size_t total = size_t(worlds) * n;
    const auto read = [](swcl_swarm s, swcl_attribute a, size_t agents) {
        std::vector<float> out(3 * agents);
        EXPECT_EQ(swcl_swarm_read(s, a, out.data(), agents), SWCL_OK) << swcl_last_error();
        return out;
    };
    EXPECT_EQ(swcl_swarm_step(all, steps), SWCL_OK) << swcl_last_error();
    const std::vector<float> pos = read(all, SWCL_ATTRIBUTE_POSITION, total);
    const std::vector<float> vel = read(all, SWCL_ATTRIBUTE_VELOCITY, total);
    std::vector<swcl_step_stats> st(worlds);
    for (auto& s : st) s.struct_size = sizeof(swcl_step_stats);
    EXPECT_EQ(swcl_swarm_take_world_step_stats(all, st.data(), worlds), SWCL_OK) << swcl_last_error();
    for (uint32_t k = 0; k < worlds; ++k) {
        swcl_swarm one = alone(k);
        EXPECT_EQ(swcl_swarm_step(one, steps), SWCL_OK) << swcl_last_error();
        expect_world_equal(pos, read(one, SWCL_ATTRIBUTE_POSITION, n), k, worlds, "positions");
        expect_world_equal(vel, read(one, SWCL_ATTRIBUTE_VELOCITY, n), k, worlds, "velocities");
        swcl_step_stats s1{};
        s1.struct_size = sizeof(s1);
        EXPECT_EQ(swcl_swarm_take_step_stats(one, &s1), SWCL_OK);
        EXPECT_EQ(st[k].mde_moved_total, s1.mde_moved_total) << "world " << k;
        EXPECT_EQ(st[k].mde_moved_last, s1.mde_moved_last) << "world " << k;
        EXPECT_EQ(st[k].steps, s1.steps) << "world " << k;
    }
    EXPECT_NE(std::memcmp(pos.data(), pos.data() + 3 * size_t(n), 3 * size_t(n) * sizeof(float)), 0);
    return st;
}

}  // namespace worlds_test
