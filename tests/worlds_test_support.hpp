// Shared by the tests of swarms of worlds (test_worlds, test_force_worlds,
// test_energy_worlds): a context and the swarms a test makes (destroyed
// after it), a descriptor of W worlds in a cube, reads and per-world
// parameters through the C API, and the byte-for-byte comparison of one
// world with its swarm alone.
#pragma once
#include <gtest/gtest.h>

#include <cstring>
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

    swcl_context ctx_{};
    std::vector<swcl_swarm> swarms_;
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

}  // namespace worlds_test
