// The point grid (spatial/point_grid.hpp, kernels/point_grid.cl) against a
// brute-force reference at cell sizes unlike any swarm's: the cell of every
// point, the sorted slots (stable: by slot within a cell), the cell ranges;
// with the geometry from the bounding box and given.  And the one radix sort
// (spatial/radix_sort.hpp): stable, with and without ids, over several
// passes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <numeric>
#include <random>
#include <string>

#include "spatial/point_grid.hpp"
#include "spatial/radix_sort.hpp"
#include "test_support.hpp"

using namespace swarmcl;
using namespace swarmcl::test;

namespace {

struct RawGeometry {
    float origin[3], inv_cell;
    int dims[3];
    uint32_t cells;
};

RawGeometry read_raw_geometry(Context& ctx, PointGrid& grid) {
    cl_float4 geo[2];
    grid.geometry().download(ctx, geo, 2);
    RawGeometry g;
    for (int a = 0; a < 3; ++a) {
        g.origin[a] = geo[0].s[a];
        std::memcpy(&g.dims[a], &geo[1].s[a], sizeof(int));
    }
    g.inv_cell = geo[0].s[3];
    std::memcpy(&g.cells, &geo[1].s[3], sizeof(uint32_t));
    return g;
}

// Reference cell: floor((x - origin) / cell) clamped to the grid, per axis.
uint32_t reference_cell(const RawGeometry& g, const float* p) {
    uint32_t c[3];
    for (int a = 0; a < 3; ++a) {
        float f = std::floor((p[a] - g.origin[a]) * g.inv_cell);
        f = std::min(std::max(f, 0.0f), float(g.dims[a] - 1));
        c[a] = uint32_t(f);
    }
    return c[0] + uint32_t(g.dims[0]) * (c[1] + uint32_t(g.dims[1]) * c[2]);
}

DeviceBuffer<cl_float4> upload_points(Context& ctx, const std::vector<float>& xyz) {
    const size_t n = xyz.size() / 3;
    std::vector<cl_float4> p(std::max<size_t>(n, 1));
    for (size_t i = 0; i < n; ++i) p[i] = cl_float4{{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], 0.0f}};
    DeviceBuffer<cl_float4> buf(ctx, p.size(), "test points");
    buf.upload(ctx, p.data(), p.size());
    return buf;
}

// The grid's sorted slots, keys and ranges against a stable sort of the
// slots by reference key: the cell, after the group (groups of n / groups
// consecutive points, build_groups).
void expect_matches_reference(Context& ctx, PointGrid& grid, const std::vector<float>& xyz, uint32_t groups = 1) {
    const uint32_t n = uint32_t(xyz.size() / 3);
    const RawGeometry g = read_raw_geometry(ctx, grid);
    ASSERT_EQ(g.cells, uint32_t(g.dims[0]) * uint32_t(g.dims[1]) * uint32_t(g.dims[2]));
    const uint32_t keys_in_all = g.cells * groups;
    std::vector<uint32_t> cell(n), order(n);
    for (uint32_t i = 0; i < n; ++i) cell[i] = (i / (n / groups)) * g.cells + reference_cell(g, &xyz[3 * i]);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return cell[a] < cell[b]; });
    std::vector<cl_uint> start(size_t(keys_in_all) + 1);
    grid.cell_start().download(ctx, start.data(), start.size());
    if (n > 0) {
        std::vector<cl_uint> slots(n), keys(n);
        grid.sorted_slots().download(ctx, slots.data(), n);
        grid.sorted_keys().download(ctx, keys.data(), n);
        for (uint32_t k = 0; k < n; ++k) {
            ASSERT_EQ(slots[k], order[k]) << "sorted position " << k;
            ASSERT_EQ(keys[k], cell[order[k]]) << "sorted position " << k;
        }
    }
    // start[c] = points in cells below c.
    std::vector<uint32_t> below(size_t(keys_in_all) + 1, 0);
    for (uint32_t i = 0; i < n; ++i) ++below[cell[i] + 1];
    for (size_t c = 1; c < below.size(); ++c) below[c] += below[c - 1];
    for (size_t c = 0; c < below.size(); ++c) ASSERT_EQ(start[c], below[c]) << "cell " << c;
}

}  // namespace

// Groups (worlds; the metrics of a swarm of worlds): one geometry over all
// points, each group's cells apart, so a group's sorted positions are its
// own points only, in cell order.
TEST(PointGrid, GroupsKeepTheirPointsApartAndMatchBruteForce) {
    auto ctx = shared_context();
    constexpr uint32_t kGroups = 5, kPer = 301;
    std::vector<float> xyz;
    for (uint32_t k = 0; k < kGroups; ++k) {
        const std::vector<float> p = random_points(kPer, -1.0f + 0.1f * float(k), 1.0f, 40 + k);
        xyz.insert(xyz.end(), p.begin(), p.end());
    }
    const auto pts = upload_points(*ctx, xyz);
    PointGrid grid(*ctx);
    grid.build_groups(pts, kGroups * kPer, kGroups, 0.0f);
    EXPECT_LE(read_raw_geometry(*ctx, grid).cells, PointGrid::max_cells(kPer));
    expect_matches_reference(*ctx, grid, xyz, kGroups);
    // Groups that do not split the points evenly are refused.
    EXPECT_THROW(grid.build_groups(pts, kGroups * kPer, 4, 0.0f), Error);
    EXPECT_THROW(grid.build_groups(pts, kGroups * kPer, 0, 0.0f), Error);
}

// Groups apart (the force model's worlds), each at its own smallest cell:
// each group gets the geometry,
// sorted slots and cell ranges it gets built alone, bit for bit, at the key
// stride max_cells(n / groups); a cell's range is the group's sorted
// positions, offset by the group's first.
TEST(PointGrid, GroupsApartHaveTheGeometryAndOrderOfEachGroupAlone) {
    auto ctx = shared_context();
    constexpr uint32_t kGroups = 4, kPer = 301;
    const uint32_t stride = PointGrid::max_cells(kPer);
    std::vector<float> xyz;
    for (uint32_t k = 0; k < kGroups; ++k) {  // boxes of different sizes and places
        const std::vector<float> p = random_points(kPer, -1.0f - float(k), 1.0f + 0.5f * float(k), 60 + k);
        xyz.insert(xyz.end(), p.begin(), p.end());
    }
    const auto pts = upload_points(*ctx, xyz);
    PointGrid grid(*ctx);
    const std::vector<float> min_cells{0.05f, 0.3f, 0.0f, 0.12f};  // R_rep of each world
    grid.build_groups_apart(pts, kGroups * kPer, min_cells);
    std::vector<cl_float4> geo(2 * kGroups);
    grid.geometry().download(*ctx, geo.data(), geo.size());
    std::vector<cl_uint> slots(kGroups * kPer), start(size_t(kGroups) * stride + 1);
    grid.sorted_slots().download(*ctx, slots.data(), slots.size());
    grid.cell_start().download(*ctx, start.data(), start.size());
    for (uint32_t k = 0; k < kGroups; ++k) {
        SCOPED_TRACE("group " + std::to_string(k));
        const std::vector<float> own(xyz.begin() + 3 * size_t(k) * kPer, xyz.begin() + 3 * size_t(k + 1) * kPer);
        const auto own_pts = upload_points(*ctx, own);
        PointGrid alone(*ctx);
        alone.build(own_pts, kPer, min_cells[k]);
        const RawGeometry a = read_raw_geometry(*ctx, alone);
        for (int c = 0; c < 3; ++c) {
            EXPECT_EQ(geo[2 * k].s[c], a.origin[c]);
            int d;
            std::memcpy(&d, &geo[2 * k + 1].s[c], sizeof(int));
            EXPECT_EQ(d, a.dims[c]);
        }
        EXPECT_EQ(geo[2 * k].s[3], a.inv_cell);
        uint32_t w;
        std::memcpy(&w, &geo[2 * k + 1].s[3], sizeof(w));
        EXPECT_EQ(w, stride);
        EXPECT_LE(a.cells, stride);
        std::vector<cl_uint> a_slots(kPer), a_start(size_t(a.cells) + 1);
        alone.sorted_slots().download(*ctx, a_slots.data(), kPer);
        alone.cell_start().download(*ctx, a_start.data(), a_start.size());
        for (uint32_t i = 0; i < kPer; ++i) ASSERT_EQ(slots[k * kPer + i], k * kPer + a_slots[i]) << i;
        for (uint32_t c = 0; c <= a.cells; ++c) ASSERT_EQ(start[size_t(k) * stride + c], k * kPer + a_start[c]) << c;
        // The unused keys up to the stride are empty.
        for (uint32_t c = a.cells; c <= stride; ++c) ASSERT_EQ(start[size_t(k) * stride + c], (k + 1) * kPer) << c;
        const GridGeometry rg = grid.read_geometry(k);
        EXPECT_EQ(rg.origin[0], a.origin[0]);
    }
    // One group apart is build().
    grid.build_groups_apart(pts, kGroups * kPer, {0.05f});
    expect_matches_reference(*ctx, grid, xyz);
}

TEST(PointGrid, BoundingBoxGridMatchesBruteForce) {
    auto ctx = shared_context();
    // A clustered cloud (duplicates included) and a cell far below any
    // swarm's interaction radius.
    std::vector<float> xyz = random_points(3000, -2.0f, 3.0f, 11);
    const std::vector<float> dense = random_points(500, 0.1f, 0.3f, 12);
    xyz.insert(xyz.end(), dense.begin(), dense.end());
    xyz.insert(xyz.end(), dense.begin(), dense.begin() + 300);  // 100 exact duplicates
    const uint32_t n = uint32_t(xyz.size() / 3);
    auto pts = upload_points(*ctx, xyz);
    PointGrid grid(*ctx);
    const float min_cell = 0.23f;
    grid.build(pts, n, min_cell);
    expect_matches_reference(*ctx, grid, xyz);
    const RawGeometry g = read_raw_geometry(*ctx, grid);
    float lo[3] = {xyz[0], xyz[1], xyz[2]};
    for (uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], xyz[3 * i + a]);
    for (int a = 0; a < 3; ++a) EXPECT_EQ(g.origin[a], lo[a]) << "the origin is the bounding box's corner";
    EXPECT_GE(1.0f / g.inv_cell, min_cell * (1.0f - 1e-6f));
    EXPECT_LE(g.cells, PointGrid::max_cells(n));
    EXPECT_GT(g.cells, 64u);
}

TEST(PointGrid, CellEdgeGrowsToTheCellBound) {
    auto ctx = shared_context();
    const std::vector<float> xyz = random_points(400, -5.0f, 5.0f, 13);
    auto pts = upload_points(*ctx, xyz);
    PointGrid grid(*ctx);
    grid.build(pts, 400, 1e-4f);  // would be 10^15 cells
    expect_matches_reference(*ctx, grid, xyz);
    EXPECT_LE(read_raw_geometry(*ctx, grid).cells, PointGrid::max_cells(400));
}

TEST(PointGrid, GivenGeometryMatchesBruteForce) {
    auto ctx = shared_context();
    // Points partly outside the given cells: clamped into the border cells.
    const std::vector<float> xyz = random_points(2500, -1.5f, 2.0f, 14);
    auto pts = upload_points(*ctx, xyz);
    GridGeometry g;
    g.origin = {-1.0f, -0.75f, -1.25f};
    g.cell = 0.13f;
    g.dims = {17, 9, 23};
    PointGrid grid(*ctx);
    grid.build(pts, 2500, g);
    expect_matches_reference(*ctx, grid, xyz);
    const GridGeometry back = grid.read_geometry();
    EXPECT_EQ(back.dims, g.dims);
    EXPECT_EQ(back.origin, g.origin);
    // A rebuild at another geometry and count reuses nothing stale.
    grid.build(pts, 1000, 0.05f);
    expect_matches_reference(*ctx, grid, std::vector<float>(xyz.begin(), xyz.begin() + 3000));
}

TEST(PointGrid, NoPointsAndOnePoint) {
    auto ctx = shared_context();
    const std::vector<float> one{0.5f, -0.25f, 2.0f};
    auto pts = upload_points(*ctx, one);
    PointGrid grid(*ctx);
    grid.build(pts, 0, 0.1f);
    expect_matches_reference(*ctx, grid, {});
    grid.build(pts, 1, 0.1f);
    expect_matches_reference(*ctx, grid, one);
}

TEST(PointGrid, BuildsAreBitwiseRepeatable) {
    auto ctx = shared_context();
    const std::vector<float> xyz = random_points(5000, 0.0f, 1.0f, 15);
    auto pts = upload_points(*ctx, xyz);
    PointGrid a(*ctx), b(*ctx);
    a.build(pts, 5000, 0.01f);
    b.build(pts, 5000, 0.01f);
    b.build(pts, 5000, 0.01f);
    std::vector<cl_uint> sa(5000), sb(5000);
    a.sorted_slots().download(*ctx, sa.data(), 5000);
    b.sorted_slots().download(*ctx, sb.data(), 5000);
    EXPECT_EQ(sa, sb);
}

namespace {

// Sorts the first m of `keys` (with slots 0.. and the given ids) on the
// device and checks the result against std::stable_sort.
void expect_stable_sort(uint32_t max_key, uint32_t max_bits, uint32_t blocks, const std::vector<cl_uint>& keys,
                        uint32_t m, bool with_ids, uint32_t expected_passes, uint32_t max_count = UINT32_MAX) {
    auto ctx = shared_context();
    const size_t len = keys.size();
    std::vector<cl_uint> slots(len), ids(len);
    std::iota(slots.begin(), slots.end(), 0u);
    std::mt19937 rng(7);
    for (auto& v : ids) v = rng();
    DeviceBuffer<cl_uint> k[2], s[2], i[2], count(*ctx, 1, "count");
    for (int h = 0; h < 2; ++h) {
        k[h].allocate(*ctx, len, "keys");
        s[h].allocate(*ctx, len, "slots");
        i[h].allocate(*ctx, len, "ids");
    }
    k[0].upload(*ctx, keys.data(), len);
    s[0].upload(*ctx, slots.data(), len);
    i[0].upload(*ctx, ids.data(), len);
    count.upload(*ctx, &m, 1);
    RadixSort sort(*ctx, max_key, blocks, max_bits);
    EXPECT_EQ(sort.passes(), expected_passes);
    RadixSort::Columns a{&k[0], &s[0], with_ids ? &i[0] : nullptr}, b{&k[1], &s[1], with_ids ? &i[1] : nullptr};
    sort.sort(count, a, b, max_count);
    std::vector<uint32_t> order(m);
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return keys[x] < keys[y]; });
    std::vector<cl_uint> gk(len), gs(len), gi(len);
    a.key->download(*ctx, gk.data(), len);
    a.slot->download(*ctx, gs.data(), len);
    if (with_ids) a.id->download(*ctx, gi.data(), len);
    for (uint32_t j = 0; j < m; ++j) {
        ASSERT_EQ(gk[j], keys[order[j]]) << j;
        ASSERT_EQ(gs[j], order[j]) << "equal keys keep their input order (" << j << ")";
        if (with_ids) ASSERT_EQ(gi[j], ids[order[j]]) << j;
    }
}

}  // namespace

TEST(RadixSort, StableOverSeveralPassesWithAndWithoutIds) {
    std::mt19937 rng(3);
    std::vector<cl_uint> keys(20000);
    for (auto& v : keys) v = (rng() % 40u) * 127u;  // many equal keys, up to 4953
    for (bool ids : {true, false}) {
        expect_stable_sort(4999, 5, 16, keys, 17000, ids, 3);   // 13 bits: 3 passes (odd)
        expect_stable_sort(4999, 7, 64, keys, 20000, ids, 2);   // 2 passes (even)
        expect_stable_sort(4999, 13, 3, keys, 12345, ids, 1);   // 1 pass, few blocks
    }
}

// A bound on the count takes fewer blocks (each block's histogram row is
// fixed work): 1, a few and all of them sort as the full count of blocks.
TEST(RadixSort, FewerBlocksForABoundedCountSortTheSame) {
    std::mt19937 rng(5);
    std::vector<cl_uint> keys(20000);
    for (auto& v : keys) v = (rng() % 300u) * 17u;  // up to 5083: 13 bits, 2 passes of 7
    auto ctx = shared_context();
    const RadixSort probe(*ctx, 5099, 64, 7);
    const uint32_t per_block = RadixSort::kKeysPerDigit << probe.digit_bits();
    EXPECT_EQ(probe.blocks_for(0), 1u);
    EXPECT_EQ(probe.blocks_for(per_block - 1), 1u);
    EXPECT_EQ(probe.blocks_for(5 * per_block), 5u);
    EXPECT_EQ(probe.blocks_for(UINT32_MAX), 64u);
    for (uint32_t m : {100u, 3000u, 20000u})
        for (uint32_t bound : {m, 5 * per_block, UINT32_MAX}) {
            SCOPED_TRACE(std::to_string(m) + " keys, bound " + std::to_string(bound));
            if (bound < m) continue;
            expect_stable_sort(5099, 7, 64, keys, m, true, 2, bound);
        }
}

TEST(RadixSort, EmptyAndSingleEntry) {
    const std::vector<cl_uint> keys{5, 3, 9, 1};
    expect_stable_sort(15, 2, 4, keys, 0, true, 2);
    expect_stable_sort(15, 2, 4, keys, 1, true, 2);
    expect_stable_sort(15, 2, 64, keys, 4, false, 2);
}

namespace {
// Regression (issue 16, limits): 8 n used to wrap in 32 bits for n >= 2^29.
TEST(PointGridLimits, MaxCellsNeverWrapsAndStaysBelow2To31) {
    uint32_t prev = 0;
    for (uint32_t n : {0u, 1u, 1000u, 1u << 20, (1u << 29) - 1, 1u << 29, 1u << 30, 0xFFFFFFFFu}) {
        const uint32_t c = swarmcl::PointGrid::max_cells(n);
        EXPECT_GE(c, prev) << n;
        EXPECT_LE(c, 1u << 30) << n;
        prev = c;
    }
    EXPECT_EQ(swarmcl::PointGrid::max_cells(1u << 29), 1u << 30);
}
}  // namespace
