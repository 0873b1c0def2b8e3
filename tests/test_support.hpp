// Shared test helpers: one context per test binary (kernels compile once),
// random points, and plain brute-force references.
#pragma once
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "device/context.hpp"
#include "fields/noise_field.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl::test {

// Contexts a test binary keeps for all its tests are released when the tests
// end (a GoogleTest environment's TearDown, before main returns), not by
// static destructors at exit: an OpenCL implementation may already be torn
// down by then (Oclgrind 21.10 aborts with "corrupted double-linked list",
// LLVM freeing a program in clReleaseProgram from an exit handler).
class KeptContexts : public ::testing::Environment {
public:
    static std::vector<std::shared_ptr<Context>*>& slots() {
        static std::vector<std::shared_ptr<Context>*> s;
        return s;
    }
    void TearDown() override {
        for (auto* slot : slots()) slot->reset();
    }
};
inline ::testing::Environment* const kept_contexts_environment =
    ::testing::AddGlobalTestEnvironment(new KeptContexts);

// A context made on first use and kept (in *slot) until the tests end.
inline std::shared_ptr<Context> kept_context(std::shared_ptr<Context>& slot) {
    if (!slot) {
        slot = std::make_shared<Context>("", "");
        auto& slots = KeptContexts::slots();
        if (std::find(slots.begin(), slots.end(), &slot) == slots.end()) slots.push_back(&slot);
    }
    return slot;
}

inline std::shared_ptr<Context> shared_context() {
    static std::shared_ptr<Context> ctx;
    return kept_context(ctx);
}

inline std::vector<float> random_points(size_t n, float lo, float hi, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(lo, hi);
    std::vector<float> xyz(3 * n);
    for (auto& v : xyz) v = u(rng);
    return xyz;
}

inline SwarmConfig cube_config(uint32_t capacity, float lo, float hi, float radius) {
    SwarmConfig c;
    c.capacity = capacity;
    c.domain_min = {lo, lo, lo};
    c.domain_max = {hi, hi, hi};
    c.interaction_radius = radius;
    return c;
}

// Squared distance in float, computed as the kernels do.
inline float dist2(const float* a, const float* b) {
    const float dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    return dx * dx + dy * dy + dz * dz;
}

// Selects the explicit-width kernels' width (1, 8, 16) for its lifetime
// without touching the environment (setenv races PoCL's threads' getenv).
class ScopedKernelWidth {
public:
    explicit ScopedKernelWidth(uint32_t width) : saved_(kernel_width_override()) { set_kernel_width_override(width); }
    ~ScopedKernelWidth() { set_kernel_width_override(saved_); }
    ScopedKernelWidth(const ScopedKernelWidth&) = delete;
    ScopedKernelWidth& operator=(const ScopedKernelWidth&) = delete;

private:
    uint32_t saved_;
};

}  // namespace swarmcl::test
