// Chasing and positive phototaxis of the curl-noise paper (seed 004 §7):
// the target ball as a boundary of Eq. 2 whose cost field is recomputed as
// it moves, and the lamp's probabilistic pull (kernel against a C++
// reference; the moths circle the lamp).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "models/path_model.hpp"
#include "scenario/make_swarm.hpp"
#include "scenario/scenario.hpp"
#include "reference/noise_reference.hpp"
#include "test_support.hpp"

using namespace swarmcl;

namespace {

constexpr float kPi = 3.14159265358979f;

Goal point_goal(float x, float y, float z) {
    Goal g;
    g.center = {x, y, z};
    return g;
}

PathTarget target_at(float x, float y, float z, float r) {
    PathTarget t;
    t.center = {x, y, z};
    t.radius = r;
    return t;
}

// n agents on the sphere (c, r), on a Fibonacci lattice.
std::vector<float> on_sphere(uint32_t n, const std::array<float, 3>& c, float r) {
    std::vector<float> p(3 * n);
    for (uint32_t i = 0; i < n; ++i) {
        const double z = 1.0 - 2.0 * (i + 0.5) / n, s = std::sqrt(1.0 - z * z), a = 2.399963229728653 * i;
        p[3 * i] = c[0] + float(r * s * std::cos(a));
        p[3 * i + 1] = c[1] + float(r * s * std::sin(a));
        p[3 * i + 2] = c[2] + float(r * z);
    }
    return p;
}

// Mean |v . n| and mean |v| of the first-step noise velocities of agents on
// the sphere (c, r), with s0 = 0 (the velocity is the curl noise alone).
std::array<double, 2> normal_and_speed(const PathModelConfig& base, bool with_target) {
    auto ctx = test::shared_context();
    const uint32_t n = 400;
    SwarmConfig sc = test::cube_config(n, -1, 1, 0.1f);
    sc.agent_count = n;
    Swarm swarm(ctx, sc);
    const std::array<float, 3> c{0.1f, -0.2f, 0.05f};
    const float r = 0.3f;
    std::vector<float> p = on_sphere(n, c, r), v(3 * n);
    swarm.write(Attribute::Position, p.data(), n);
    PathModelConfig pc = base;
    if (with_target) pc.targets.push_back(target_at(c[0], c[1], c[2], r));
    swarm.set_behavior(std::make_shared<PathModel>(swarm, pc));
    swarm.step(1);
    swarm.read(Attribute::Velocity, v.data(), n);
    double vn = 0, speed = 0;
    for (uint32_t i = 0; i < n; ++i) {
        double d = 0, s = 0;
        for (int a = 0; a < 3; ++a) {
            d += v[3 * i + a] * (p[3 * i + a] - c[a]) / r;
            s += double(v[3 * i + a]) * v[3 * i + a];
        }
        vn += std::fabs(d);
        speed += std::sqrt(s);
    }
    return {vn / n, speed / n};
}

}  // namespace

// §7: "The ball is also regarded as a boundary condition used in Eq. 2": on
// its surface the curl noise has no normal component, with and without
// obstacle meshes (the mesh-aware kernel takes the ball as an analytic
// boundary too).  Without the target the same agents cross the surface.
TEST(PathChasing, TheTargetIsABoundaryOfEq2) {
    PathModelConfig pc;
    pc.noise.scale = 0.5f;
    pc.noise.gain = 1.0f;
    pc.noise.boundary_distance = 0.25f;
    pc.resolution = {32, 32, 32};
    pc.speed = 0.0f;
    pc.groups.push_back({0, {}});
    for (bool mesh : {false, true}) {
        SCOPED_TRACE(mesh ? "with a mesh obstacle" : "no mesh");
        PathModelConfig c = pc;
        if (mesh) c.obstacles.push_back(box_mesh({0.7f, 0.7f, 0.7f}, {0.15f, 0.15f, 0.15f}));
        const auto with = normal_and_speed(c, true);
        EXPECT_GT(with[1], 0.3);
        EXPECT_LT(with[0], 1e-3 * with[1]);
        c.groups[0].goals = {point_goal(0.9f, 0.9f, -0.9f)};
        const auto without = normal_and_speed(c, false);
        EXPECT_GT(without[0], 0.2 * without[1]);
    }
}

namespace {

// Moving a target (set_target) against a model built with it there: the
// cost fields, and the positions after `steps` steps of n agents, which are
// returned.  bake: the noise bake's nodes per axis; res: the cost grid's.
std::vector<float> expect_moving_the_target_matches_a_fresh_build(uint32_t bake, uint32_t res, uint32_t n,
                                                                   int steps) {
    auto ctx = test::shared_context();
    PathModelConfig pc;
    pc.noise.scale = 0.5f;
    pc.noise.gain = 0.8f;
    pc.noise.boundary_distance = 0.2f;
    pc.noise.baked = true;
    pc.noise.bake_resolution = {bake, bake, bake};
    pc.obstacles.push_back(box_mesh({0, 0, 0}, {0.25f, 0.25f, 0.25f}));
    pc.resolution = {res, res, res};
    pc.goal_falloff = 0.3f;
    pc.groups.push_back({0, {}});
    const std::array<float, 3> to{0.55f, -0.5f, 0.3f};
    auto run = [&](bool move, std::vector<double>* cost) {
        SwarmConfig sc = test::cube_config(n, -1, 1, 0.1f);
        sc.agent_count = n;
        sc.seed = 6;
        Swarm swarm(ctx, sc);
        PathModelConfig c = pc;
        c.targets.push_back(move ? target_at(-0.6f, 0.6f, -0.4f, 0.15f) : target_at(to[0], to[1], to[2], 0.15f));
        auto model = std::make_shared<PathModel>(swarm, c);
        swarm.set_behavior(model);
        if (move) {
            EXPECT_GT(model->set_target(0, to), 0.0);
            EXPECT_EQ(model->recomputes(), 1u);
            EXPECT_EQ(model->set_target(0, to), 0.0);  // the same place: nothing recomputed
            EXPECT_EQ(model->recomputes(), 1u);
            EXPECT_EQ(model->config().targets[0].center, to);
        }
        *cost = model->cost(0);
        swarm.step(steps);
        std::vector<float> p(3 * size_t(n));
        swarm.read(Attribute::Position, p.data(), n);
        return p;
    };
    std::vector<double> moved_cost, fresh_cost;
    const auto moved = run(true, &moved_cost), fresh = run(false, &fresh_cost);
    EXPECT_EQ(moved_cost, fresh_cost);
    EXPECT_EQ(moved, fresh);
    return moved;
}

}  // namespace

// "When the position of the target (ball) is changed, the minimum cost field
// is recomputed": moving a target gives bitwise the model built with it
// there (cost field, and the first step from the same positions: the
// rebaked mesh-aware noise and the global field).  Not moving recomputes nothing.
TEST(PathChasing, MovingTheTargetMatchesAFreshBuild) {
    expect_moving_the_target_matches_a_fresh_build(33, 28, 300, 3);
}

// The same on small grids, with the scalar kernels and the 16-lane ones
// (bitwise the same run): what scripts/oclgrind_check.py runs under
// Oclgrind, where the test above takes minutes.
TEST(PathChasing, SmallGridsMovingTheTargetMatchesAFreshBuildAtWidths1And16) {
    std::vector<std::vector<float>> by_width;
    for (uint32_t w : {1u, 16u}) {
        SCOPED_TRACE("width " + std::to_string(w));
        test::ScopedKernelWidth scoped_width(w);
        by_width.push_back(expect_moving_the_target_matches_a_fresh_build(9, 8, 21, 2));
    }
    EXPECT_EQ(by_width[0], by_width[1]);
}

// A target outside the grid or inside an obstacle, a NaN, a bad index or
// group: Error, and the model is as it was.
TEST(PathChasing, BadTargetsChangeNothing) {
    auto ctx = test::shared_context();
    SwarmConfig sc = test::cube_config(20, -1, 1, 0.1f);
    sc.agent_count = 20;
    Swarm swarm(ctx, sc);
    PathModelConfig pc;
    pc.obstacles.push_back(box_mesh({0, 0, 0}, {0.3f, 0.3f, 0.3f}));
    pc.resolution = {20, 20, 20};
    pc.groups.push_back({0, {}});
    pc.targets.push_back(target_at(0.6f, 0.6f, 0.6f, 0.1f));
    auto model = std::make_shared<PathModel>(swarm, pc);
    swarm.set_behavior(model);
    const std::vector<double> cost = model->cost(0);
    auto expect_error = [&](const std::function<void()>& f, const char* words) {
        try {
            f();
            ADD_FAILURE() << "no error (" << words << ")";
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
    };
    expect_error([&] { model->set_target(0, {0.0f, 0.05f, 0.0f}); }, "inside an obstacle");
    expect_error([&] { model->set_target(0, {1.5f, 0.0f, 0.0f}); }, "outside the path grid");
    expect_error([&] { model->set_target(0, {NAN, 0.0f, 0.0f}); }, "finite");
    expect_error([&] { model->set_target(1, {0.5f, 0.5f, 0.5f}); }, "does not exist");
    expect_error([&] { model->add_target({3, {0.5f, 0.5f, 0.5f}, 0.1f}); }, "group 3 does not exist");
    expect_error([&] { model->add_target({0, {0.5f, 0.5f, 0.5f}, 0.0f}); }, "radius");
    EXPECT_EQ(model->config().targets.size(), 1u);
    EXPECT_EQ(model->config().targets[0].center, (std::array<float, 3>{0.6f, 0.6f, 0.6f}));
    EXPECT_EQ(model->cost(0), cost);
    EXPECT_EQ(model->recomputes(), 0u);
    // In the constructor: a target in the box, a waypoint outside the grid.
    PathModelConfig bad = pc;
    bad.targets[0].center = {0.1f, 0.1f, 0.1f};
    EXPECT_THROW(std::make_shared<PathModel>(swarm, bad), Error);
    bad = pc;
    bad.waypoints = {{0.5f, 0.5f, 0.5f}, {2.0f, 0.0f, 0.0f}};
    EXPECT_THROW(std::make_shared<PathModel>(swarm, bad), Error);
    // A group with neither goals nor a target.
    bad = pc;
    bad.targets.clear();
    EXPECT_THROW(std::make_shared<PathModel>(swarm, bad), Error);
}

// The lamp's pull in the kernel against a plain C++ reference (Philox draw,
// the turn about the vertical axis, Eq. 3's fade near the bulb), with no
// noise and no global field: V = pull.
TEST(PathPhototaxis, LampPullMatchesTheHostReference) {
    auto ctx = test::shared_context();
    const uint32_t n = 500;
    SwarmConfig sc = test::cube_config(n, -1, 1, 0.1f);
    sc.agent_count = n;
    sc.seed = 12;
    Swarm swarm(ctx, sc);
    PathModelConfig pc;
    pc.noise.gain = 0.0f;
    pc.noise.seed = 77;
    pc.resolution = {16, 16, 16};
    pc.speed = 0.0f;
    pc.groups.push_back({0, {point_goal(0.5f, 0.5f, 0.5f)}});
    PathLamp& L = pc.lamp;
    L.enabled = true;
    L.center = {0.1f, -0.1f, 0.2f};
    L.radius = 0.15f;
    L.probability = 0.4f;
    L.speed = 0.7f;
    L.angle = 1.0f;
    L.keep_out = 0.5f;
    swarm.set_behavior(std::make_shared<PathModel>(swarm, pc));
    std::vector<float> p(3 * n), v(3 * n);
    swarm.read(Attribute::Position, p.data(), n);
    const uint32_t step = 0;
    swarm.step(1);
    swarm.read(Attribute::Velocity, v.data(), n);
    size_t pulled = 0;
    for (uint32_t a = 0; a < n; ++a) {
        const double u = swcl_ref::u01_co(swcl_ref::rand_u4(77, a, step, 24u, 0u)[0]);
        double e[3] = {0, 0, 0};
        if (u < L.probability) {
            ++pulled;
            const double r[3] = {L.center[0] - p[3 * a], L.center[1] - p[3 * a + 1], L.center[2] - p[3 * a + 2]};
            const double dist = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
            const double hl = std::hypot(r[0], r[1]);
            const double fade = swcl_ref::ramp(std::max(dist - L.radius, 0.0) / L.keep_out);
            const double t[3] = {r[1] / hl, -r[0] / hl, 0.0};  // z x (p - lamp)
            for (int k = 0; k < 3; ++k)
                e[k] = L.speed * (std::cos(L.angle) * fade * r[k] / dist + std::sin(L.angle) * t[k]);
        }
        for (int k = 0; k < 3; ++k) ASSERT_NEAR(v[3 * a + k], e[k], 2e-5) << "agent " << a;
    }
    EXPECT_GT(pulled, n / 4);  // probability 0.4: about 200
    EXPECT_LT(pulled, n / 2);
}

// A lamp outside the grid, with no free space around it, or with bad
// parameters: Error, the model keeps its lamp.
TEST(PathPhototaxis, BadLampsChangeNothing) {
    auto ctx = test::shared_context();
    SwarmConfig sc = test::cube_config(20, -1, 1, 0.1f);
    sc.agent_count = 20;
    Swarm swarm(ctx, sc);
    PathModelConfig pc;
    pc.obstacles.push_back(box_mesh({0, 0, 0}, {0.6f, 0.6f, 0.6f}));
    pc.resolution = {20, 20, 20};
    pc.groups.push_back({0, {point_goal(0.8f, 0.8f, 0.8f)}});
    auto model = std::make_shared<PathModel>(swarm, pc);
    PathLamp good;
    good.enabled = true;
    good.center = {0.8f, -0.8f, 0.8f};
    model->set_lamp(good);
    auto expect_error = [&](PathLamp lamp, const char* words) {
        try {
            model->set_lamp(lamp);
            ADD_FAILURE() << "no error (" << words << ")";
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
        }
        EXPECT_EQ(model->config().lamp.center, good.center);
    };
    PathLamp l = good;
    l.center = {0.0f, 0.0f, 0.0f};  // in the middle of the box
    expect_error(l, "no free space around it");
    l.center = {0.0f, 0.0f, 3.0f};
    expect_error(l, "outside the path grid");
    l = good, l.probability = 1.5f;
    expect_error(l, "probability");
    l = good, l.angle = 2.0f;
    expect_error(l, "angle");
    l = good, l.keep_out = 0.0f;
    expect_error(l, "keep_out");
    PathModelConfig bad = pc;
    bad.lamp = good;
    bad.lamp.center = {0.1f, 0.0f, 0.0f};
    EXPECT_THROW(std::make_shared<PathModel>(swarm, bad), Error);
}

// "The moths circle the lamp" (Fig. 1, Fig. 10): over the run's second half
// the mean angular momentum about the lamp's vertical axis is clearly
// non-zero and of one sign for most moths, and they stay near the lamp but
// out of its bulb.  With the pull straight at the lamp (angle 0, the
// paper's words alone) the circling is much weaker.
TEST(PathPhototaxis, MothsCircleTheLamp) {
    auto ctx = test::shared_context();
    struct Result {
        double mean_l = 0, mean_abs_l = 0, same_sign = 0, mean_dist = 0, min_dist = 1e9;
    };
    const std::array<float, 3> lamp{0.0f, 0.0f, 0.3f};
    const float bulb = 0.15f;
    auto run = [&](float angle) {
        const uint32_t n = 120;
        SwarmConfig sc = test::cube_config(n, -2, 2, 0.1f);
        sc.agent_count = n;
        sc.seed = 3;
        sc.dt = 1.0f / 30.0f;
        Swarm swarm(ctx, sc);
        PathModelConfig pc;
        pc.noise.scale = 0.6f;
        pc.noise.gain = 0.3f;
        pc.noise.seed = 5;
        pc.noise.boundary_distance = 0.2f;
        pc.noise.domain_walls = true;
        pc.obstacles.push_back(sphere_mesh({lamp[0], lamp[1], lamp[2]}, bulb));
        pc.obstacles.push_back(box_mesh({0.0f, 0.0f, -1.15f}, {0.05f, 0.05f, 1.3f}));  // the post
        pc.resolution = {40, 40, 40};
        pc.speed = 1.0f;
        pc.goal_falloff = 0.5f;
        pc.groups.push_back({0, {[&] {
                                 Goal g;
                                 g.kind = Goal::Kind::Sphere;
                                 g.center = lamp;
                                 g.radius = 0.6f;
                                 return g;
                             }()}});
        pc.lamp.enabled = true;
        pc.lamp.center = lamp;
        pc.lamp.radius = bulb;
        pc.lamp.probability = 0.5f;
        pc.lamp.speed = 1.0f;
        pc.lamp.angle = angle;
        pc.lamp.keep_out = 0.3f;
        swarm.set_behavior(std::make_shared<PathModel>(swarm, pc));
        swarm.step(300);
        std::vector<double> per_agent(n, 0.0);
        std::vector<float> p(3 * n), v(3 * n);
        Result r;
        const int frames = 300;
        for (int f = 0; f < frames; ++f) {
            swarm.step(1);
            swarm.read(Attribute::Position, p.data(), n);
            swarm.read(Attribute::Velocity, v.data(), n);
            for (uint32_t a = 0; a < n; ++a) {
                const double x = p[3 * a] - lamp[0], y = p[3 * a + 1] - lamp[1], z = p[3 * a + 2] - lamp[2];
                const double l = x * v[3 * a + 1] - y * v[3 * a];
                per_agent[a] += l / frames;
                r.mean_l += l / (double(frames) * n);
                r.mean_abs_l += std::fabs(l) / (double(frames) * n);
                const double d = std::sqrt(x * x + y * y + z * z);
                r.mean_dist += d / (double(frames) * n);
                r.min_dist = std::min(r.min_dist, d);
            }
        }
        for (double l : per_agent) r.same_sign += (l * r.mean_l > 0) / double(n);
        return r;
    };
    const Result circling = run(70.0f * kPi / 180.0f), straight = run(0.0f);
    RecordProperty("mean_L", std::to_string(circling.mean_l));
    std::printf("circling: mean L %.4f, mean |L| %.4f, same sign %.2f, mean dist %.3f, min dist %.3f\n",
                circling.mean_l, circling.mean_abs_l, circling.same_sign, circling.mean_dist, circling.min_dist);
    std::printf("straight: mean L %.4f, mean |L| %.4f, same sign %.2f, mean dist %.3f, min dist %.3f\n",
                straight.mean_l, straight.mean_abs_l, straight.same_sign, straight.mean_dist, straight.min_dist);
    EXPECT_GT(circling.mean_l, 0.3 * circling.mean_abs_l);  // counter-clockwise seen from +z
    EXPECT_GT(circling.same_sign, 0.8);
    EXPECT_LT(circling.mean_dist, 1.0);
    EXPECT_GT(circling.min_dist, bulb);
    EXPECT_LT(std::fabs(straight.mean_l), 0.2 * circling.mean_l);
}

// The scenario reader's "targets" and "lamp" (examples/scenarios/path_chasing.json,
// path_phototaxis.json): read as given, bad values named by their key path,
// and a target or lamp the model refuses (inside an obstacle, outside the
// grid, no free space) named when the swarm is made.
TEST(PathScenario, TargetsAndLampAreReadAndChecked) {
    const std::string dir = std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios/";
    const auto chasing = std::get<PathModelConfig>(load_scenario(dir + "path_chasing.json").model);
    ASSERT_EQ(chasing.targets.size(), 1u);
    EXPECT_TRUE(chasing.groups[0].goals.empty());  // the ball is the goal
    EXPECT_FALSE(chasing.waypoints.empty());
    const auto photo = std::get<PathModelConfig>(load_scenario(dir + "path_phototaxis.json").model);
    EXPECT_TRUE(photo.lamp.enabled);
    EXPECT_NEAR(photo.lamp.angle, 70.0 * kPi / 180.0, 1e-6);
    const std::string head =
        R"({"name": "t", "domain": {"min": [0,0,0], "max": [4,2,2]}, "agents": {"count": 4},
            "obstacles": [{"type": "box", "center": [2,1,1], "half_extents": [0.4,0.4,0.4]}],)";
    auto error = [&](const std::string& tail, bool make = false) -> std::string {
        try {
            const Scenario s = parse_scenario(head + tail);
            if (make) make_swarm(test::shared_context(), s);
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    };
    const std::string path = R"("model": {"type": "path", "grid": {"resolution": [20, 10, 10]}, )";
    EXPECT_EQ(error(path + R"("targets": [{"center": [3.5,1,1], "radius": 0.2}]}})", true), "");
    EXPECT_EQ(error(path + R"("goals": [{"center": [3.5,1,1]}], "lamp": {"center": [3,1,1], "angle_deg": 45}}})", true), "");
    EXPECT_NE(error(path + R"("targets": [{"center": [3.5,1,1]}]}})").find("model.targets[0].radius: missing"),
              std::string::npos);
    EXPECT_NE(error(path + R"("targets": [{"center": [3.5,1,1], "radius": 0.2, "colour": 1}]}})")
                  .find("model.targets[0].colour: unknown key"),
              std::string::npos);
    EXPECT_NE(error(path + R"("targets": []}})").find("model.targets"), std::string::npos);
    EXPECT_NE(error(path + R"("goals": [{"center": [3.5,1,1]}], "lamp": {"center": [3,1,1], "probability": 2}}})")
                  .find("model.lamp.probability"),
              std::string::npos);
    EXPECT_NE(error(path + R"("goals": [{"center": [3.5,1,1]}], "lamp": {"center": [3,1,1], "angle_deg": 120}}})")
                  .find("model.lamp.angle_deg"),
              std::string::npos);
    EXPECT_NE(error(path + R"("goals": [{"center": [3.5,1,1]}], "lamp": {"radius": 0.1}}})").find("model.lamp.center: missing"),
              std::string::npos);
    // Refused by the model when the swarm is made.
    EXPECT_NE(error(path + R"("targets": [{"center": [2,1,1], "radius": 0.2}]}})", true).find("inside an obstacle"),
              std::string::npos);
    EXPECT_NE(error(path + R"("targets": [{"center": [5,1,1], "radius": 0.2}]}})", true).find("outside the path grid"),
              std::string::npos);
    EXPECT_NE(error(path + R"("targets": [{"center": [3.5,1,1], "radius": 0.2}], "moving_goal": {"waypoints": [[2.1,1,1]]}}})", true)
                  .find("waypoint 0"),
              std::string::npos);
    EXPECT_NE(error(path + R"("goals": [{"center": [3.5,1,1]}], "lamp": {"center": [2,1,1], "radius": 0.01, "keep_out": 0.01}}})", true)
                  .find("no free space around it"),
              std::string::npos);
}

// The lamp's pull and a target in the explicit-width kernel (CPU devices,
// baked noise): bitwise the one-agent kernel's run.
TEST(PathPhototaxis, WideKernelMatchesTheScalarOne) {
    auto ctx = test::shared_context();
    auto run = [&](uint32_t width) {
        test::ScopedKernelWidth scoped_width(width);
        SwarmConfig sc = test::cube_config(700, -1, 1, 0.1f);
        sc.agent_count = 700;  // not a multiple of 16
        sc.seed = 8;
        Swarm swarm(ctx, sc);
        PathModelConfig pc;
        pc.noise.baked = true;
        pc.noise.bake_resolution = {33, 33, 33};
        pc.obstacles.push_back(sphere_mesh({0, 0, 0}, 0.2f));
        pc.resolution = {24, 24, 24};
        pc.goal_falloff = 0.5f;
        pc.groups.push_back({400, {point_goal(0.9f, 0.9f, 0.9f)}});
        pc.groups.push_back({0, {}});
        pc.targets.push_back({1, {-0.6f, 0.5f, 0.0f}, 0.15f});
        pc.lamp.enabled = true;
        pc.lamp.radius = 0.2f;
        pc.lamp.angle = 1.1f;
        auto model = std::make_shared<PathModel>(swarm, pc);
        swarm.set_behavior(model);
        swarm.step(5);
        model->set_target(0, {-0.5f, -0.5f, 0.2f});
        swarm.step(5);
        std::vector<float> p(2100);
        swarm.read(Attribute::Position, p.data(), 700);
        return p;
    };
    const auto scalar = run(1), wide = run(16);
    EXPECT_EQ(scalar, wide);
}
