// Signed distance grids (kernels/sdf.cl + host fast marching): the exact
// band against brute force, spheres and boxes against their analytic
// distance, a mesh with a hole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "fields/sdf.hpp"
#include "reference/sdf_reference.hpp"
#include "test_support.hpp"

using namespace swarmcl;
using swarmcl::test::D3;

namespace {

Grid3 cube_grid(double lo, double hi, uint32_t n) {
    Grid3 g;
    g.origin = {lo, lo, lo};
    g.h = (hi - lo) / n;
    g.dims = {n, n, n};
    return g;
}

double box_distance(const D3& p, const D3& c, const D3& h) {
    double out2 = 0, in = -INFINITY;
    for (int a = 0; a < 3; ++a) {
        const double q = std::fabs(p[a] - c[a]) - h[a];
        out2 += std::max(q, 0.0) * std::max(q, 0.0);
        in = std::max(in, q);
    }
    return out2 > 0 ? std::sqrt(out2) : in;
}

}  // namespace

TEST(Sdf, BandMatchesBruteForceAndFarFieldIsClose) {
    auto& ctx = *test::shared_context();
    const TriangleMesh mesh = merged({sphere_mesh({0.1f, -0.2f, 0.05f}, 0.6f, 8, 12),
                                      box_mesh({-0.5f, 0.5f, 0.3f}, {0.3f, 0.2f, 0.4f})});
    const Grid3 g = cube_grid(-1.2, 1.2, 20);
    const SdfGrid sdf = compute_sdf(ctx, mesh, g);
    const auto ref = test::sdf_brute_force(mesh, g);
    size_t band = 0;
    double far_err = 0;
    for (size_t c = 0; c < g.count(); ++c) {
        ASSERT_TRUE(std::isfinite(sdf.phi[c]));
        if (std::fabs(ref[c]) <= 3.0 * g.h) {
            ++band;
            ASSERT_NEAR(sdf.phi[c], ref[c], 1e-5) << "cell " << c;
        } else {
            EXPECT_EQ(sdf.phi[c] < 0, ref[c] < 0) << "cell " << c;
            far_err = std::max(far_err, std::fabs(sdf.phi[c] - ref[c]));
        }
    }
    EXPECT_GT(band, 1000u);
    EXPECT_LT(far_err, g.h);
}

TEST(Sdf, SphereAndBoxAgainstAnalyticDistance) {
    auto& ctx = *test::shared_context();
    const Grid3 g = cube_grid(-2.0, 2.0, 48);
    {
        const SdfGrid s = compute_sdf(ctx, sphere_mesh({0.2f, 0.0f, -0.1f}, 1.0f, 48, 96), g);
        double worst = 0;
        for (uint32_t k = 0; k < 48; ++k)
            for (uint32_t j = 0; j < 48; ++j)
                for (uint32_t i = 0; i < 48; ++i) {
                    const D3 p = g.center(i, j, k);
                    const double exact = std::hypot(p[0] - 0.2, p[1], p[2] + 0.1) - 1.0;
                    worst = std::max(worst, std::fabs(s.phi[g.index(i, j, k)] - exact));
                }
        EXPECT_LT(worst, g.h) << "sphere";
    }
    {
        const SdfGrid s = compute_sdf(ctx, box_mesh({-0.3f, 0.1f, 0.2f}, {0.9f, 0.5f, 0.7f}), g);
        double worst = 0;
        for (uint32_t k = 0; k < 48; ++k)
            for (uint32_t j = 0; j < 48; ++j)
                for (uint32_t i = 0; i < 48; ++i) {
                    const D3 p = g.center(i, j, k);
                    const double exact = box_distance(p, {-0.3, 0.1, 0.2}, {0.9, 0.5, 0.7});
                    worst = std::max(worst, std::fabs(s.phi[g.index(i, j, k)] - exact));
                    if (std::fabs(exact) <= 3 * g.h) ASSERT_NEAR(s.phi[g.index(i, j, k)], exact, 1e-5);
                }
        EXPECT_LT(worst, g.h) << "box";
    }
}

// A closed sphere with two triangles removed: the distance is still exact
// (it does not depend on closedness) and the sign agrees with the closed
// mesh everywhere but next to the hole; the inside stays inside.
TEST(Sdf, MeshWithAHole) {
    auto& ctx = *test::shared_context();
    TriangleMesh closed = sphere_mesh({0, 0, 0}, 1.0f, 16, 32);
    TriangleMesh holed = closed;
    const size_t t0 = closed.triangle_count() / 2;
    holed.triangles.erase(holed.triangles.begin() + t0, holed.triangles.begin() + t0 + 2);
    const auto hole = closed.corners(t0)[0];
    const Grid3 g = cube_grid(-1.6, 1.6, 32);
    const SdfGrid a = compute_sdf(ctx, closed, g), b = compute_sdf(ctx, holed, g);
    size_t differ = 0;
    for (uint32_t k = 0; k < 32; ++k)
        for (uint32_t j = 0; j < 32; ++j)
            for (uint32_t i = 0; i < 32; ++i) {
                const size_t c = g.index(i, j, k);
                const D3 p = g.center(i, j, k);
                const double to_hole = std::hypot(p[0] - hole[0], p[1] - hole[1], p[2] - hole[2]);
                if ((a.phi[c] < 0) != (b.phi[c] < 0)) {
                    ++differ;
                    EXPECT_LT(to_hole, 0.5) << "a sign flipped far from the hole";
                }
                // Within the exact band the distance does not depend on the
                // hole (away from it); beyond, the march from it agrees to h.
                if (to_hole > 0.5)
                    EXPECT_NEAR(std::fabs(a.phi[c]), std::fabs(b.phi[c]), std::fabs(a.phi[c]) <= 3 * g.h ? 1e-5 : g.h);
            }
    EXPECT_LT(differ, 20u);
    EXPECT_LT(b.phi[g.index(16, 16, 16)], -0.8);  // the centre is inside
    EXPECT_GT(b.phi[g.index(0, 0, 0)], 0.8);
}

TEST(Sdf, MeshOutsideTheGridLeavesItFar) {
    auto& ctx = *test::shared_context();
    const SdfGrid s = compute_sdf(ctx, box_mesh({10, 10, 10}, {1, 1, 1}), cube_grid(-1, 1, 8));
    for (float v : s.phi) EXPECT_TRUE(std::isinf(v) && v > 0);
    EXPECT_THROW(compute_sdf(ctx, box_mesh({0, 0, 0}, {1, 1, 1}), cube_grid(-1, 1, 8), 0.5), Error);
}
