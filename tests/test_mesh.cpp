// The shared triangle mesh type: validation, and the closed, outward
// primitives (every edge shared by exactly two triangles in opposite
// directions; positive enclosed volume close to the analytic one).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>

#include "core/error.hpp"
#include "shapes/triangle_mesh.hpp"

using namespace swarmcl;

namespace {

void expect_closed_and_oriented(const TriangleMesh& m) {
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const auto& f : m.triangles)
        for (int e = 0; e < 3; ++e) ++directed[{f[e], f[(e + 1) % 3]}];
    for (const auto& [edge, count] : directed) {
        EXPECT_EQ(count, 1) << "edge used twice in one direction";
        EXPECT_EQ(directed.count({edge.second, edge.first}), 1u) << "open edge";
    }
}

}  // namespace

TEST(Mesh, PrimitivesAreClosedOutwardAndHaveTheirVolume) {
    const double pi = 3.14159265358979323846;
    auto box = box_mesh({1, 2, 3}, {0.5f, 1.0f, 2.0f});
    expect_closed_and_oriented(box);
    EXPECT_NEAR(signed_volume(box), 8.0, 1e-9);
    EXPECT_NEAR(surface_area(box), 2 * (1 * 2 + 1 * 4 + 2 * 4), 1e-9);

    auto sphere = sphere_mesh({0, 0, 0}, 2.0f, 64, 128);
    expect_closed_and_oriented(sphere);
    EXPECT_NEAR(signed_volume(sphere), 4.0 / 3.0 * pi * 8.0, 0.01 * 4.0 / 3.0 * pi * 8.0);
    EXPECT_NEAR(surface_area(sphere), 4 * pi * 4.0, 0.01 * 4 * pi * 4.0);

    auto cyl = cylinder_mesh({0, 0, -1}, 1.0f, 3.0f, 256);
    expect_closed_and_oriented(cyl);
    EXPECT_NEAR(signed_volume(cyl), pi * 3.0, 0.001 * pi * 3.0);

    auto mirrored = transformed(box, {-1, 1, 1}, {0, 0, 0});
    EXPECT_NEAR(signed_volume(mirrored), 8.0, 1e-9);
    auto both = merged({box, sphere});
    EXPECT_EQ(both.triangle_count(), box.triangle_count() + sphere.triangle_count());
}

TEST(Mesh, BadInputIsAClearErrorAndDegenerateTrianglesAreSkipped) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::vector<float> xyz{0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0};
    size_t skipped = 0;
    // Triangle 1 repeats a vertex, triangle 2 is collinear: both skipped.
    auto m = make_mesh(xyz, {0, 1, 2, 0, 0, 1, 0, 1, 3}, &skipped);
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(skipped, 2u);

    try {
        make_mesh(xyz, {0, 1, 7});
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("triangle 0"), std::string::npos) << e.what();
    }
    auto bad = xyz;
    bad[4] = nan;
    try {
        make_mesh(bad, {0, 1, 2});
        FAIL();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("vertex 1"), std::string::npos) << e.what();
    }
    EXPECT_THROW(make_mesh(xyz, {}), Error);
    EXPECT_THROW(make_mesh(xyz, {0, 1}), Error);
    EXPECT_THROW(make_mesh(xyz, {0, 0, 1}), Error);  // only degenerate triangles
    EXPECT_THROW(box_mesh({0, 0, 0}, {0, 1, 1}), Error);
}
