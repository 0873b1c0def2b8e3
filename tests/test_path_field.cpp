// The global path field (curl-noise paper §5-6): repulsion (Eq. 6), the
// minimum cost field by fast marching (Eq. 4, 7), the global velocity
// (Eq. 8) and the full model (Eq. 9) with groups and moving goals.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <queue>
#include <random>

#include "core/error.hpp"
#include "fields/cost_field.hpp"
#include "fast_march_cases.hpp"
#include "fields/fast_marching.hpp"
#include "models/path_model.hpp"
#include "test_support.hpp"

using namespace swarmcl;

namespace {

Grid3 cube_grid(double lo, double hi, uint32_t n) {
    Grid3 g;
    g.origin = {lo, lo, lo};
    g.h = (hi - lo) / n;
    g.dims = {n, n, n};
    return g;
}

Goal point_goal(float x, float y, float z) {
    Goal g;
    g.center = {x, y, z};
    return g;
}

Goal sphere_goal(float x, float y, float z, float r) {
    Goal g;
    g.kind = Goal::Kind::Sphere;
    g.center = {x, y, z};
    g.radius = r;
    return g;
}

double box_distance(const std::array<float, 3>& p, const Vec3f& c, const Vec3f& h) {
    double out2 = 0, in = -INFINITY;
    for (int a = 0; a < 3; ++a) {
        const double q = std::fabs(double(p[a]) - c[a]) - h[a];
        out2 += std::max(q, 0.0) * std::max(q, 0.0);
        in = std::max(in, q);
    }
    return out2 > 0 ? std::sqrt(out2) : in;
}

}  // namespace

TEST(Repulsion, BellFunctionOfEq6) {
    const double l = 0.1, two_a = 2 * std::sqrt(2.0) * l;
    EXPECT_EQ(repulsion(-0.01, l), 1.0);
    EXPECT_DOUBLE_EQ(repulsion(0.0, l), 1.0);
    EXPECT_NEAR(repulsion(two_a, l), 0.0, 1e-12);
    EXPECT_EQ(repulsion(1.01 * two_a, l), 0.0);
    EXPECT_NEAR(repulsion(0.5 * two_a, l), 1 - 4.0 / 9 / 64 + 17.0 / 9 / 16 - 22.0 / 9 / 4, 1e-12);
    for (int i = 1; i <= 100; ++i) EXPECT_LE(repulsion(two_a * i / 100, l), repulsion(two_a * (i - 1) / 100, l));
}

// The cost from a point goal (x, y, z) on an n^3 grid of [-1, 1]^3 with no
// obstacles and A = 1, B = 0, first and second order, and each order's
// largest distance from the Euclidean distance (+inf if a cell is not finite).
namespace {
struct FreeSpaceCost {
    Grid3 grid;
    std::vector<double> slowness, c1, c2;
    Goal goal;
    double err1 = 0, err2 = 0;
};
FreeSpaceCost free_space_cost(uint32_t n, float x, float y, float z) {
    FreeSpaceCost r;
    r.grid = cube_grid(-1, 1, n);
    CostWeights w;
    w.A = 1.0;
    w.B = 0.0;
    r.slowness = cost_slowness(r.grid, {}, w);
    r.goal = point_goal(x, y, z);
    r.c1 = solve_cost(r.grid, r.slowness, {r.goal}, false);
    r.c2 = solve_cost(r.grid, r.slowness, {r.goal}, true);
    for (uint32_t k = 0; k < n; ++k)
        for (uint32_t j = 0; j < n; ++j)
            for (uint32_t i = 0; i < n; ++i) {
                const auto p = r.grid.center(i, j, k);
                const double d = std::hypot(p[0] - x, p[1] - y, p[2] - z);
                const size_t c = r.grid.index(i, j, k);
                r.err1 = std::max(r.err1, std::fabs(r.c1[c] - d));
                r.err2 = std::max(r.err2, std::fabs(r.c2[c] - d));
                if (!std::isfinite(r.c1[c]) || !std::isfinite(r.c2[c])) r.err1 = r.err2 = kInf;  // max() skips NaN
            }
    return r;
}
}  // namespace

// No obstacles, a point goal, A = 1, B = 0: C is the Euclidean distance up
// to the first-order error (scikit-fmm's bound, 1.5 cells); second order is closer.
TEST(CostField, FreeSpacePointGoalIsTheDistance) {
    const FreeSpaceCost r = free_space_cost(40, 0.13f, -0.31f, 0.07f);
    EXPECT_LT(r.err1, 1.5 * r.grid.h);
    EXPECT_LT(r.err2, r.err1);
    // The default weights scale it by A = 0.6.
    const auto c = solve_cost(r.grid, cost_slowness(r.grid, {}, CostWeights{}), {r.goal});
    for (size_t i = 0; i < c.size(); i += 97) EXPECT_NEAR(c[i], 0.6 * r.c1[i], 1e-9);
}

// A grid past 2 MB of cells (64^3: 4.8 MB padded), which fast_march keeps on
// huge pages (host/fields/fast_marching.cpp, CellArray), solves as a small
// one does: within first-order accuracy of the distance (the error of a
// point source grows like h log(1/h): 1.70 cells here, 1.79 at 128^3 in
// fmm_bench, scikit-fmm 2.19 there), second order closer, and every run the
// same bit for bit.
TEST(CostField, LargeGridIsTheDistanceAndTheSameEveryRun) {
    const FreeSpaceCost r = free_space_cost(64, -0.27f, 0.41f, 0.05f);
    EXPECT_LT(r.err1, 2.0 * r.grid.h);
    EXPECT_LT(r.err2, r.err1);
    EXPECT_EQ(solve_cost(r.grid, r.slowness, {r.goal}, false), r.c1);
    EXPECT_EQ(solve_cost(r.grid, r.slowness, {r.goal}, true), r.c2);
}

namespace {

// The plain reference: Sethian's fast marching, first order, cells accepted
// one at a time in order of value from a binary heap, each neighbour's
// Godunov update solved with the axes sorted by value.
std::vector<double> heap_fast_march(const Grid3& g, const std::vector<double>& f, std::vector<double> u) {
    const int n[3] = {int(g.dims[0]), int(g.dims[1]), int(g.dims[2])};
    std::vector<char> known(u.size(), 0);
    using Entry = std::pair<double, size_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap;
    for (size_t c = 0; c < u.size(); ++c)
        if (std::isfinite(u[c])) heap.push({u[c], c});
    auto coords = [&](size_t c, int p[3]) {
        p[0] = int(c % n[0]);
        p[1] = int(c / n[0] % n[1]);
        p[2] = int(c / (size_t(n[0]) * n[1]));
    };
    auto at = [&](const int p[3]) { return size_t(p[0]) + size_t(n[0]) * (size_t(p[1]) + size_t(n[1]) * p[2]); };
    while (!heap.empty()) {
        const auto [v, c] = heap.top();
        heap.pop();
        if (known[c] || v > u[c]) continue;
        known[c] = 1;
        int p[3];
        coords(c, p);
        for (int a = 0; a < 3; ++a)
            for (int s = -1; s <= 1; s += 2) {
                int q[3] = {p[0], p[1], p[2]};
                q[a] += s;
                if (q[a] < 0 || q[a] >= n[a]) continue;
                const size_t d = at(q);
                if (known[d] || !std::isfinite(f[d])) continue;
                double b[3];
                for (int e = 0; e < 3; ++e) {
                    b[e] = INFINITY;
                    for (int t = -1; t <= 1; t += 2) {
                        int r[3] = {q[0], q[1], q[2]};
                        r[e] += t;
                        if (r[e] >= 0 && r[e] < n[e] && known[at(r)]) b[e] = std::min(b[e], u[at(r)]);
                    }
                }
                std::sort(b, b + 3);
                const double fh = f[d] * g.h;
                double x = b[0] + fh;
                for (int k = 2; k <= 3 && x > b[k - 1]; ++k) {
                    double sum = 0, sq = 0;
                    for (int e = 0; e < k; ++e) {
                        sum += b[e];
                        sq += b[e] * b[e];
                    }
                    x = (sum + std::sqrt(std::max(sum * sum - k * (sq - fh * fh), 0.0))) / k;
                }
                if (x < u[d]) {
                    u[d] = x;
                    heap.push({x, d});
                }
            }
    }
    return u;
}

}  // namespace

// fast_march drains its buckets in batches, two cells at a time where it
// can (host/fields/fast_marching.cpp): against the heap-ordered reference on
// a grid of random slowness in [1, 3] with impassable walls, first order,
// every cell within a small part of a cell's cost of the reference's value,
// and unreached or impassable cells alike.
TEST(CostField, FastMarchingMatchesTheHeapOrderedReference) {
    const uint32_t N = 48;
    const Grid3 g = cube_grid(0, 1, N);
    std::vector<double> f = test::random_slowness(g.count(), 7, 1.0, 3.0), u(g.count(), kInf);
    for (uint32_t k = 0; k < N; ++k)
        for (uint32_t j = 0; j < N; ++j) {
            if (j < 10 || j >= 14) f[g.index(20, j, k)] = kInf;  // a wall with a gap
            f[g.index(j, 30, k)] = kInf;                         // a wall that seals off y > 30
        }
    u[g.index(5, 7, 9)] = 0.0;
    const auto reference = heap_fast_march(g, f, u);
    fast_march(g, f, u);
    double worst = 0;
    size_t reached = 0;
    for (size_t c = 0; c < u.size(); ++c) {
        ASSERT_EQ(std::isfinite(u[c]), std::isfinite(reference[c])) << c;
        if (!std::isfinite(u[c])) continue;
        ++reached;
        worst = std::max(worst, std::fabs(u[c] - reference[c]) / (f[c] * g.h));
    }
    EXPECT_GT(reached, g.count() / 2);
    EXPECT_LT(worst, 0.02);
}

// The batches' stages on a second thread (a 64^3 grid is over the 2 MB from
// which fast_march starts one) give the same bits as the caller's thread
// alone, for either order, every run.
TEST(CostField, FastMarchingGivesTheSameBitsOnOneThreadOrTwo) {
    const test::WalledGrid w = test::walled_grid_64();
    for (const bool second : {false, true}) {
        FastMarchingOptions one, two;
        one.threads = 1;
        one.second_order = two.second_order = second;
        std::vector<double> a = w.known, b = w.known, c = w.known;
        fast_march(w.grid, w.slowness, a, one);
        fast_march(w.grid, w.slowness, b, two);
        fast_march(w.grid, w.slowness, c, two);
        EXPECT_EQ(a, b) << "second order " << second;
        EXPECT_EQ(b, c) << "second order " << second;
        EXPECT_TRUE(std::all_of(a.begin(), a.end(), [](double v) { return v >= 0; }));
    }
}

// Bad slowness (0, negative, NaN) anywhere, on a grid small enough for one
// thread and on one large enough for two, or arrays that do not match the
// grid: an InvalidArgument error, and the caller's values untouched.
TEST(CostField, FastMarchingRejectsBadSlowness) {
    for (const uint32_t N : {8u, 64u}) {
        const Grid3 g = cube_grid(0, 1, N);
        for (const double bad : {0.0, -1.0, double(NAN)}) {
            std::vector<double> f(g.count(), 1.0), u(g.count(), kInf);
            u[0] = 0.0;
            f[g.index(N - 1, N / 2, N - 2)] = bad;
            const std::vector<double> before = u;
            try {
                fast_march(g, f, u);
                ADD_FAILURE() << "slowness " << bad << " accepted at " << N << "^3";
            } catch (const Error& e) {
                EXPECT_EQ(e.status(), Status::InvalidArgument);
                EXPECT_NE(std::string(e.what()).find("slowness"), std::string::npos) << e.what();
            }
            EXPECT_EQ(std::memcmp(u.data(), before.data(), u.size() * sizeof(double)), 0);
        }
        std::vector<double> f(g.count(), 1.0), short_u(g.count() - 1, kInf);
        EXPECT_THROW(fast_march(g, f, short_u), Error);
    }
}

// With obstacles: every free cell has a finite cost and, outside the goal,
// a neighbour of lower cost (no local minima, §5.2); obstacle cells are
// impassable.
TEST(CostField, ObstaclesLeaveNoLocalMinima) {
    auto& ctx = *test::shared_context();
    const Grid3 g = cube_grid(-1, 1, 32);
    const TriangleMesh mesh = merged({box_mesh({0, 0, 0}, {0.15f, 0.8f, 0.8f}), sphere_mesh({-0.5f, 0.5f, 0}, 0.25f)});
    const SdfGrid sdf = compute_sdf(ctx, mesh, g);
    const auto f = cost_slowness(g, sdf.phi, CostWeights{});
    const auto C = solve_cost(g, f, {sphere_goal(0.7f, 0, 0, 0.1f)});
    size_t free_cells = 0;
    for (uint32_t k = 0; k < 32; ++k)
        for (uint32_t j = 0; j < 32; ++j)
            for (uint32_t i = 0; i < 32; ++i) {
                const size_t c = g.index(i, j, k);
                if (sdf.phi[c] <= 0) {
                    EXPECT_TRUE(std::isinf(C[c]));
                    continue;
                }
                ++free_cells;
                ASSERT_TRUE(std::isfinite(C[c])) << i << " " << j << " " << k;
                if (C[c] == 0.0) continue;
                double lowest = INFINITY;
                const int p[3] = {int(i), int(j), int(k)};
                for (int a = 0; a < 3; ++a)
                    for (int s = -1; s <= 1; s += 2) {
                        int q[3] = {p[0], p[1], p[2]};
                        q[a] += s;
                        if (q[a] < 0 || q[a] >= 32) continue;
                        lowest = std::min(lowest, C[g.index(q[0], q[1], q[2])]);
                    }
                ASSERT_LT(lowest, C[c]) << i << " " << j << " " << k;
            }
    EXPECT_GT(free_cells, 20000u);
    // Going round the wall costs more than the straight line would.
    const size_t behind = g.index(4, 16, 16);
    EXPECT_GT(C[behind], 0.6 * 1.5);
}

TEST(CostField, BadGoals) {
    auto& ctx = *test::shared_context();
    const Grid3 g = cube_grid(-1, 1, 16);
    const SdfGrid sdf = compute_sdf(ctx, box_mesh({0, 0, 0}, {0.5f, 0.5f, 0.5f}), g);
    const auto f = cost_slowness(g, sdf.phi, CostWeights{});
    EXPECT_THROW(solve_cost(g, f, {point_goal(5, 0, 0)}), Error);       // outside the grid
    EXPECT_THROW(solve_cost(g, f, {point_goal(0, 0, 0)}), Error);       // inside the obstacle
    EXPECT_THROW(solve_cost(g, f, {point_goal(NAN, 0, 0)}), Error);
    EXPECT_THROW(solve_cost(g, f, {sphere_goal(0.8f, 0, 0, -1)}), Error);
    EXPECT_THROW(solve_cost(g, f, {}), Error);
    EXPECT_THROW(make_grid({0, 0, 0}, {1, 1, 1}, {0, 4, 4}, "grid"), Error);
    EXPECT_THROW(make_grid({0, 0, 0}, {1, 1, 1}, {100000, 100000, 100000}, "grid"), Error);
    EXPECT_THROW(make_grid({0, 0, 0}, {0, 1, 1}, {4, 4, 4}, "grid"), Error);
}

namespace {

// A maze of walls (boxes) in [0, 4] x [0, 4] x [0, 1]: three walls with
// alternating gaps; the goal is in the far corridor.
std::vector<TriangleMesh> maze_walls() {
    return {box_mesh({1.0f, 1.5f, 0.5f}, {0.1f, 1.5f, 0.6f}), box_mesh({2.0f, 2.5f, 0.5f}, {0.1f, 1.5f, 0.6f}),
            box_mesh({3.0f, 1.5f, 0.5f}, {0.1f, 1.5f, 0.6f})};
}

bool inside_maze_wall(const float* p) {
    const Vec3f c[3] = {{1.0f, 1.5f, 0.5f}, {2.0f, 2.5f, 0.5f}, {3.0f, 1.5f, 0.5f}};
    for (const auto& w : c)
        if (box_distance({p[0], p[1], p[2]}, w, {0.1f, 1.5f, 0.6f}) < 0) return true;
    return false;
}

}  // namespace

// Eq. 8 alone (no noise): insects released in random free cells of a maze all
// reach the goal within a bounded time, none ever inside a wall.
TEST(PathModel, MazeAgentsAllReachTheGoal) {
    auto ctx = test::shared_context();
    SwarmConfig sc;
    sc.capacity = 200;
    sc.domain_min = {0, 0, 0};
    sc.domain_max = {4, 4, 1};
    sc.interaction_radius = 0.1f;
    sc.dt = 0.02f;
    Swarm swarm(ctx, sc);
    PathModelConfig pc;
    pc.noise.gain = 0.0f;
    pc.obstacles = maze_walls();
    pc.resolution = {80, 80, 20};
    pc.speed = 1.0f;
    pc.groups.push_back({0, {sphere_goal(3.6f, 0.4f, 0.5f, 0.2f)}});
    auto model = std::make_shared<PathModel>(swarm, pc);
    const Grid3& g = model->grid();
    // Random free cells (at least one cell clear of the walls).
    std::mt19937 rng(7);
    std::vector<float> xyz;
    while (xyz.size() < 3 * 200) {
        const uint32_t i = rng() % g.dims[0], j = rng() % g.dims[1], k = rng() % g.dims[2];
        const size_t c = g.index(i, j, k);
        if (model->sdf()[c] < g.h || !(model->cost(0)[c] > 0)) continue;
        const auto p = g.center(i, j, k);
        xyz.insert(xyz.end(), {float(p[0]), float(p[1]), float(p[2])});
    }
    swarm.write(Attribute::Position, xyz.data(), 200);
    swarm.set_behavior(model);
    std::vector<float> p(600);
    // The longest path is about 4 corridors of 4 m: 20 m at 1 m/s.
    for (int frame = 0; frame < 60; ++frame) {
        swarm.step(25);
        swarm.read(Attribute::Position, p.data(), 200);
        for (int a = 0; a < 200; ++a) ASSERT_FALSE(inside_maze_wall(&p[3 * a])) << "agent " << a << " frame " << frame;
    }
    for (int a = 0; a < 200; ++a) {
        const double d = std::hypot(p[3 * a] - 3.6, p[3 * a + 1] - 0.4, p[3 * a + 2] - 0.5);
        EXPECT_LT(d, 0.2 + 2 * g.h) << "agent " << a;
    }
}

// Beyond the paper (its third limitation): two groups with opposite goals
// fly through each other; each reaches its own goal.
TEST(PathModel, TwoSwarmsCrossInOppositeDirections) {
    auto ctx = test::shared_context();
    SwarmConfig sc;
    sc.capacity = 100;
    sc.domain_min = {0, 0, 0};
    sc.domain_max = {4, 1, 1};
    sc.interaction_radius = 0.1f;
    sc.dt = 0.02f;
    Swarm swarm(ctx, sc);
    std::vector<float> xyz;
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.3f, 0.7f);
    for (int a = 0; a < 100; ++a) xyz.insert(xyz.end(), {a < 50 ? 0.3f : 3.7f, u(rng), u(rng)});
    swarm.write(Attribute::Position, xyz.data(), 100);
    PathModelConfig pc;
    pc.noise.gain = 0.1f;
    pc.resolution = {64, 16, 16};
    pc.speed = 1.0f;
    pc.min_distance = 0.02f;
    pc.groups.push_back({50, {sphere_goal(3.7f, 0.5f, 0.5f, 0.15f)}});
    pc.groups.push_back({50, {sphere_goal(0.3f, 0.5f, 0.5f, 0.15f)}});
    auto model = std::make_shared<PathModel>(swarm, pc);
    swarm.set_behavior(model);
    swarm.step(100);  // 2 s: halfway, the groups overlap
    std::vector<float> p(300);
    swarm.read(Attribute::Position, p.data(), 100);
    for (int a = 0; a < 100; ++a) EXPECT_NEAR(p[3 * a], 2.0f, 0.6f) << "agent " << a;
    swarm.step(200);
    swarm.read(Attribute::Position, p.data(), 100);
    for (int a = 0; a < 100; ++a) EXPECT_NEAR(p[3 * a], a < 50 ? 3.7f : 0.3f, 0.35f) << "agent " << a;
    const StepStats st = *swarm.take_step_stats();
    EXPECT_EQ(st.steps, 300u);
    EXPECT_GT(st.mde_moved_total, 0u);  // the crowd at each goal sphere is kept apart
}

// Chasing (§7): moving the goal recomputes the cost field, and the swarm follows.
TEST(PathModel, MovingTheGoalRecomputesTheField) {
    auto ctx = test::shared_context();
    SwarmConfig sc = test::cube_config(50, -1, 1, 0.1f);
    sc.agent_count = 50;
    sc.dt = 0.02f;
    Swarm swarm(ctx, sc);
    PathModelConfig pc;
    pc.noise.gain = 0.05f;
    pc.resolution = {32, 32, 32};
    pc.speed = 1.0f;
    pc.groups.push_back({0, {sphere_goal(-0.7f, 0, 0, 0.1f)}});
    auto model = std::make_shared<PathModel>(swarm, pc);
    swarm.set_behavior(model);
    EXPECT_THROW(model->set_goals(0, {point_goal(9, 9, 9)}), Error);
    EXPECT_THROW(model->set_goals(3, {point_goal(0, 0, 0)}), Error);
    EXPECT_EQ(model->config().groups[0].goals[0].center[0], -0.7f);  // unchanged by the errors
    const size_t far = model->grid().index(31, 16, 16);
    const double before = model->cost(0)[far];
    const double seconds = model->set_goals(0, {sphere_goal(0.7f, 0, 0, 0.1f)});
    EXPECT_GT(seconds, 0.0);
    EXPECT_LT(model->cost(0)[far], before);
    swarm.step(150);
    std::vector<float> p(150);
    swarm.read(Attribute::Position, p.data(), 50);
    for (int a = 0; a < 50; ++a) EXPECT_NEAR(p[3 * a], 0.7f, 0.3f);
}

// The mesh joins the curl noise's boundaries (Eq. 2 with the B-spline of the
// signed distance): with noise only (s0 = 0), insects around a mesh box stay
// out of it, and two runs are bitwise the same.
TEST(PathModel, MeshShapesTheCurlNoise) {
    auto ctx = test::shared_context();
    auto run = [&](std::vector<float>* out) {
        SwarmConfig sc = test::cube_config(300, -1, 1, 0.1f);
        sc.agent_count = 300;
        sc.seed = 5;
        sc.dt = 0.02f;
        Swarm swarm(ctx, sc);
        std::vector<float> xyz(900);
        swarm.read(Attribute::Position, xyz.data(), 300);
        for (int a = 0; a < 300; ++a)  // move agents out of the box
            if (box_distance({xyz[3 * a], xyz[3 * a + 1], xyz[3 * a + 2]}, {0, 0, 0}, {0.4f, 0.4f, 0.4f}) < 0.05)
                xyz[3 * a] = xyz[3 * a] < 0 ? -0.8f : 0.8f;
        swarm.write(Attribute::Position, xyz.data(), 300);
        PathModelConfig pc;
        pc.noise.scale = 0.5f;
        pc.noise.gain = 1.0f;
        pc.noise.boundary_distance = 0.3f;
        pc.noise.domain_walls = true;
        pc.obstacles.push_back(box_mesh({0, 0, 0}, {0.4f, 0.4f, 0.4f}));
        pc.resolution = {40, 40, 40};
        pc.speed = 0.0f;
        pc.groups.push_back({0, {point_goal(0.9f, 0.9f, 0.9f)}});
        swarm.set_behavior(std::make_shared<PathModel>(swarm, pc));
        size_t inside = 0;
        for (int frame = 0; frame < 10; ++frame) {
            swarm.step(20);
            swarm.read(Attribute::Position, out->data(), 300);
            for (int a = 0; a < 300; ++a)
                inside += box_distance({(*out)[3 * a], (*out)[3 * a + 1], (*out)[3 * a + 2]}, {0, 0, 0},
                                       {0.4f, 0.4f, 0.4f}) < -0.02;
        }
        return inside;
    };
    std::vector<float> a(900), b(900);
    EXPECT_EQ(run(&a), 0u);
    run(&b);
    EXPECT_EQ(a, b);
}

// The advance kernel against a plain C++ reference: with no noise, each
// agent's velocity is s0 times the trilinear interpolation (cell centres,
// clamped at the border) of the host's direction field (Eq. 8).
TEST(PathModel, GlobalVelocityMatchesTheHostReference) {
    auto ctx = test::shared_context();
    SwarmConfig sc = test::cube_config(500, -1, 1, 0.1f);
    sc.agent_count = 500;
    sc.seed = 9;
    Swarm swarm(ctx, sc);
    PathModelConfig pc;
    pc.noise.gain = 0.0f;
    pc.obstacles.push_back(sphere_mesh({0.1f, 0.2f, 0.0f}, 0.3f));
    pc.resolution = {20, 20, 20};
    pc.speed = 1.3f;
    pc.groups.push_back({0, {point_goal(0.8f, -0.7f, 0.5f)}});
    auto model = std::make_shared<PathModel>(swarm, pc);
    swarm.set_behavior(model);
    std::vector<float> p(1500), v(1500);
    swarm.read(Attribute::Position, p.data(), 500);
    swarm.step(1);
    swarm.read(Attribute::Velocity, v.data(), 500);
    const Grid3& g = model->grid();
    std::vector<float> dirs(4 * g.count());
    direction_field(g, model->cost(0), model->sdf(), dirs.data());
    for (int a = 0; a < 500; ++a) {
        double w[3];
        int i0[3];
        for (int k = 0; k < 3; ++k) {
            const double u = std::clamp((p[3 * a + k] - g.origin[k]) / g.h - 0.5, 0.0, double(g.dims[k] - 1));
            i0[k] = std::min(int(u), int(g.dims[k]) - 2);
            w[k] = u - i0[k];
        }
        for (int k = 0; k < 3; ++k) {
            double r = 0;
            for (int c = 0; c < 8; ++c) {
                const int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
                const double wt = (dx ? w[0] : 1 - w[0]) * (dy ? w[1] : 1 - w[1]) * (dz ? w[2] : 1 - w[2]);
                r += wt * dirs[4 * g.index(i0[0] + dx, i0[1] + dy, i0[2] + dz) + k];
            }
            ASSERT_NEAR(v[3 * a + k], 1.3 * r, 1e-4) << "agent " << a;
        }
    }
}

// Baking the mesh-aware curl noise (noise.baked) gives the procedural field
// up to the trilinear interpolation error.
TEST(PathModel, BakedMeshNoiseMatchesProcedural) {
    auto ctx = test::shared_context();
    auto first_velocities = [&](bool baked) {
        SwarmConfig sc = test::cube_config(400, -1, 1, 0.1f);
        sc.agent_count = 400;
        sc.seed = 4;
        Swarm swarm(ctx, sc);
        PathModelConfig pc;
        pc.noise.scale = 0.6f;
        pc.noise.gain = 1.0f;
        pc.noise.boundary_distance = 0.3f;
        pc.noise.baked = baked;
        pc.noise.bake_resolution = {97, 97, 97};
        pc.obstacles.push_back(box_mesh({0, 0, 0}, {0.3f, 0.3f, 0.3f}));
        pc.resolution = {32, 32, 32};
        pc.speed = 0.0f;
        pc.groups.push_back({0, {point_goal(0.9f, 0.9f, 0.9f)}});
        swarm.set_behavior(std::make_shared<PathModel>(swarm, pc));
        swarm.step(1);
        std::vector<float> v(1200);
        swarm.read(Attribute::Velocity, v.data(), 400);
        return v;
    };
    const auto a = first_velocities(false), b = first_velocities(true);
    double diff = 0, norm = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        diff += std::fabs(a[i] - b[i]);
        norm += std::fabs(a[i]);
    }
    EXPECT_GT(norm / a.size(), 0.1);
    EXPECT_LT(diff / norm, 0.05);
}

// On CPU devices the baked path (a mesh obstacle's baked local field) and
// the procedural curl noise with domain walls run SWCL_W agents per
// work-item: the same arithmetic as the one-agent kernel, so bitwise the
// same run.
TEST(PathModel, WideKernelMatchesTheScalarOne) {
    auto ctx = test::shared_context();
    auto run = [&](uint32_t width, bool procedural) {
        test::ScopedKernelWidth scoped_width(width);
        SwarmConfig sc = test::cube_config(1000, -1, 1, 0.1f);
        sc.agent_count = 1000;  // not a multiple of 16: the last work-item is partial
        sc.seed = 8;
        Swarm swarm(ctx, sc);
        PathModelConfig pc;
        if (procedural) {
            pc.noise.domain_walls = true;
        } else {
            pc.noise.baked = true;
            pc.noise.bake_resolution = {33, 33, 33};
            pc.obstacles.push_back(box_mesh({0, 0, 0}, {0.3f, 0.3f, 0.3f}));
        }
        pc.resolution = {24, 24, 24};
        pc.goal_falloff = 0.5f;
        pc.groups.push_back({600, {point_goal(0.9f, 0.9f, 0.9f)}});
        pc.groups.push_back({0, {point_goal(-0.9f, -0.9f, 0.9f)}});
        swarm.set_behavior(std::make_shared<PathModel>(swarm, pc));
        swarm.step(5);
        std::vector<float> p(3000);
        swarm.read(Attribute::Position, p.data(), 1000);
        return p;
    };
    for (const bool procedural : {false, true}) {
        const auto scalar = run(1, procedural), wide = run(16, procedural);
        EXPECT_EQ(scalar, wide) << (procedural ? "procedural curl noise" : "baked local field");
    }
}

// Chasing in a scenario: every `waypoint_every` steps group 0's goals move to
// the next waypoint (cyclically) and its cost field is recomputed.
TEST(PathModel, WaypointsMoveTheGoal) {
    auto ctx = test::shared_context();
    SwarmConfig sc = test::cube_config(20, -1, 1, 0.1f);
    sc.agent_count = 20;
    Swarm swarm(ctx, sc);
    PathModelConfig pc;
    pc.resolution = {16, 16, 16};
    pc.groups.push_back({0, {sphere_goal(0.5f, 0, 0, 0.2f), point_goal(0.6f, 0.1f, 0)}});
    pc.waypoints = {{-0.5f, 0.5f, 0.0f}, {0.0f, -0.5f, 0.5f}};
    pc.waypoint_every = 4;
    auto model = std::make_shared<PathModel>(swarm, pc);
    swarm.set_behavior(model);
    swarm.step(4);  // steps 0-3: no move yet
    EXPECT_EQ(model->recomputes(), 0u);
    swarm.step(1);  // step 4: first waypoint
    EXPECT_EQ(model->recomputes(), 1u);
    const auto& g = model->config().groups[0].goals;
    EXPECT_EQ(g[0].center, (std::array<float, 3>{-0.5f, 0.5f, 0.0f}));
    EXPECT_NEAR(g[1].center[0], -0.4f, 1e-6);  // the second goal keeps its offset
    swarm.step(8);  // steps 5-12: waypoints 2 (step 8) and 1 again (step 12)
    EXPECT_EQ(model->recomputes(), 3u);
    EXPECT_EQ(model->config().groups[0].goals[0].center, (std::array<float, 3>{-0.5f, 0.5f, 0.0f}));
    EXPECT_GT(model->recompute_seconds(), 0.0);
}
