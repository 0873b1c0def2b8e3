// Target shapes of the force model: generated meshes, stratified sampling
// (§5.1), Manhattan neighbour lists (§5.2) against brute force, assignment
// (§5.3), and the B-spline path (§6).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <set>

#include "core/error.hpp"
#include "shapes/bspline_path.hpp"
#include "shapes/shape_library.hpp"
#include "shapes/shape_sampling.hpp"

using namespace swarmcl;

TEST(ShapeLibrary, EveryShapeIsAValidOutwardMesh) {
    for (const std::string name : {"sphere", "torus", "moon", "star", "heart", "mammoth", "shark", "horse",
                                   "horse:0.25"}) {
        const TriangleMesh m = generated_shape(name);
        EXPECT_GE(m.triangle_count(), 40u) << name;
        EXPECT_GT(surface_area(m), 1.0) << name;
        EXPECT_GT(signed_volume(m), 0.05) << name;  // closed parts, outward
        const MeshBounds b = bounds(m);
        for (int a = 0; a < 3; ++a) EXPECT_LT(b.max[a] - b.min[a], 4.0f) << name;
    }
    EXPECT_NEAR(signed_volume(generated_shape("torus")), 2 * M_PI * M_PI * 0.8 * 0.09, 0.03);
}

TEST(ShapeLibrary, HorseCycleKeepsTopologyAndMovesLegs) {
    const TriangleMesh a = horse_mesh(0.0f), b = horse_mesh(0.25f), c = horse_mesh(1.0f);
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.triangles, b.triangles);
    double moved = 0.0;
    for (size_t i = 0; i < a.vertices.size(); ++i)
        moved = std::max(moved, double(std::fabs(a.vertices[i][0] - b.vertices[i][0])));
    EXPECT_GT(moved, 0.2);                            // the legs swing
    for (size_t i = 0; i < a.vertices.size(); ++i)    // one full cycle
        EXPECT_NEAR(a.vertices[i][0], c.vertices[i][0], 1e-4f);
}

TEST(ShapeLibrary, UnknownNameIsAnError) {
    try {
        generated_shape("unicorn");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("mammoth"), std::string::npos);
    }
    EXPECT_THROW(generated_shape("horse:x"), Error);
}

TEST(ShapeSampling, StratifiedSamplesLieOnTheMeshInProportionToArea) {
    // Two boxes of different size: sample counts follow the areas.
    const TriangleMesh small = box_mesh({-3, 0, 0}, {0.5f, 0.5f, 0.5f}), big = box_mesh({3, 0, 0}, {1, 1, 1});
    const TriangleMesh m = merged({small, big});
    const uint32_t n = 5000;
    const auto s = stratified_samples(m, n, 7);
    const auto p = sample_points(m, s);
    ASSERT_EQ(p.size(), 3u * n);
    size_t in_small = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const bool left = p[3 * i] < 0;
        in_small += left;
        // On the surface of its box: one coordinate at +-half extent.
        const float c = left ? -3.0f : 3.0f, h = left ? 0.5f : 1.0f;
        const float q[3] = {std::fabs(p[3 * i] - c), std::fabs(p[3 * i + 1]), std::fabs(p[3 * i + 2])};
        EXPECT_NEAR(std::max({q[0], q[1], q[2]}), h, 1e-5f);
    }
    // Areas 6 and 24: exactly 1/5 up to one sample per stratum boundary.
    EXPECT_NEAR(double(in_small) / n, 0.2, 0.002);
    // Same seed, same samples; another seed, other samples.
    EXPECT_EQ(sample_points(m, stratified_samples(m, n, 7)), p);
    EXPECT_NE(sample_points(m, stratified_samples(m, n, 8)), p);
}

TEST(ShapeSampling, ScalingMeetsTheMinimumSpacing) {
    const TriangleMesh m = sphere_mesh({1, 2, 3}, 1.0f);
    const ShapeTargets t = make_targets(m, 2000, 1, 0.1f, 2.0);
    EXPECT_NEAR(t.spacing, 0.1, 1e-4);
    const MeshBounds b = bounds(scaled_for_spacing(m, 2000, 0.1f));
    EXPECT_NEAR(0.5f * (b.min[0] + b.max[0]), 1.0f, 1e-4f);  // about its centre
    // Already spaced enough: unchanged.
    EXPECT_NEAR(make_targets(m, 100, 1, 0.1f, 2.0).spacing, std::sqrt(surface_area(m) / 100), 1e-9);
    EXPECT_THROW(make_targets(m, 0, 1, 0.1f, 2.0), Error);
    EXPECT_THROW(scaled_for_spacing(m, 10, -1.0f), Error);
}

TEST(ShapeSampling, ManhattanNeighboursMatchBruteForce) {
    const TriangleMesh m = generated_shape("moon");
    const ShapeTargets t = make_targets(m, 1500, 3, 0.0f, 2.0);
    const double thr = 2.0 * t.spacing;
    size_t total = 0;
    for (size_t i = 0; i < t.count(); ++i) {
        std::vector<uint32_t> want;
        for (size_t j = 0; j < t.count(); ++j) {
            if (j == i) continue;
            float md = 0.0f;
            for (int a = 0; a < 3; ++a) md += std::fabs(t.points[3 * i + a] - t.points[3 * j + a]);
            if (md < float(thr)) want.push_back(uint32_t(j));
        }
        const std::vector<uint32_t> got(t.nbr_index.begin() + t.nbr_start[i], t.nbr_index.begin() + t.nbr_start[i + 1]);
        ASSERT_EQ(got, want) << "target " << i;
        total += got.size();
    }
    EXPECT_GT(double(total) / t.count(), 4.0);  // a real neighbourhood on the surface
}

TEST(ShapeSampling, AssignmentsArePermutationsAndNearlyOptimal) {
    // Insects already near a shape (targets jittered by 5 cm, in shuffled id
    // order): the optimal assignment travels at most 5 cm * sqrt(3) each.
    const uint32_t n = 3000;
    const ShapeTargets t = make_targets(generated_shape("mammoth"), n, 1, 0.0f, 2.0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> jitter(-0.05f, 0.05f);
    std::vector<uint32_t> perm(n);
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), rng);
    std::vector<float> agents(3 * n);
    for (uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) agents[3 * i + a] = t.points[3 * perm[i] + a] + jitter(rng);
    const double bound = total_travel(agents, t.points, perm);
    for (Assignment m : {Assignment::Nearest, Assignment::Curve}) {
        const auto a = assign_targets(agents, t.points, m);
        std::vector<uint32_t> sorted = a;
        std::sort(sorted.begin(), sorted.end());
        for (uint32_t i = 0; i < n; ++i) ASSERT_EQ(sorted[i], i);
        const double d = total_travel(agents, t.points, a);
        std::printf("[ assign ] %s: total travel %.1f m (the jitter's assignment: %.1f m)\n",
                    m == Assignment::Nearest ? "nearest" : "curve", d, bound);
        // The curve matching keeps the layout but not distances (measured
        // 5x the bound here): it is only checked to be a permutation.
        if (m == Assignment::Nearest) EXPECT_LT(d, 1.5 * bound);
    }
    // A morph (sphere samples to mammoth targets): both, printed for docs.
    const ShapeTargets from = make_targets(generated_shape("sphere"), n, 2, 0.0f, 2.0);
    for (Assignment m : {Assignment::Nearest, Assignment::Curve})
        std::printf("[ assign ] sphere->mammoth %s: total travel %.1f m\n",
                    m == Assignment::Nearest ? "nearest" : "curve",
                    total_travel(from.points, t.points, assign_targets(from.points, t.points, m)));
    EXPECT_THROW(assign_targets(agents, std::vector<float>(3 * (n - 1)), Assignment::Nearest), Error);
    EXPECT_THROW(assign_targets(agents, std::vector<float>(3 * (n + 1)), Assignment::Curve), Error);
}

TEST(BSplinePathTest, ArcLengthParameterisation) {
    // Control points on a straight line: the curve is the segment from the
    // first to the last point and arc length is distance along it.
    const BSplinePath line({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0, 4, 0, 0});
    EXPECT_NEAR(line.length(), 4.0, 1e-4);
    for (double s : {0.0, 0.7, 2.0, 3.9, 4.0}) EXPECT_NEAR(line.at_length(s)[0], s, 2e-3) << s;
    EXPECT_NEAR(line.at_length(10.0)[0], 4.0f, 1e-5f);  // clamped
    // A curved path: equal arc-length steps give equal chord lengths.
    const BSplinePath curve({0, 0, 0, 2, 0, 0, 2, 2, 0, 0, 2, 1, -2, 4, 2});
    const double step = curve.length() / 50;
    for (int i = 0; i < 50; ++i) {
        const Vec3f a = curve.at_length(i * step), b = curve.at_length((i + 1) * step);
        const double d = std::sqrt(double(a[0] - b[0]) * (a[0] - b[0]) + double(a[1] - b[1]) * (a[1] - b[1]) +
                                   double(a[2] - b[2]) * (a[2] - b[2]));
        EXPECT_NEAR(d, step, 0.02 * step) << i;
    }
    EXPECT_NEAR(curve.at_length(0)[0], 0.0f, 1e-5f);  // interpolates the ends
    EXPECT_NEAR(curve.at_length(curve.length())[2], 2.0f, 1e-4f);
}

TEST(BSplinePathTest, BadControlPoints) {
    EXPECT_THROW(BSplinePath({0, 0, 0, 1, 0, 0, 2, 0, 0}), Error);  // 3 points
    EXPECT_THROW(BSplinePath({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0}), Error);
    EXPECT_THROW(BSplinePath({0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, NAN}), Error);
}
