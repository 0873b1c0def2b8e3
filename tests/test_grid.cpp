// The grid build (kernels/grid.cl) against a host counting sort: cell keys,
// cell ranges, order by (cell, agent id), the id <-> slot maps, bitwise
// determinism, and the awkward inputs (outside the domain, one crowded cell,
// duplicates, N = 0 and N = 1).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>
#include <string>

#include "spatial/neighbor_grid.hpp"
#include "test_support.hpp"

using namespace swarmcl;
using namespace swarmcl::test;

namespace {

struct GridSnapshot {
    std::vector<cl_float4> pos;
    std::vector<cl_uint> ids, slot_of, start;
};

GridSnapshot build_and_read(Swarm& swarm) {
    swarm.ensure_grid();
    auto& ctx = swarm.context();
    const uint32_t n = swarm.agent_count();
    GridSnapshot s;
    s.pos.resize(n);
    s.ids.resize(n);
    s.slot_of.resize(n);
    s.start.resize(size_t(swarm.grid().geometry().cell_count()) + 1);
    swarm.positions().download(ctx, s.pos.data(), n);
    swarm.ids().download(ctx, s.ids.data(), n);
    swarm.slot_of().download(ctx, s.slot_of.data(), n);
    swarm.grid().cell_start().download(ctx, s.start.data(), s.start.size());
    return s;
}

// Reference cell of a point: floor((x - origin) / cell), clamped per axis.
uint32_t reference_cell(const GridGeometry& g, const float* p) {
    uint32_t c[3];
    for (int a = 0; a < 3; ++a) {
        float f = std::floor((p[a] - g.origin[a]) * (1.0f / g.cell));
        f = std::min(std::max(f, 0.0f), float(g.dims[a] - 1));
        c[a] = uint32_t(f);
    }
    return c[0] + uint32_t(g.dims[0]) * (c[1] + uint32_t(g.dims[1]) * c[2]);
}

// Checks the device grid against a host counting sort of `xyz` by (cell, id).
void expect_matches_reference(Swarm& swarm, const std::vector<float>& xyz) {
    const uint32_t n = uint32_t(xyz.size() / 3);
    const auto& g = swarm.grid().geometry();
    const GridSnapshot s = build_and_read(swarm);
    std::vector<uint32_t> order(n), cell(n);
    for (uint32_t i = 0; i < n; ++i) cell[i] = reference_cell(g, &xyz[3 * i]);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return cell[a] < cell[b]; });
    ASSERT_EQ(s.ids.size(), n);
    for (uint32_t slot = 0; slot < n; ++slot) {
        ASSERT_EQ(s.ids[slot], order[slot]) << "slot " << slot;
        ASSERT_EQ(s.slot_of[order[slot]], slot);
        for (int a = 0; a < 3; ++a) ASSERT_EQ(s.pos[slot].s[a], xyz[3 * order[slot] + a]);
    }
    std::vector<uint32_t> start(g.cell_count() + 1, 0);
    for (uint32_t i = 0; i < n; ++i) start[cell[i] + 1]++;
    std::partial_sum(start.begin(), start.end(), start.begin());
    ASSERT_EQ(s.start, start);
}

TEST(Grid, RandomPointsMatchHostCountingSort) {
    auto ctx = shared_context();
    const auto xyz = random_points(20000, -5.0f, 5.0f, 1);
    Swarm swarm(ctx, cube_config(20000, -5.0f, 5.0f, 0.4f));
    swarm.write(Attribute::Position, xyz.data(), 20000);
    expect_matches_reference(swarm, xyz);
}

// Builds after a history, so the state is in the last build's order and ids
// are not in slot order: half the agents moved a little (movers and stayers
// interleaved in every chunk, each cell's movers from several old cells, so
// in no id order; the merge's and the compaction's branch-free loops), one
// in 40 (their loops for few movers), then every agent (all movers, runs of
// every length up to a 40-agent cell: the short runs' rank sort and the
// longer runs' sort).
TEST(Grid, MovedAgentsMatchHostCountingSort) {
    auto ctx = shared_context();
    const uint32_t n = 30001;  // the merge's last work-item gets an odd count
    auto xyz = random_points(n, 0.0f, 4.0f, 21);
    Swarm swarm(ctx, cube_config(n, 0.0f, 4.0f, 0.2f));
    swarm.write(Attribute::Position, xyz.data(), n);
    expect_matches_reference(swarm, xyz);
    std::mt19937 rng(22);
    std::uniform_real_distribution<float> jitter(-0.08f, 0.08f);
    for (const uint32_t every : {2u, 2u, 40u}) {
        for (uint32_t i = 0; i < n; i += every)
            for (int a = 0; a < 3; ++a) xyz[3 * i + a] = std::clamp(xyz[3 * i + a] + jitter(rng), 0.0f, 3.999f);
        swarm.write(Attribute::Position, xyz.data(), n);
        expect_matches_reference(swarm, xyz);
    }
    auto fresh = random_points(n, 0.0f, 4.0f, 23);
    for (uint32_t i = 0; i < 40; ++i)  // one crowded cell
        for (int a = 0; a < 3; ++a) fresh[3 * (i * 701) + a] = 1.01f + 0.001f * float(i % 7);
    swarm.write(Attribute::Position, fresh.data(), n);
    expect_matches_reference(swarm, fresh);
}

TEST(Grid, AgentsOutsideTheDomainAreClampedIntoBorderCells) {
    auto ctx = shared_context();
    auto xyz = random_points(3000, -20.0f, 20.0f, 2);
    xyz[0] = 1e30f;  // far outside: clamping must not overflow
    xyz[4] = -1e30f;
    Swarm swarm(ctx, cube_config(3000, -1.0f, 1.0f, 0.25f));
    swarm.write(Attribute::Position, xyz.data(), 3000);
    expect_matches_reference(swarm, xyz);
}

TEST(Grid, AllAgentsInOneCellAndDuplicates) {
    auto ctx = shared_context();
    // 5000 agents in one cell (heap-sort path), half of them on one point.
    auto xyz = random_points(5000, 0.01f, 0.09f, 3);
    for (size_t i = 0; i < xyz.size() / 2; ++i) xyz[i] = 0.05f;
    Swarm swarm(ctx, cube_config(5000, 0.0f, 1.0f, 0.1f));
    swarm.write(Attribute::Position, xyz.data(), 5000);
    expect_matches_reference(swarm, xyz);
}

TEST(Grid, EmptyAndSingleAgentSwarms) {
    auto ctx = shared_context();
    Swarm swarm(ctx, cube_config(4, 0.0f, 1.0f, 0.1f));
    std::vector<float> none;
    swarm.write(Attribute::Position, none.data(), 0);
    expect_matches_reference(swarm, none);
    const std::vector<float> one = {0.5f, 0.5f, 0.5f};
    swarm.write(Attribute::Position, one.data(), 1);
    expect_matches_reference(swarm, one);
}

TEST(Grid, OrderIsBitwiseTheSameOnEveryRunAndIndependentOfHistory) {
    auto ctx = shared_context();
    const auto xyz = random_points(50000, 0.0f, 4.0f, 4);
    Swarm a(ctx, cube_config(50000, 0.0f, 4.0f, 0.2f));
    Swarm b(ctx, cube_config(50000, 0.0f, 4.0f, 0.2f));
    a.write(Attribute::Position, xyz.data(), 50000);
    // b reaches the same positions by another history: shuffled first.
    auto other = random_points(50000, 0.0f, 4.0f, 5);
    b.write(Attribute::Position, other.data(), 50000);
    b.ensure_grid();
    b.write(Attribute::Position, xyz.data(), 50000);
    const auto sa = build_and_read(a), sb = build_and_read(b);
    EXPECT_EQ(sa.ids, sb.ids);
    EXPECT_EQ(sa.start, sb.start);
    EXPECT_EQ(0, std::memcmp(sa.pos.data(), sb.pos.data(), sa.pos.size() * sizeof(cl_float4)));
}

TEST(Grid, ReorderKeepsEachAgentsVelocityWithIt) {
    auto ctx = shared_context();
    const auto xyz = random_points(10000, 0.0f, 2.0f, 6);
    const auto vel = random_points(10000, -1.0f, 1.0f, 7);
    Swarm swarm(ctx, cube_config(10000, 0.0f, 2.0f, 0.1f));
    swarm.write(Attribute::Position, xyz.data(), 10000);
    swarm.write(Attribute::Velocity, vel.data(), 10000);
    swarm.ensure_grid();
    std::vector<float> p(xyz.size()), v(vel.size());
    swarm.read(Attribute::Position, p.data(), 10000);
    swarm.read(Attribute::Velocity, v.data(), 10000);
    EXPECT_EQ(p, xyz);
    EXPECT_EQ(v, vel);
}

// permute_state moves positions, velocities and ids by the build's
// permutation, every slot and nothing else: x_out[s] = x[perm[s]] bitwise.
// The CPU profile copies chunks of slots with prefetches ahead (one chunk of
// 1 or 255 slots, 7 chunks of 286 at 2,000); the GPU profile
// (gpu_profile.) one slot a work-item.  The scratch arrays start as NaN so a
// slot left unwritten shows.
TEST(Grid, PermuteStateMovesEveryArrayByThePermutation) {
    auto ctx = shared_context();
    for (const uint32_t n : {1u, 255u, 2000u}) {
        SCOPED_TRACE("n = " + std::to_string(n));
        const auto xyz = random_points(n, 0.0f, 4.0f, 11 + n), uvw = random_points(n, -1.0f, 1.0f, 12 + n);
        std::vector<cl_float4> pos(n), vel(n);
        std::vector<cl_uint> ids(n);
        for (uint32_t s = 0; s < n; ++s) {
            pos[s] = cl_float4{{xyz[3 * s], xyz[3 * s + 1], xyz[3 * s + 2], float(s)}};
            vel[s] = cl_float4{{uvw[3 * s], uvw[3 * s + 1], uvw[3 * s + 2], -float(s)}};
            ids[s] = (s * 7919u) % n;  // a permutation of 0..n-1 (7919 is prime)
        }
        const float lo[3] = {0, 0, 0}, hi[3] = {4, 4, 4};
        NeighborGrid grid(*ctx, GridGeometry::cover(lo, hi, 0.25f, 1u << 12), n);
        DeviceBuffer<cl_float4> p(*ctx, n, "p"), v(*ctx, n, "v"), po(*ctx, n, "po"), vo(*ctx, n, "vo");
        DeviceBuffer<cl_uint> id(*ctx, n, "id"), io(*ctx, n, "io");
        p.upload(*ctx, pos.data(), n);
        v.upload(*ctx, vel.data(), n);
        id.upload(*ctx, ids.data(), n);
        const float nan = std::nanf("");
        const std::vector<cl_float4> nans(n, cl_float4{{nan, nan, nan, nan}});
        const std::vector<cl_uint> ones(n, 0xFFFFFFFFu);
        po.upload(*ctx, nans.data(), n);
        vo.upload(*ctx, nans.data(), n);
        io.upload(*ctx, ones.data(), n);
        grid.build(p, id, n);
        grid.permute_state(p, v, id, po, vo, io, n);
        std::vector<cl_uint> perm(n), ids_out(n);
        std::vector<cl_float4> pos_out(n), vel_out(n);
        grid.permutation().download(*ctx, perm.data(), n);
        po.download(*ctx, pos_out.data(), n);
        vo.download(*ctx, vel_out.data(), n);
        io.download(*ctx, ids_out.data(), n);
        std::vector<cl_uint> sorted = perm;
        std::sort(sorted.begin(), sorted.end());
        for (uint32_t s = 0; s < n; ++s) ASSERT_EQ(sorted[s], s);
        for (uint32_t s = 0; s < n; ++s) {
            const uint32_t q = perm[s];
            ASSERT_EQ(std::memcmp(&pos_out[s], &pos[q], sizeof(cl_float4)), 0) << "slot " << s;
            ASSERT_EQ(std::memcmp(&vel_out[s], &vel[q], sizeof(cl_float4)), 0) << "slot " << s;
            ASSERT_EQ(ids_out[s], ids[q]) << "slot " << s;
        }
        if (n > 1) EXPECT_NE(perm, sorted);  // the build did reorder them
    }
}

// One build of `pos` (slot order, ids a permutation per world) by the
// NeighborGrid `grid`: its permutation and cell starts.
std::pair<std::vector<cl_uint>, std::vector<cl_uint>> build_grid(Context& ctx, NeighborGrid& grid,
                                                                 const std::vector<cl_float4>& pos,
                                                                 const std::vector<cl_uint>& ids,
                                                                 uint32_t world_agents, uint32_t ncells) {
    const uint32_t n = uint32_t(pos.size());
    DeviceBuffer<cl_float4> p(ctx, n, "positions");
    DeviceBuffer<cl_uint> id(ctx, n, "ids");
    p.upload(ctx, pos.data(), n);
    id.upload(ctx, ids.data(), n);
    grid.build(p, id, n, world_agents);
    std::vector<cl_uint> perm(n), start(size_t(ncells) + 1);
    grid.permutation().download(ctx, perm.data(), n);
    grid.cell_start().download(ctx, start.data(), start.size());
    return {perm, start};
}

// A state on the device: positions, velocities (the positions again) and
// ids, and the reorder's outputs.
struct StateBuffers {
    StateBuffers(Context& ctx, const std::vector<cl_float4>& pos, const std::vector<cl_uint>& ids)
        : n(pos.size()), p(ctx, n, "p"), v(ctx, n, "v"), po(ctx, n, "po"), vo(ctx, n, "vo"), id(ctx, n, "id"),
          io(ctx, n, "io") {
        p.upload(ctx, pos.data(), n);
        v.upload(ctx, pos.data(), n);
        id.upload(ctx, ids.data(), n);
    }
    size_t n;
    DeviceBuffer<cl_float4> p, v, po, vo;
    DeviceBuffer<cl_uint> id, io;
};

// The counting sort (the GPU default) and the chunked sort of the movers
// (the CPU default), its movers in buckets (the CPU default) or by the radix
// sort, build the same grid, bitwise: three worlds of their own
// geometry, agents outside the domain, a crowded cell (the heap sort), and a
// second build after a step-like reorder and moves (the chunked sort then
// sorts only the movers).
TEST(Grid, CountingAndChunkedSortsBuildTheSameGrid) {
    auto ctx = shared_context();
    const uint32_t per_world = 1201, worlds = 3, n = per_world * worlds;
    std::vector<GridGeometry> geo;
    for (uint32_t w = 0; w < worlds; ++w) {
        const float lo[3] = {-1.0f - w, 0.0f, 2.0f * w}, hi[3] = {1.0f + w, 1.5f, 2.0f * w + 1.0f};
        geo.push_back(GridGeometry::cover(lo, hi, 0.1f + 0.05f * w, 1u << 16));
    }
    uint32_t ncells = 0;
    for (const auto& g : geo) ncells += g.cell_count();
    std::vector<cl_float4> pos(n);
    std::vector<cl_uint> ids(n);
    const auto xyz = random_points(n, -3.0f, 6.0f, 11);
    for (uint32_t s = 0; s < n; ++s) {
        pos[s] = cl_float4{{xyz[3 * s], xyz[3 * s + 1], xyz[3 * s + 2], 0.0f}};
        if (s % per_world < 100) pos[s] = cl_float4{{0.01f, 0.01f, 2.0f * (s / per_world) + 0.01f, 0.0f}};
        ids[s] = per_world - 1 - s % per_world;  // reversed in each world
    }
    // The chunked path with each sort of its movers: the buckets and the
    // radix sort.
    NeighborGrid counting(*ctx, geo, n), chunked(*ctx, geo, n), radix(*ctx, geo, n);
    if (!counting.use_counting_sort(true)) GTEST_SKIP() << "the device cannot run the scan's work-groups";
    chunked.use_counting_sort(false);
    radix.use_counting_sort(false);
    ASSERT_TRUE(counting.counting_sort());
    ASSERT_FALSE(chunked.counting_sort());
    ASSERT_TRUE(chunked.use_bucket_sort(true));
    ASSERT_FALSE(radix.use_bucket_sort(false));
    const auto a = build_grid(*ctx, counting, pos, ids, per_world, ncells);
    const auto b = build_grid(*ctx, chunked, pos, ids, per_world, ncells);
    EXPECT_EQ(a.first, b.first);
    EXPECT_EQ(a.second, b.second);
    const auto r = build_grid(*ctx, radix, pos, ids, per_world, ncells);
    EXPECT_EQ(a.first, r.first);
    EXPECT_EQ(a.second, r.second);
    // A permutation that keeps every agent in its world's slots.
    std::vector<cl_uint> sorted = a.first;
    std::sort(sorted.begin(), sorted.end());
    for (uint32_t d = 0; d < n; ++d) {
        ASSERT_EQ(sorted[d], d);
        ASSERT_EQ(a.first[d] / per_world, d / per_world) << d;
    }

    // Reorder by the build (each grid its own layout), move a tenth of the
    // agents, build again.
    std::vector<cl_float4> pos2(n);
    std::vector<cl_uint> ids2(n);
    for (uint32_t d = 0; d < n; ++d) {
        pos2[d] = pos[a.first[d]];
        ids2[d] = ids[a.first[d]];
        if (d % 10 == 3) pos2[d].s[0] += 0.37f;
    }
    for (NeighborGrid* g : {&counting, &chunked, &radix}) {
        StateBuffers st(*ctx, pos, ids);
        g->build(st.p, st.id, n, per_world);
        g->reorder_state(st.p, st.v, st.id, st.po, st.vo, st.io, n);
    }
    const auto c = build_grid(*ctx, counting, pos2, ids2, per_world, ncells);
    const auto e = build_grid(*ctx, chunked, pos2, ids2, per_world, ncells);
    EXPECT_EQ(c.first, e.first);
    EXPECT_EQ(c.second, e.second);
    const auto f = build_grid(*ctx, radix, pos2, ids2, per_world, ncells);
    EXPECT_EQ(c.first, f.first);
    EXPECT_EQ(c.second, f.second);
    EXPECT_NE(c.first, a.first);  // the moves changed the order
    // Each reorders the state by that build: a tenth moved, so the chunked
    // paths gather the ids (kernels/grid.cl, ids_from_build), the counting
    // sort copies its own.
    for (NeighborGrid* g : {&counting, &chunked, &radix}) {
        StateBuffers st(*ctx, pos2, ids2);
        g->permute_state(st.p, st.v, st.id, st.po, st.vo, st.io, n);
        std::vector<cl_uint> ids_out(n);
        std::vector<cl_float4> pos_out(n);
        st.io.download(*ctx, ids_out.data(), n);
        st.vo.download(*ctx, pos_out.data(), n);
        for (uint32_t d = 0; d < n; ++d) {
            ASSERT_EQ(ids_out[d], ids2[c.first[d]]) << d;
            ASSERT_EQ(std::memcmp(&pos_out[d], &pos2[c.first[d]], sizeof(cl_float4)), 0) << d;
        }
    }
}

TEST(GridGeometry, CellCountIsBoundedByGrowingTheCell) {
    const float lo[3] = {0, 0, 0}, hi[3] = {1000, 1000, 1000};
    const auto g = GridGeometry::cover(lo, hi, 0.01f, 1u << 16);
    EXPECT_LE(g.cell_count(), 1u << 16);
    EXPECT_GE(g.cell, 0.01f);
    for (int a = 0; a < 3; ++a) EXPECT_GE(g.dims[a] * g.cell, 1000.0f * 0.999f);
}

}  // namespace
