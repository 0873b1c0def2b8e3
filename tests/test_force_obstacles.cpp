// Mesh obstacles of the force model (issue 5): the kernels' sampled signed
// distance against the exact distance and the host grid, insects flying at
// a mesh never inside it (exact inside test), a mesh sphere avoided like the
// analytic sphere, runs without mesh obstacles bitwise unchanged, bad input
// through the C API and scenario files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <random>
#include <string>

#include "core/error.hpp"
#include "scenario/scenario.hpp"
#include "models/force_model.hpp"
#include "swarm/swarm.hpp"
#include "capi_fixture.hpp"
#include "swarmcl/swarmcl.h"
#include "test_support.hpp"

using namespace swarmcl;
using swarmcl::test::shared_context;

namespace {

std::shared_ptr<Swarm> make_swarm(uint32_t n, uint64_t seed, float dt = 1.0f / 60.0f) {
    SwarmConfig c = test::cube_config(n, -4.0f, 4.0f, 1.0f);
    c.agent_count = n;
    c.seed = seed;
    c.dt = dt;
    return std::make_shared<Swarm>(shared_context(), c);
}

// Host reference of the kernel's read: trilinear interpolation of the
// cell-centred grid (double).
double trilinear(const SdfGrid& s, const std::array<double, 3>& p) {
    const Grid3& g = s.grid;
    std::array<double, 3> u;
    std::array<uint32_t, 3> i0;
    for (size_t a = 0; a < 3; ++a) {
        u[a] = (p[a] - g.origin[a]) / g.h - 0.5;
        i0[a] = std::min<uint32_t>(uint32_t(std::floor(u[a])), g.dims[a] - 2);
        u[a] -= i0[a];
    }
    double v = 0.0;
    for (uint32_t c = 0; c < 8; ++c) {
        double w = 1.0;
        for (size_t a = 0; a < 3; ++a) w *= (c >> a & 1u) ? u[a] : 1.0 - u[a];
        v += w * s.phi[g.index(i0[0] + (c & 1u), i0[1] + (c >> 1 & 1u), i0[2] + (c >> 2 & 1u))];
    }
    return v;
}

// Insects start in a cluster at x = -2 and fly to a sphere of targets at
// x = +2; the obstacle sits in between.
ForceModelConfig flight_config() {
    ForceModelConfig c;
    c.min_spacing = 0.0f;
    c.keyframes.push_back({0, sphere_mesh({2.0f, 0.0f, 0.0f}, 0.4f, 12, 24)});
    c.obstacle_range = 0.5f;
    return c;
}

void place_cluster(Swarm& swarm, uint32_t n) {
    std::vector<float> start = test::random_points(n, -0.35f, 0.35f, 11);
    for (uint32_t i = 0; i < n; ++i) start[3 * i] -= 2.0f;
    swarm.write(Attribute::Position, start.data(), n);
}

std::string write_file(const std::string& name, const std::string& text) {
    const std::string path = ::testing::TempDir() + name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

const char* kBoxObj =
    "v -0.3 -0.6 -0.6\nv 0.3 -0.6 -0.6\nv 0.3 0.6 -0.6\nv -0.3 0.6 -0.6\n"
    "v -0.3 -0.6 0.6\nv 0.3 -0.6 0.6\nv 0.3 0.6 0.6\nv -0.3 0.6 0.6\n"
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";

}  // namespace

// ---- the sampled distance ---------------------------------------------------

TEST(ForceMeshObstacles, SampledDistanceOfASphereMeshIsWithinACell) {
    auto swarm = make_swarm(8, 1);
    ForceModelConfig c;
    const std::array<float, 3> centre{0.3f, -0.2f, 0.1f};
    const float r = 1.0f;
    c.mesh_obstacles.push_back(sphere_mesh(centre, r, 24, 48));
    c.obstacle_range = 1.0f;
    ForceModel model(*swarm, c);
    const Grid3& g = model.mesh_grid();
    EXPECT_DOUBLE_EQ(g.h, 0.25);  // obstacle_range / 4
    const SdfGrid host = force_mesh_sdf(swarm->context(), c);
    // Points within range of the surface, inside and out.
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f), rad(0.2f, r + c.obstacle_range);
    std::vector<float> xyz;
    while (xyz.size() < 3 * 2000) {
        std::array<float, 3> d{u(rng), u(rng), u(rng)};
        const float l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (l < 0.1f || l > 1.0f) continue;
        const float s = rad(rng) / l;
        for (size_t a = 0; a < 3; ++a) xyz.push_back(centre[a] + s * d[a]);
    }
    const std::vector<cl_float4> got = model.sample_mesh_obstacles(*swarm, xyz);
    double worst_exact = 0.0, worst_grid = 0.0, worst_normal = 0.0;
    for (size_t i = 0; i < got.size(); ++i) {
        const std::array<double, 3> p{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
        std::array<double, 3> q;
        for (size_t a = 0; a < 3; ++a) q[a] = p[a] - centre[a];
        const double l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        const double exact = l - r;
        worst_exact = std::max(worst_exact, std::fabs(got[i].s[3] - exact));
        worst_grid = std::max(worst_grid, std::fabs(got[i].s[3] - trilinear(host, p)));
        if (l > 0.5) {  // away from the centre, where the distance has a kink
            double cosine = 0.0;
            for (size_t a = 0; a < 3; ++a) cosine += got[i].s[a] * q[a] / l;
            worst_normal = std::max(worst_normal, 1.0 - cosine);
        }
    }
    std::printf("[ mesh ] sphere: |sampled - exact| <= %.4f m (cell %.3f), |sampled - host trilinear| <= %.2e, "
                "1 - cos(normal) <= %.4f\n", worst_exact, g.h, worst_grid, worst_normal);
    EXPECT_LT(worst_exact, g.h);   // within one cell
    EXPECT_LT(worst_grid, 1e-4);   // the kernel reads the host grid
    EXPECT_LT(worst_normal, 0.05);
    // Beyond the grid: out of range.
    const std::vector<cl_float4> far = model.sample_mesh_obstacles(*swarm, {10.0f, 0.0f, 0.0f});
    EXPECT_TRUE(std::isinf(far[0].s[3]));
}

// ---- the paper's property: insects never enter an obstacle (§6) ---------------

TEST(ForceMeshObstacles, InsectsFlyingAtABoxMeshNeverEndUpInside) {
    const uint32_t n = 150;
    auto swarm = make_swarm(n, 3, 0.05f);
    place_cluster(*swarm, n);
    ForceModelConfig c = flight_config();
    // Off the flight line (the face spans y in [0.05, 0.85]): half of the
    // cluster hits the face and slides off its edge towards the targets (a
    // face square across the way would hold insects at its centre, where
    // the pull has no tangential part).
    const std::array<float, 3> centre{0.0f, 0.45f, 0.0f}, half{0.3f, 0.4f, 0.6f};
    c.mesh_obstacles.push_back(box_mesh(centre, half));
    c.min_distance = 0.05f;  // MDE pushes insects about; the push-out follows it
    swarm->set_behavior(std::make_shared<ForceModel>(*swarm, c));
    std::vector<float> p(3 * size_t(n));
    double deepest = -HUGE_VAL;  // max over insects and steps of the exact inside depth
    uint32_t most_near = 0;
    for (int step = 0; step < 300; ++step) {
        swarm->step(1);
        swarm->read(Attribute::Position, p.data(), n);
        uint32_t near = 0;
        for (uint32_t i = 0; i < n; ++i) {
            double depth = HUGE_VAL;  // > 0: strictly inside the box
            for (size_t a = 0; a < 3; ++a)
                depth = std::min(depth, double(half[a]) - std::fabs(double(p[3 * i + a]) - centre[a]));
            deepest = std::max(deepest, depth);
            near += depth > -0.1;
        }
        most_near = std::max(most_near, near);
    }
    double mean_x = 0.0;
    for (uint32_t i = 0; i < n; ++i) mean_x += p[3 * i] / n;
    std::printf("[ mesh ] box: deepest %.4f m (<= 0: never inside), up to %u insects within 10 cm, mean x %.2f\n",
                deepest, most_near, mean_x);
    EXPECT_LE(deepest, 0.0);
    EXPECT_GT(most_near, 10u);  // the box was in the way
    EXPECT_GT(mean_x, 1.0);     // and they got past it
}

// Insects put just inside a box mesh (up to 10 cm deep behind one face) are
// outside it after the next step (the push-out after each step), where the
// kernels' sampled distance is within a cell of the exact one.  Small, for
// scripts/oclgrind_check.py (the tests above take minutes under Oclgrind).
TEST(ForceMeshObstacles, InsectsJustInsideABoxMeshAreOutsideAfterTheNextStep) {
    const uint32_t n = 12;
    auto swarm = make_swarm(n, 5, 0.05f);
    const std::array<float, 3> centre{0.0f, 0.45f, 0.0f}, half{0.3f, 0.4f, 0.6f};
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> depth(0.02f, 0.1f), across(-0.6f, 0.6f);
    std::vector<float> p(3 * size_t(n));
    for (uint32_t i = 0; i < n; ++i) {
        p[3 * i] = centre[0] - half[0] + depth(rng);  // behind the -x face
        p[3 * i + 1] = centre[1] + across(rng) * half[1];
        p[3 * i + 2] = centre[2] + across(rng) * half[2];
    }
    swarm->write(Attribute::Position, p.data(), n);
    ForceModelConfig c = flight_config();
    c.mesh_obstacles.push_back(box_mesh(centre, half));
    auto model = std::make_shared<ForceModel>(*swarm, c);
    swarm->set_behavior(model);
    swarm->step(1);
    swarm->read(Attribute::Position, p.data(), n);
    // And the kernel's sampled distance there: within a cell of the exact one.
    const std::vector<cl_float4> sampled = model->sample_mesh_obstacles(*swarm, p);
    const double h = model->mesh_grid().h;
    for (uint32_t i = 0; i < n; ++i) {
        double inside = HUGE_VAL, out2 = 0.0;  // inside > 0: strictly inside the box
        for (size_t a = 0; a < 3; ++a) {
            ASSERT_TRUE(std::isfinite(p[3 * i + a]));
            const double q = std::fabs(double(p[3 * i + a]) - centre[a]) - half[a];
            inside = std::min(inside, -q);
            out2 += std::max(q, 0.0) * std::max(q, 0.0);
        }
        EXPECT_LE(inside, 0.0) << "insect " << i;
        EXPECT_NEAR(sampled[i].s[3], std::sqrt(out2), h) << "insect " << i;
    }
}

TEST(ForceMeshObstacles, MeshSphereIsAvoidedLikeTheAnalyticSphere) {
    const uint32_t n = 120;
    const float r = 0.5f;
    std::vector<std::vector<float>> runs;
    std::vector<double> closest;
    for (int mesh = 0; mesh < 2; ++mesh) {
        auto swarm = make_swarm(n, 4, 0.05f);
        place_cluster(*swarm, n);
        ForceModelConfig c = flight_config();
        if (mesh) {
            c.mesh_obstacles.push_back(sphere_mesh({0.0f, 0.0f, 0.0f}, r, 24, 48));
        } else {
            Boundary b;
            b.kind = Boundary::Kind::Sphere;
            b.radius = r;
            c.obstacles.push_back(b);
        }
        swarm->set_behavior(std::make_shared<ForceModel>(*swarm, c));
        std::vector<float> p(3 * size_t(n)), trace;
        double nearest = HUGE_VAL;
        for (int chunk = 0; chunk < 30; ++chunk) {
            swarm->step(10);
            swarm->read(Attribute::Position, p.data(), n);
            std::array<double, 3> centroid{0, 0, 0};
            for (uint32_t i = 0; i < n; ++i) {
                nearest = std::min(nearest, std::sqrt(double(p[3 * i]) * p[3 * i] + double(p[3 * i + 1]) * p[3 * i + 1] +
                                                      double(p[3 * i + 2]) * p[3 * i + 2]));
                for (size_t a = 0; a < 3; ++a) centroid[a] += p[3 * i + a] / n;
            }
            trace.insert(trace.end(), centroid.begin(), centroid.end());
        }
        runs.push_back(trace);
        closest.push_back(nearest);
    }
    double worst = 0.0;
    for (size_t k = 0; k + 2 < runs[0].size(); k += 3) {
        double d2 = 0.0;
        for (size_t a = 0; a < 3; ++a) d2 += (runs[0][k + a] - runs[1][k + a]) * (runs[0][k + a] - runs[1][k + a]);
        worst = std::max(worst, std::sqrt(d2));
    }
    std::printf("[ mesh ] sphere r %.2f: closest approach analytic %.3f m, mesh %.3f m; centroids differ by <= %.3f m\n",
                r, closest[0], closest[1], worst);
    EXPECT_GE(closest[0], r - 0.02);
    EXPECT_GE(closest[1], r - 0.02);
    EXPECT_NEAR(closest[1], closest[0], 0.1);
    EXPECT_LT(worst, 0.1);
}

// ---- without mesh obstacles nothing changes ------------------------------------

TEST(ForceMeshObstacles, AnOutOfReachMeshLeavesTheRunBitwiseUnchanged) {
    // The analytic path (sphere ramp, MDE and its push-out) with and without
    // a mesh obstacle far from every insect: the same bits.
    const uint32_t n = 100;
    std::vector<std::vector<float>> out;
    for (int mesh = 0; mesh < 2; ++mesh) {
        auto swarm = make_swarm(n, 9, 0.05f);
        place_cluster(*swarm, n);
        ForceModelConfig c = flight_config();
        Boundary b;
        b.kind = Boundary::Kind::Sphere;
        b.radius = 0.4f;
        c.obstacles.push_back(b);
        c.min_distance = 0.1f;
        if (mesh) c.mesh_obstacles.push_back(box_mesh({30.0f, 30.0f, 30.0f}, {0.5f, 0.5f, 0.5f}));
        swarm->set_behavior(std::make_shared<ForceModel>(*swarm, c));
        swarm->step(60);
        std::vector<float> p(3 * size_t(n)), v(3 * size_t(n));
        swarm->read(Attribute::Position, p.data(), n);
        swarm->read(Attribute::Velocity, v.data(), n);
        p.insert(p.end(), v.begin(), v.end());
        out.push_back(p);
    }
    ASSERT_EQ(out[0].size(), out[1].size());
    EXPECT_EQ(std::memcmp(out[0].data(), out[1].data(), out[0].size() * sizeof(float)), 0);
}

// ---- bad input -----------------------------------------------------------------

TEST(ForceMeshObstacles, BadConfigsAreRejected) {
    auto swarm = make_swarm(8, 1);
    auto rejected = [&](ForceModelConfig c, const char* needle) {
        try {
            ForceModel m(*swarm, c);
            ADD_FAILURE() << "accepted, expected " << needle;
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    ForceModelConfig c;
    c.mesh_obstacles.push_back(TriangleMesh{});
    rejected(c, "empty or degenerate");
    c.mesh_obstacles[0] = box_mesh({0, 0, 0}, {1, 1, 1});
    c.mesh_obstacles[0].vertices[2][1] = std::nanf("");
    rejected(c, "finite");
    c.mesh_obstacles[0] = box_mesh({0, 0, 0}, {1, 1, 1});
    c.mesh_cell = 0.001f;  // 2.6 m / 1 mm per axis: 1.7e10 cells
    rejected(c, "raise mesh_cell");
    c.mesh_cell = std::nanf("");
    rejected(c, "mesh_cell");
}

class ForceMeshCApi : public swarmcl::test::CApiSwarmTest {
protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(create([](swcl_swarm_desc& s) {
            s.capacity = 100;
            s.agent_count = 100;
            s.seed = 3;
            for (int a = 0; a < 3; ++a) s.domain_min[a] = -3, s.domain_max[a] = 3;
            s.interaction_radius = 1.0f;
        }));
    }
    // The current model's first target (its keyframe's offset tells models apart).
    float first_target_x() {
        float xyz[3] = {0, 0, 0};
        EXPECT_EQ(swcl_swarm_force_get_targets(swarm, xyz, 1), SWCL_OK) << swcl_last_error();
        return xyz[0];
    }
};

TEST_F(ForceMeshCApi, MeshesObjFilesAndPrimitivesAndBadInputChangesNothing) {
    swcl_keyframe k{};
    k.shape = "sphere";
    k.scale = 0.5f;
    k.offset[0] = 20.0f;  // the good model's targets are far in +x
    swcl_force_model_desc d = swcl_force_model_desc_default();
    EXPECT_EQ(d.mesh_obstacles, nullptr);
    EXPECT_EQ(d.mesh_obstacle_count, 0u);
    EXPECT_EQ(d.mesh_cell, 0.0f);
    d.keyframes = &k;
    d.keyframe_count = 1;
    const std::string obj = write_file("swarmcl_force_box.obj", kBoxObj);
    const float tet[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
    const uint32_t tet_idx[] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    swcl_obstacle o[4] = {};
    o[0].type = SWCL_OBSTACLE_OBJ;
    o[0].path = obj.c_str();
    o[1].type = SWCL_OBSTACLE_MESH;
    o[1].vertices = tet;
    o[1].vertex_count = 4;
    o[1].indices = tet_idx;
    o[1].triangle_count = 4;
    o[2].type = SWCL_OBSTACLE_CYLINDER;
    o[2].center[1] = 1.5f;
    o[2].radius = 0.2f;
    o[2].height = 1.0f;
    o[3].type = SWCL_OBSTACLE_SPHERE;
    o[3].center[2] = -1.5f;
    o[3].radius = 0.3f;
    d.mesh_obstacles = o;
    d.mesh_obstacle_count = 4;
    ASSERT_EQ(swcl_swarm_force_set_model(swarm, &d), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(swarm, 2), SWCL_OK) << swcl_last_error();
    EXPECT_GT(first_target_x(), 15.0f);

    // Each bad descriptor: a clear status, and the model in place stays (its
    // targets at +20 m, not the bad one's at -20 m).
    swcl_force_model_desc bad = d;
    swcl_keyframe k2 = k;
    k2.offset[0] = -20.0f;
    bad.keyframes = &k2;
    auto rejected = [&](const swcl_force_model_desc& b, swcl_status want, const char* needle) {
        EXPECT_EQ(swcl_swarm_force_set_model(swarm, &b), want) << needle;
        EXPECT_NE(std::string(swcl_last_error()).find(needle), std::string::npos) << swcl_last_error();
        EXPECT_GT(first_target_x(), 15.0f);
    };
    swcl_force_model_desc b = bad;
    b.mesh_obstacles = nullptr;
    rejected(b, SWCL_ERROR_INVALID_ARGUMENT, "mesh_obstacles is NULL");
    const float nan_tet[] = {0, 0, 0, 1, 0, 0, 0, std::nanf(""), 0, 0, 0, 1};
    swcl_obstacle ob = o[1];
    ob.vertices = nan_tet;
    b = bad;
    b.mesh_obstacles = &ob;
    b.mesh_obstacle_count = 1;
    rejected(b, SWCL_ERROR_INVALID_ARGUMENT, "mesh_obstacles[0]");
    const float flat[] = {0, 0, 0, 1, 0, 0, 2, 0, 0};
    const uint32_t flat_idx[] = {0, 1, 2};
    ob.vertices = flat;
    ob.vertex_count = 3;
    ob.indices = flat_idx;
    ob.triangle_count = 1;
    rejected(b, SWCL_ERROR_INVALID_ARGUMENT, "mesh_obstacles[0]");
    ob = o[0];
    const std::string missing = ::testing::TempDir() + "swarmcl_no_such_file.obj";
    ob.path = missing.c_str();
    rejected(b, SWCL_ERROR_IO, "mesh_obstacles[0]");
    const std::string broken = write_file("swarmcl_force_broken.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    ob.path = broken.c_str();
    rejected(b, SWCL_ERROR_PARSE, "mesh_obstacles[0]");
    b.mesh_obstacles = o;
    b.mesh_obstacle_count = 4;
    b.mesh_cell = 1e-3f;
    rejected(b, SWCL_ERROR_INVALID_ARGUMENT, "raise mesh_cell");
    // Random bytes as an OBJ file: an error, never a crash.
    std::mt19937 rng(17);
    for (int t = 0; t < 20; ++t) {
        std::string bytes(size_t(rng() % 400), '\0');
        for (char& ch : bytes) ch = char(rng() % 256);
        const std::string path = write_file("swarmcl_force_random.obj", bytes);
        ob.path = path.c_str();
        b = bad;
        b.mesh_obstacles = &ob;
        b.mesh_obstacle_count = 1;
        EXPECT_NE(swcl_swarm_force_set_model(swarm, &b), SWCL_OK);
        EXPECT_GT(first_target_x(), 15.0f);
    }

    // A descriptor of the previous version (ending at path_orient) has no
    // mesh obstacles, whatever lies beyond it.
    b = bad;
    b.struct_size = uint32_t(offsetof(swcl_force_model_desc, path_orient) + sizeof(b.path_orient));
    b.mesh_obstacles = nullptr;
    b.mesh_obstacle_count = 7;
    ASSERT_EQ(swcl_swarm_force_set_model(swarm, &b), SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_swarm_step(swarm, 1), SWCL_OK) << swcl_last_error();
    EXPECT_LT(first_target_x(), -15.0f);
    std::vector<float> p(3 * 100);  // waits for the steps before the context goes
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 100), SWCL_OK) << swcl_last_error();
}

// ---- scenario files --------------------------------------------------------------

TEST(ForceMeshScenario, MeshAndCylinderObstaclesAndRelativeObjPaths) {
    write_file("swarmcl_force_scn_box.obj", kBoxObj);
    const std::string text = R"({"agents": {"count": 20},
        "obstacles": [{"type": "sphere", "center": [0, 0, 2], "radius": 0.3},
                      {"type": "mesh", "file": "swarmcl_force_scn_box.obj", "offset": [1, 0, 0]},
                      {"type": "cylinder", "base": [0, 2, 0], "radius": 0.2, "height": 1}],
        "model": {"type": "force", "obstacle_range": 0.6, "mesh_cell": 0.1}})";
    std::string dir = ::testing::TempDir();
    if (!dir.empty() && dir.back() == '/') dir.pop_back();
    const Scenario s = parse_scenario(text, dir);
    ASSERT_TRUE(std::holds_alternative<ForceModelConfig>(s.model));
    const ForceModelConfig& c = std::get<ForceModelConfig>(s.model);
    EXPECT_EQ(c.obstacles.size(), 1u);  // the sphere stays analytic
    ASSERT_EQ(c.mesh_obstacles.size(), 2u);
    EXPECT_NEAR(bounds(c.mesh_obstacles[0]).min[0], 0.7f, 1e-6f);  // offset applied
    EXPECT_FLOAT_EQ(c.mesh_cell, 0.1f);
    // The scenario's swarm runs with them.
    auto swarm = make_swarm(20, 2);
    swarm->set_behavior(std::make_shared<ForceModel>(*swarm, c));
    swarm->step(3);
    // Wait for the steps (a kernel still compiling when the process exits
    // can crash PoCL's worker thread) and check they moved finite insects.
    std::vector<float> p(3 * 20);
    swarm->read(Attribute::Position, p.data(), 20);
    for (float v : p) EXPECT_TRUE(std::isfinite(v));
}

TEST(ForceMeshScenario, BadMeshObstaclesNameTheKey) {
    auto parse_error = [](const std::string& obstacles, const std::string& model_extra, const char* needle) {
        const std::string text = R"({"agents": {"count": 5}, "obstacles": [)" + obstacles +
                                 R"(], "model": {"type": "force")" + model_extra + "}}";
        try {
            parse_scenario(text, ::testing::TempDir());
            ADD_FAILURE() << "accepted " << obstacles;
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::Parse) << e.what();
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    parse_error(R"({"type": "mesh", "file": "swarmcl_force_none.obj"})", "", "obstacles[0]");
    parse_error(R"({"type": "cylinder", "base": [0, 0, 0], "radius": -1, "height": 1})", "", "obstacles[0]");
    parse_error(R"({"type": "sphere", "center": [0, 0, 0], "radius": 1}, {"type": "mesh"})", "", "obstacles[1]");
    write_file("swarmcl_force_scn_box2.obj", kBoxObj);
    parse_error(R"({"type": "mesh", "file": "swarmcl_force_scn_box2.obj"})", R"(, "mesh_cell": 0.0005)",
                "raise mesh_cell");
    parse_error(R"({"type": "plane", "normal": [0, 0, 1]})", "", "obstacles[0]");
}

// ---- OBJ files as keyframes (scenario files only; see docs/force-model.md) -----

TEST(ForceMeshScenario, ObjKeyframesAreReadRelativeToTheScenario) {
    write_file("swarmcl_force_kf_box.obj", kBoxObj);
    std::string dir = ::testing::TempDir();
    if (!dir.empty() && dir.back() == '/') dir.pop_back();
    const Scenario s = parse_scenario(R"({"agents": {"count": 30}, "model": {"type": "force", "min_spacing": 0,
        "keyframes": [{"frame": 0, "shape": "sphere"},
                      {"frame": 20, "obj": "swarmcl_force_kf_box.obj", "scale": 2, "offset": [1, 0, 0]}]}})",
                                      dir);
    ASSERT_TRUE(std::holds_alternative<ForceModelConfig>(s.model));
    const TriangleMesh& m = std::get<ForceModelConfig>(s.model).keyframes.at(1).mesh;
    EXPECT_EQ(m.triangle_count(), 12u);  // 6 quads, triangulated
    EXPECT_NEAR(bounds(m).min[0], 0.4f, 1e-6f);  // -0.3 * 2 + 1
    EXPECT_NEAR(bounds(m).max[2], 1.2f, 1e-6f);
    auto bad = [&](const std::string& keyframe, const char* needle) {
        try {
            parse_scenario(R"({"agents": {"count": 5}, "model": {"type": "force", "keyframes": [)" + keyframe + "]}}",
                           dir);
            ADD_FAILURE() << "accepted " << keyframe;
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::Parse) << e.what();
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    bad(R"({"frame": 0, "obj": "swarmcl_force_kf_none.obj"})", "keyframes[0].obj");
    bad(R"({"frame": 0, "obj": ""})", "keyframes[0].obj");
    bad(R"({"frame": 0, "obj": "swarmcl_force_kf_box.obj", "shape": "sphere"})", "keyframes[0]");
    write_file("swarmcl_force_kf_bad.obj", "v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n");
    bad(R"({"frame": 0, "obj": "swarmcl_force_kf_bad.obj"})", "keyframes[0].obj");
    // Random bytes: a parse error naming the key, never a crash.
    std::mt19937 rng(23);
    for (int t = 0; t < 20; ++t) {
        std::string bytes(size_t(rng() % 300), '\0');
        for (char& ch : bytes) ch = char(rng() % 256);
        write_file("swarmcl_force_kf_random.obj", bytes);
        bad(R"({"frame": 0, "obj": "swarmcl_force_kf_random.obj"})", "keyframes[0]");
    }
}
