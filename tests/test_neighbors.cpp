// Neighbour queries (kernels/neighbors.cl) against brute force over all
// pairs: counts within a radius, nearest neighbour (distance and id, ties to
// the lowest id), capped neighbour lists nearest-first with truncation.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "swarmcl/swarmcl.h"
#include "test_support.hpp"

using namespace swarmcl;
using namespace swarmcl::test;

namespace {

std::vector<uint32_t> brute_counts(const std::vector<float>& xyz, float r) {
    const size_t n = xyz.size() / 3;
    std::vector<uint32_t> out(n, 0);
    for (size_t i = 0; i < n; ++i)
        for (size_t j = 0; j < n; ++j)
            if (i != j && dist2(&xyz[3 * i], &xyz[3 * j]) <= r * r) out[i]++;
    return out;
}

struct Nearest { float d; uint32_t id; };

std::vector<Nearest> brute_nearest(const std::vector<float>& xyz) {
    const size_t n = xyz.size() / 3;
    std::vector<Nearest> out(n, {std::numeric_limits<float>::infinity(), SWCL_NO_AGENT});
    for (size_t i = 0; i < n; ++i) {
        float best = std::numeric_limits<float>::infinity();
        uint32_t id = SWCL_NO_AGENT;
        for (size_t j = 0; j < n; ++j) {
            if (i == j) continue;
            const float d2 = dist2(&xyz[3 * i], &xyz[3 * j]);
            if (d2 < best || (d2 == best && j < id)) { best = d2; id = uint32_t(j); }
        }
        out[i] = {id == SWCL_NO_AGENT ? best : std::sqrt(best), id};
    }
    return out;
}

// Each agent's neighbours within r, sorted by (distance, id), first `cap`.
std::vector<std::vector<uint32_t>> brute_lists(const std::vector<float>& xyz, float r, uint32_t cap) {
    const size_t n = xyz.size() / 3;
    std::vector<std::vector<uint32_t>> out(n);
    for (size_t i = 0; i < n; ++i) {
        std::vector<std::pair<float, uint32_t>> found;
        for (size_t j = 0; j < n; ++j) {
            const float d2 = dist2(&xyz[3 * i], &xyz[3 * j]);
            if (i != j && d2 <= r * r) found.emplace_back(d2, uint32_t(j));
        }
        std::sort(found.begin(), found.end());
        for (size_t k = 0; k < found.size() && k < cap; ++k) out[i].push_back(found[k].second);
    }
    return out;
}

void expect_queries_match(const std::vector<float>& xyz, SwarmConfig config, float radius, uint32_t cap) {
    const uint32_t n = uint32_t(xyz.size() / 3);
    config.capacity = std::max<uint32_t>(n, 1);
    Swarm swarm(shared_context(), config);
    swarm.write(Attribute::Position, xyz.data(), n);

    std::vector<uint32_t> counts(n);
    swarm.neighbor_count(radius, counts.data(), n);
    EXPECT_EQ(counts, brute_counts(xyz, radius)) << "counts, radius " << radius;

    std::vector<float> dist(n);
    std::vector<uint32_t> ids(n);
    swarm.nearest_neighbor(dist.data(), ids.data(), n);
    const auto ref = brute_nearest(xyz);
    for (uint32_t i = 0; i < n; ++i) {
        ASSERT_EQ(ids[i], ref[i].id) << "nearest of agent " << i;
        // OpenCL's sqrt may differ from the correctly rounded one by 3 ulp.
        if (std::isinf(ref[i].d))
            ASSERT_TRUE(std::isinf(dist[i]));
        else
            ASSERT_NEAR(dist[i], ref[i].d, 4e-7f * ref[i].d) << "nearest distance of agent " << i;
    }

    std::vector<uint32_t> lists(size_t(n) * cap), full(n);
    const uint32_t truncated = swarm.neighbor_lists(radius, cap, lists.data(), full.data(), n);
    const auto ref_lists = brute_lists(xyz, radius, cap);
    uint32_t ref_truncated = 0;
    for (uint32_t i = 0; i < n; ++i) {
        ASSERT_EQ(full[i], counts[i]);
        ref_truncated += counts[i] > cap;
        for (uint32_t k = 0; k < cap; ++k) {
            const uint32_t want = k < ref_lists[i].size() ? ref_lists[i][k] : SWCL_NO_AGENT;
            ASSERT_EQ(lists[size_t(i) * cap + k], want) << "agent " << i << " entry " << k;
        }
    }
    EXPECT_EQ(truncated, ref_truncated);
}

TEST(Neighbors, RandomPointsAgreeWithBruteForce) {
    expect_queries_match(random_points(3000, 0.0f, 3.0f, 11), cube_config(1, 0.0f, 3.0f, 0.3f), 0.3f, 8);
}

TEST(Neighbors, RadiusLargerAndSmallerThanTheCell) {
    const auto xyz = random_points(2000, -1.0f, 1.0f, 12);
    expect_queries_match(xyz, cube_config(1, -1.0f, 1.0f, 0.1f), 0.35f, 16);
    expect_queries_match(xyz, cube_config(1, -1.0f, 1.0f, 0.4f), 0.05f, 4);
}

TEST(Neighbors, AgentsOutsideTheDomain) {
    auto xyz = random_points(1500, -6.0f, 6.0f, 13);
    xyz[3] = 1e20f;
    expect_queries_match(xyz, cube_config(1, -1.0f, 1.0f, 0.2f), 0.5f, 6);
}

TEST(Neighbors, CrowdedCellWithDuplicatesAndTies) {
    // 600 agents on 3 exact points plus a few around: ties in distance are
    // broken by id, duplicates are neighbours at distance 0.
    auto xyz = random_points(800, 0.0f, 0.2f, 14);
    for (size_t i = 0; i < 600; ++i) {
        const float v = float(i % 3) * 0.05f;
        xyz[3 * i] = v; xyz[3 * i + 1] = v; xyz[3 * i + 2] = v;
    }
    expect_queries_match(xyz, cube_config(1, 0.0f, 1.0f, 0.5f), 0.1f, 5);
}

TEST(Neighbors, LatticeAtExactlyTheRadius) {
    // Points at spacing exactly r: neighbours at distance == r count.
    std::vector<float> xyz;
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 6; ++x) {
                xyz.push_back(x * 0.25f); xyz.push_back(y * 0.25f); xyz.push_back(z * 0.25f);
            }
    expect_queries_match(xyz, cube_config(1, 0.0f, 1.25f, 0.25f), 0.25f, 6);
}

TEST(Neighbors, SparseSwarmNearestSearchesFar) {
    // Two agents at opposite corners of a fine grid, and one lone agent.
    const std::vector<float> two = {0.01f, 0.01f, 0.01f, 9.99f, 9.99f, 9.99f};
    expect_queries_match(two, cube_config(1, 0.0f, 10.0f, 0.1f), 0.1f, 2);
    const std::vector<float> one = {1.0f, 2.0f, 3.0f};
    expect_queries_match(one, cube_config(1, 0.0f, 10.0f, 0.1f), 0.1f, 2);
    expect_queries_match({}, cube_config(1, 0.0f, 10.0f, 0.1f), 0.1f, 2);
}

// The count at 1, 8 and 16 slots a work-item (neighbor_count_w, the CPU
// devices' default, walks the union of its lanes' boxes but counts for each
// lane only the cells of its own): the brute force's counts at every width,
// with a radius above and below the cell, agents outside the domain, a
// count that is no multiple of the lanes, and points exactly at the radius.
TEST(Neighbors, CountsAtEveryWidthAreTheBruteForces) {
    struct Case {
        std::vector<float> xyz;
        SwarmConfig config;
        float radius;
    };
    std::vector<Case> cases;
    cases.push_back({random_points(1003, -1.0f, 1.0f, 21), cube_config(1, -1.0f, 1.0f, 0.1f), 0.35f});
    cases.push_back({random_points(1003, -1.0f, 1.0f, 22), cube_config(1, -1.0f, 1.0f, 0.4f), 0.05f});
    auto outside = random_points(777, -6.0f, 6.0f, 23);
    outside[3] = 1e20f;
    cases.push_back({outside, cube_config(1, -1.0f, 1.0f, 0.2f), 0.5f});
    std::vector<float> lattice;
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 6; ++x) lattice.insert(lattice.end(), {x * 0.25f, y * 0.25f, z * 0.25f});
    cases.push_back({lattice, cube_config(1, 0.0f, 1.25f, 0.25f), 0.25f});
    for (size_t c = 0; c < cases.size(); ++c) {
        const auto& k = cases[c];
        const uint32_t n = uint32_t(k.xyz.size() / 3);
        const auto want = brute_counts(k.xyz, k.radius);
        for (const uint32_t width : {1u, 8u, 16u}) {
            ScopedKernelWidth w(width);
            SwarmConfig config = k.config;
            config.capacity = n;
            Swarm swarm(shared_context(), config);
            swarm.write(Attribute::Position, k.xyz.data(), n);
            std::vector<uint32_t> counts(n);
            swarm.neighbor_count(k.radius, counts.data(), n);
            EXPECT_EQ(counts, want) << "case " << c << ", " << width << " lanes";
        }
    }
}

TEST(Neighbors, QueriesAreBitwiseRepeatable) {
    const auto xyz = random_points(20000, 0.0f, 2.0f, 15);
    std::vector<float> d1(20000), d2(20000);
    std::vector<uint32_t> l1(20000 * 4), l2(20000 * 4), c(20000);
    for (auto* out : {&d1, &d2}) {
        Swarm swarm(shared_context(), cube_config(20000, 0.0f, 2.0f, 0.1f));
        swarm.write(Attribute::Position, xyz.data(), 20000);
        swarm.nearest_neighbor(out->data(), nullptr, 20000);
        swarm.neighbor_lists(0.1f, 4, (out == &d1 ? l1 : l2).data(), c.data(), 20000);
    }
    EXPECT_EQ(0, std::memcmp(d1.data(), d2.data(), d1.size() * sizeof(float)));
    EXPECT_EQ(l1, l2);
}

}  // namespace
