// The C API as a caller sees it: round trips, stepping, and misuse — NULL
// pointers, destroyed and foreign handles, NaN/Inf, counts above capacity,
// bad descriptors — each giving the right status and a message, and leaving
// the object usable.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "c_enum_callers.h"
#include "capi_fixture.hpp"
#include "swarmcl/swarmcl.h"
#include "test_support.hpp"

namespace {

class CApi : public swarmcl::test::CApiSwarmTest {
protected:
    void SetUp() override {
        ASSERT_NO_FATAL_FAILURE(create([](swcl_swarm_desc& s) {
            s.capacity = 100;
            s.agent_count = 10;
            s.seed = 7;
        }));
    }
    // The swarm still answers correctly: used after every refused call.
    void expect_usable(uint32_t expected_count) {
        uint32_t n = 0;
        ASSERT_EQ(swcl_swarm_agent_count(swarm, &n), SWCL_OK);
        ASSERT_EQ(n, expected_count);
        std::vector<float> p(3 * n);
        ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), n), SWCL_OK);
        for (float v : p) ASSERT_TRUE(std::isfinite(v));
    }
};

TEST(CApiBasics, VersionAndStatusStrings) {
    EXPECT_EQ(swcl_version(), uint32_t(SWCL_VERSION_NUMBER));
    EXPECT_STREQ(swcl_version_string(), "0.2.0");
    EXPECT_STREQ(swcl_status_string(SWCL_OK), "SWCL_OK");
    EXPECT_STREQ(swcl_status_string(SWCL_ERROR_INVALID_HANDLE), "SWCL_ERROR_INVALID_HANDLE");
    EXPECT_STREQ(swcl_status_string(swcl_status(12345)), "SWCL_UNKNOWN_STATUS");
    // Status values are part of the ABI.
    EXPECT_EQ(SWCL_ERROR_INVALID_ARGUMENT, -1);
    EXPECT_EQ(SWCL_ERROR_OPENCL, -8);
    EXPECT_EQ(SWCL_ERROR_INTERNAL, -99);
}

TEST(CApiBasics, DeviceListing) {
    uint32_t n = 0;
    ASSERT_EQ(swcl_device_count(&n), SWCL_OK);
    ASSERT_GE(n, 1u);
    swcl_device_info info;
    info.struct_size = sizeof(info);
    ASSERT_EQ(swcl_device_get_info(0, &info), SWCL_OK);
    EXPECT_GT(std::strlen(info.device_name), 0u);
    EXPECT_GE(info.compute_units, 1u);
    EXPECT_EQ(swcl_device_get_info(n, &info), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("out of range"), std::string::npos);
    EXPECT_EQ(swcl_device_count(nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    info.struct_size = 3;
    EXPECT_EQ(swcl_device_get_info(0, &info), SWCL_ERROR_INVALID_ARGUMENT);
}

TEST(CApiBasics, UnknownDeviceSelectorNamesTheDevices) {
    swcl_context_desc d = swcl_context_desc_default();
    d.device = "no-such-device-xyz";
    swcl_context c;
    EXPECT_EQ(swcl_context_create(&d, &c), SWCL_ERROR_NO_DEVICE);
    EXPECT_NE(std::string(swcl_last_error()).find("matches no device"), std::string::npos);
    d.device = "999";
    EXPECT_EQ(swcl_context_create(&d, &c), SWCL_ERROR_NO_DEVICE);
}

TEST(CApiBasics, BadDescriptors) {
    swcl_context c;
    EXPECT_EQ(swcl_context_create(nullptr, &c), SWCL_ERROR_INVALID_ARGUMENT);
    swcl_context_desc d = swcl_context_desc_default();
    EXPECT_EQ(swcl_context_create(&d, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    d.struct_size = 0;
    EXPECT_EQ(swcl_context_create(&d, &c), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("struct_size"), std::string::npos);
}

TEST_F(CApi, WriteReadRoundTripInAgentIdOrder) {
    std::vector<float> p(30), v(30), back(30);
    for (int i = 0; i < 30; ++i) {
        p[i] = 0.01f * float(i * 7 % 30) - 0.15f;
        v[i] = 0.1f * float(i);
    }
    ASSERT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 10), SWCL_OK);
    ASSERT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_VELOCITY, v.data(), 10), SWCL_OK);
    // A query reorders the device state by cell; reads stay in id order.
    std::vector<float> d(10);
    ASSERT_EQ(swcl_swarm_nearest_neighbor(swarm, d.data(), nullptr, 10), SWCL_OK);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, back.data(), 10), SWCL_OK);
    EXPECT_EQ(back, p);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_VELOCITY, back.data(), 10), SWCL_OK);
    EXPECT_EQ(back, v);
}

TEST_F(CApi, StepMovesBallisticallyAndCounts) {
    std::vector<float> p(30, 0.0f), v(30, 0.0f), out(30);
    for (int i = 0; i < 10; ++i) v[3 * i] = 1.0f;
    ASSERT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 10), SWCL_OK);
    ASSERT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_VELOCITY, v.data(), 10), SWCL_OK);
    ASSERT_EQ(swcl_swarm_step(swarm, 6), SWCL_OK);
    uint64_t steps = 0;
    ASSERT_EQ(swcl_swarm_step_count(swarm, &steps), SWCL_OK);
    EXPECT_EQ(steps, 6u);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, out.data(), 10), SWCL_OK);
    for (int i = 0; i < 10; ++i) EXPECT_NEAR(out[3 * i], 6.0f / 60.0f, 1e-6f);
}

TEST_F(CApi, InitialPlacementIsSeededAndInsideTheDomain) {
    std::vector<float> a(30), b(30);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, a.data(), 10), SWCL_OK);
    for (float x : a) {
        EXPECT_GE(x, -1.0f);
        EXPECT_LT(x, 1.0f);
    }
    swcl_swarm_desc s = swcl_swarm_desc_default();
    s.capacity = 10;
    s.agent_count = 10;
    s.seed = 7;
    swcl_swarm other;
    ASSERT_EQ(swcl_swarm_create(ctx, &s, &other), SWCL_OK);
    ASSERT_EQ(swcl_swarm_read(other, SWCL_ATTRIBUTE_POSITION, b.data(), 10), SWCL_OK);
    EXPECT_EQ(a, b);
    swcl_swarm_destroy(other);
}

TEST_F(CApi, GrowingAndShrinkingTheAgentCountKeepsVelocities) {
    std::vector<float> v(30), p(60, 0.5f), out(60);
    for (int i = 0; i < 30; ++i) v[i] = float(i);
    ASSERT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_VELOCITY, v.data(), 10), SWCL_OK);
    ASSERT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 20), SWCL_OK);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_VELOCITY, out.data(), 20), SWCL_OK);
    for (int i = 0; i < 30; ++i) EXPECT_EQ(out[i], v[i]);
    for (int i = 30; i < 60; ++i) EXPECT_EQ(out[i], 0.0f);
    ASSERT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 4), SWCL_OK);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_VELOCITY, out.data(), 4), SWCL_OK);
    for (int i = 0; i < 12; ++i) EXPECT_EQ(out[i], v[i]);
}

TEST_F(CApi, NanAndInfAreRefusedAndNothingChanges) {
    std::vector<float> before(30), p(30, 0.1f), after(30);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, before.data(), 10), SWCL_OK);
    p[13] = std::nanf("");
    EXPECT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("agent 4"), std::string::npos) << swcl_last_error();
    p[13] = INFINITY;
    EXPECT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_VELOCITY, p.data(), 10), SWCL_ERROR_INVALID_ARGUMENT);
    // A refused grow must not change the count either.
    std::vector<float> big(60, 0.0f);
    big[59] = -INFINITY;
    EXPECT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_POSITION, big.data(), 20), SWCL_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, after.data(), 10), SWCL_OK);
    EXPECT_EQ(before, after);
    expect_usable(10);
}

TEST_F(CApi, CountsAboveCapacityOrMismatchedAreRefused) {
    std::vector<float> p(3 * 101, 0.0f);
    EXPECT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 101), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("capacity"), std::string::npos);
    EXPECT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_VELOCITY, p.data(), 11), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, p.data(), 9), SWCL_ERROR_INVALID_ARGUMENT);
    std::vector<uint32_t> c(11);
    EXPECT_EQ(swcl_swarm_neighbor_count(swarm, 0.1f, c.data(), 11), SWCL_ERROR_INVALID_ARGUMENT);
    expect_usable(10);
}

TEST_F(CApi, NullPointersAndBadValues) {
    std::vector<float> p(30, 0.0f);
    std::vector<uint32_t> c(10), ids(10);
    EXPECT_EQ(swcl_swarm_write(swarm, SWCL_ATTRIBUTE_POSITION, nullptr, 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, nullptr, 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_write(swarm, swcl_attribute(42), p.data(), 10), SWCL_ERROR_INVALID_ARGUMENT);
    // Values only a C caller can pass (outside the enumerators' range in C++).
    EXPECT_EQ(c_swarm_read_attribute(swarm, -1, p.data(), 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("unknown attribute 4294967295"), std::string::npos);
    EXPECT_EQ(c_swarm_read_attribute(swarm, INT32_MIN, p.data(), 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_agent_count(swarm, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_neighbor_count(swarm, 0.0f, c.data(), 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_neighbor_count(swarm, -1.0f, c.data(), 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_neighbor_count(swarm, NAN, c.data(), 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("radius"), std::string::npos);
    EXPECT_EQ(swcl_swarm_neighbor_count(swarm, 0.1f, nullptr, 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_nearest_neighbor(swarm, nullptr, nullptr, 10), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_neighbor_lists(swarm, 0.1f, 0, ids.data(), c.data(), 10, nullptr),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_swarm_neighbor_lists(swarm, 0.1f, 1, nullptr, c.data(), 10, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    expect_usable(10);
}

// Enum fields of descriptors as only a C caller can fill them (-1,
// INT32_MIN): each refused naming the field and the value, as the scenario
// and the swarm are left as they were.
TEST_F(CApi, OutOfRangeEnumFieldsFromCAreRefusedNamingTheValue) {
    const auto refused = [&](swcl_status st, const std::string& says) {
        EXPECT_EQ(st, SWCL_ERROR_INVALID_ARGUMENT) << says;
        EXPECT_NE(std::string(swcl_last_error()).find(says), std::string::npos) << swcl_last_error();
    };
    for (const int bad : {-1, INT32_MIN}) {
        SCOPED_TRACE(bad);
        const std::string value = std::to_string(bad);
        swcl_field_model_desc field = swcl_field_model_desc_default();
        c_noise_desc_type(&field.noise, bad);
        refused(swcl_swarm_field_set_model(swarm, &field), "noise type " + value + " is not one of");
        field = swcl_field_model_desc_default();
        swcl_obstacle wall{};
        c_obstacle_type(&wall, bad);
        field.noise.boundaries = &wall;
        field.noise.boundary_count = 1;
        refused(swcl_swarm_field_set_model(swarm, &field), "noise boundaries[0]: type " + value);

        swcl_force_model_desc force = swcl_force_model_desc_default();
        c_force_assignment(&force, bad);
        refused(swcl_swarm_force_set_model(swarm, &force), "force model assignment (" + value + ")");
        force = swcl_force_model_desc_default();
        force.obstacles = &wall;
        force.obstacle_count = 1;
        refused(swcl_swarm_force_set_model(swarm, &force), "force model obstacles[0]: type " + value);
        force = swcl_force_model_desc_default();
        force.mesh_obstacles = &wall;
        force.mesh_obstacle_count = 1;
        refused(swcl_swarm_force_set_model(swarm, &force), "unknown obstacle type " + value);

        swcl_path_model_desc path = swcl_path_model_desc_default();
        path.obstacles = &wall;
        path.obstacle_count = 1;
        refused(swcl_swarm_path_set_model(swarm, &path), "obstacles[0]: unknown obstacle type " + value);
        path = swcl_path_model_desc_default();
        swcl_goal goal{};
        c_goal_type(&goal, bad);
        path.goals = &goal;
        path.goal_count = 1;
        refused(swcl_swarm_path_set_model(swarm, &path), "desc->goals[0]: unknown goal type " + value);

        swcl_policy_model_desc policy = swcl_policy_model_desc_default();
        c_policy_leader_mode(&policy, bad);
        refused(swcl_swarm_policy_set_model(swarm, &policy), "desc->leader_mode: unknown mode " + value);
    }
    expect_usable(10);
}

TEST_F(CApi, BadSwarmDescriptorsNameTheField) {
    struct Case { void (*edit)(swcl_swarm_desc&); const char* word; };
    const Case cases[] = {
        {[](swcl_swarm_desc& d) { d.capacity = 0; }, "capacity"},
        {[](swcl_swarm_desc& d) { d.agent_count = d.capacity + 1; }, "agent_count"},
        {[](swcl_swarm_desc& d) { d.domain_min[1] = 2.0f; }, "domain_min[1]"},
        {[](swcl_swarm_desc& d) { d.domain_max[0] = NAN; }, "finite"},
        {[](swcl_swarm_desc& d) { d.interaction_radius = -1.0f; }, "interaction_radius"},
        {[](swcl_swarm_desc& d) { d.dt = 0.0f; }, "dt"},
    };
    for (const auto& c : cases) {
        swcl_swarm_desc d = swcl_swarm_desc_default();
        c.edit(d);
        swcl_swarm s{12345};
        EXPECT_EQ(swcl_swarm_create(ctx, &d, &s), SWCL_ERROR_INVALID_ARGUMENT) << c.word;
        EXPECT_NE(std::string(swcl_last_error()).find(c.word), std::string::npos) << swcl_last_error();
        EXPECT_EQ(s.id, 12345u) << "out must be untouched on failure";
    }
}

TEST_F(CApi, HugeCapacityIsOutOfMemoryNotACrash) {
    swcl_swarm_desc d = swcl_swarm_desc_default();
    d.capacity = 0xFFFFFFFFu;
    swcl_swarm s;
    EXPECT_EQ(swcl_swarm_create(ctx, &d, &s), SWCL_ERROR_OUT_OF_MEMORY);
    EXPECT_GT(std::strlen(swcl_last_error()), 0u);
    std::vector<uint32_t> ids(1), c(10);
    EXPECT_EQ(swcl_swarm_neighbor_lists(swarm, 0.1f, 0xFFFFFFFFu, ids.data(), c.data(), 10, nullptr),
              SWCL_ERROR_OUT_OF_MEMORY);
    expect_usable(10);
}

TEST_F(CApi, DestroyedForeignAndNullHandles) {
    uint32_t n;
    swcl_swarm null_swarm{0};
    EXPECT_EQ(swcl_swarm_agent_count(null_swarm, &n), SWCL_ERROR_INVALID_HANDLE);
    // A context handle is not a swarm handle, and random bits are nothing.
    EXPECT_EQ(swcl_swarm_agent_count(swcl_swarm{ctx.id}, &n), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_swarm_step(swcl_swarm{0xDEADBEEFCAFEull}, 1), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_context_destroy(swcl_context{swarm.id}), SWCL_ERROR_INVALID_HANDLE);

    swcl_swarm_desc d = swcl_swarm_desc_default();
    swcl_swarm s;
    ASSERT_EQ(swcl_swarm_create(ctx, &d, &s), SWCL_OK);
    ASSERT_EQ(swcl_swarm_destroy(s), SWCL_OK);
    EXPECT_EQ(swcl_swarm_destroy(s), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_swarm_step(s, 1), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_NE(std::string(swcl_last_error()).find("not a live swarm"), std::string::npos);
    // A new swarm never reuses the destroyed id.
    swcl_swarm again;
    ASSERT_EQ(swcl_swarm_create(ctx, &d, &again), SWCL_OK);
    EXPECT_NE(again.id, s.id);
    swcl_swarm_destroy(again);
    expect_usable(10);
}

TEST_F(CApi, SwarmOutlivesItsContextHandle) {
    swcl_context_desc cd = swcl_context_desc_default();
    swcl_context c2;
    ASSERT_EQ(swcl_context_create(&cd, &c2), SWCL_OK);
    swcl_swarm_desc d = swcl_swarm_desc_default();
    d.agent_count = 5;
    swcl_swarm s;
    ASSERT_EQ(swcl_swarm_create(c2, &d, &s), SWCL_OK);
    ASSERT_EQ(swcl_context_destroy(c2), SWCL_OK);
    EXPECT_EQ(swcl_swarm_create(c2, &d, &s), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(swcl_swarm_step(s, 2), SWCL_OK);
    std::vector<float> dist(5);
    EXPECT_EQ(swcl_swarm_nearest_neighbor(s, dist.data(), nullptr, 5), SWCL_OK);
    EXPECT_EQ(swcl_swarm_destroy(s), SWCL_OK);
}

TEST_F(CApi, LastErrorIsPerThreadAndClearedBySuccess) {
    uint32_t n;
    EXPECT_EQ(swcl_swarm_agent_count(swcl_swarm{0}, &n), SWCL_ERROR_INVALID_HANDLE);
    std::string other;
    std::thread t([&] { other = swcl_last_error(); });
    t.join();
    EXPECT_EQ(other, "");
    EXPECT_NE(std::string(swcl_last_error()), "");
    EXPECT_EQ(swcl_swarm_agent_count(swarm, &n), SWCL_OK);
    EXPECT_STREQ(swcl_last_error(), "");
}

TEST_F(CApi, ConcurrentCallsOnOneSwarmAreSafe) {
    std::vector<std::thread> threads;
    std::atomic<int> failures{0};
    for (int t = 0; t < 4; ++t)
        threads.emplace_back([&] {
            std::vector<float> d(10);
            for (int i = 0; i < 20; ++i) {
                if (swcl_swarm_step(swarm, 1) != SWCL_OK) failures++;
                if (swcl_swarm_nearest_neighbor(swarm, d.data(), nullptr, 10) != SWCL_OK) failures++;
            }
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(failures.load(), 0);
    uint64_t steps;
    ASSERT_EQ(swcl_swarm_step_count(swarm, &steps), SWCL_OK);
    EXPECT_EQ(steps, 80u);
}

}  // namespace
