// Minimum distance enforcement (kernels/min_distance.cl) on crowded swarms:
// one pass against a brute-force host reference, and the explicit-width
// kernel (CPU devices) against the one-agent-per-work-item kernel, bitwise,
// for cells of 2 d_min (the 2 x 2-row fast path), of d_min / 2 (wider boxes),
// of 2.5 d_min and of 6 d_min (the scalar kernel on every device), with
// agents outside the domain and on the same point.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "swarm/min_distance.hpp"
#include "test_support.hpp"

using namespace swarmcl;
using namespace swarmcl::test;

namespace {

struct Pass {
    std::vector<cl_float4> before, after;  // slot order (the grid's)
    std::vector<cl_uint> ids;
    cl_uint moved[2] = {0, 0};
    uint32_t width = 0;
    bool wide = false;  // the explicit-width kernel ran
};

// A crowded cube [-1, 1]^3 with 2% of the agents outside it and 1% on the
// same point as another agent.
std::vector<float> crowded_points(uint32_t n, uint32_t seed) {
    auto xyz = random_points(n, -1.0f, 1.0f, seed);
    for (uint32_t i = 0; i < n; i += 50) xyz[3 * i] = 1.3f + 0.01f * float(i % 7);
    for (uint32_t i = 7; i + 1 < n; i += 100)
        for (int a = 0; a < 3; ++a) xyz[3 * (i + 1) + a] = xyz[3 * i + a];
    return xyz;
}

// One MDE pass with the kernel `width` selects (1, 8 or 16; 0 keeps the
// library's own choice).
Pass run_pass(const std::vector<float>& xyz, float cell, float d_min, uint32_t width) {
    auto ctx = shared_context();
    const uint32_t n = uint32_t(xyz.size() / 3);
    Swarm swarm(ctx, cube_config(n, -1.0f, 1.0f, cell));
    swarm.write(Attribute::Position, xyz.data(), n);
    const auto make = [&] {
        if (width == 0) return MinDistance(*ctx, d_min, 99);
        test::ScopedKernelWidth w(width);
        return MinDistance(*ctx, d_min, 99);
    };
    MinDistance mde = make();
    DeviceBuffer<cl_uint> moved(*ctx, 2, "moved");
    moved.fill(*ctx, 0u, 2);
    swarm.ensure_grid();
    Pass p;
    p.width = mde.width();
    p.wide = mde.uses_wide_kernel(swarm.grid().geometry(), n, n);
    p.before.resize(n);
    p.after.resize(n);
    p.ids.resize(n);
    swarm.positions().download(*ctx, p.before.data(), n);
    swarm.ids().download(*ctx, p.ids.data(), n);
    mde.apply(swarm, moved);
    swarm.positions().download(*ctx, p.after.data(), n);  // still the slot order: no rebuild yet
    moved.download(*ctx, p.moved, 2);
    return p;
}

struct Case {
    float cell, d_min;
    bool wide;  // the explicit-width kernel runs above 4096 agents (cells of at most 8 d_min, min_distance.cpp)
};
const Case kCases[] = {{0.1f, 0.05f, true}, {0.05f, 0.1f, true}, {0.25f, 0.1f, true}, {0.6f, 0.1f, true},
                       {0.9f, 0.1f, false}};

}  // namespace

// Every agent moves by the sum, in slot order, of half the overlap along the
// pair direction over the agents closer than d_min (Jacobi: positions before
// the pass).  Pairs on the same point take a Philox direction; their agents
// are checked for the distance they end apart instead.
TEST(MinDistance, OnePassMatchesBruteForceReference) {
    const auto xyz = crowded_points(6000, 5);
    for (const auto& c : kCases) {
        SCOPED_TRACE("cell " + std::to_string(c.cell) + ", d_min " + std::to_string(c.d_min));
        const Pass p = run_pass(xyz, c.cell, c.d_min, 0);
        const uint32_t n = uint32_t(p.before.size());
        const float d2_min = c.d_min * c.d_min;
        uint32_t touched = 0, checked = 0;
        double err = 0;
        for (uint32_t i = 0; i < n; ++i) {
            const float* pi = p.before[i].s;
            float push[3] = {0, 0, 0};
            bool any = false, coincident = false;
            for (uint32_t j = 0; j < n; ++j) {
                if (j == i) continue;
                const float* pj = p.before[j].s;
                const float d2 = dist2(pi, pj);
                if (!(d2 < d2_min)) continue;
                any = true;
                if (d2 == 0.0f) {
                    coincident = true;
                    continue;
                }
                const float d = std::sqrt(d2), k = 0.5f * (c.d_min - d);
                for (int a = 0; a < 3; ++a) push[a] += k * ((pi[a] - pj[a]) / d);
            }
            touched += any ? 1u : 0u;
            if (coincident) continue;
            ++checked;
            for (int a = 0; a < 3; ++a)
                err = std::max(err, double(std::fabs(p.after[i].s[a] - (pi[a] + push[a]))));
        }
        EXPECT_GT(touched, n / 4) << "the case must crowd the swarm";
        EXPECT_GT(checked, n - n / 20);
        EXPECT_LT(err, 1e-6) << "max |device - reference| (m)";
        EXPECT_EQ(p.moved[0], touched);
        EXPECT_EQ(p.moved[1], touched);
    }
}

// The explicit-width kernel gives bitwise the results of the scalar kernel
// (the same candidates in the same order, the same arithmetic), tails and
// coincident agents included.
TEST(MinDistance, WideKernelEqualsScalarKernelBitwise) {
    for (uint32_t n : {6000u, 6007u, 5u}) {
        const auto xyz = crowded_points(n, 11 + n);
        for (const auto& c : kCases) {
            SCOPED_TRACE("n " + std::to_string(n) + ", cell " + std::to_string(c.cell));
            const Pass scalar = run_pass(xyz, c.cell, c.d_min, 1);
            ASSERT_EQ(scalar.width, 1u);
            for (uint32_t w : {8u, 16u}) {
                const Pass wide = run_pass(xyz, c.cell, c.d_min, w);
                ASSERT_EQ(wide.width, w);
                // Up to 4096 agents, cells of up to 20 d_min run it too.
                ASSERT_EQ(wide.wide, c.wide || n <= 4096u);
                ASSERT_EQ(std::memcmp(wide.before.data(), scalar.before.data(), n * sizeof(cl_float4)), 0);
                EXPECT_EQ(std::memcmp(wide.after.data(), scalar.after.data(), n * sizeof(cl_float4)), 0)
                    << "width " << w;
                EXPECT_EQ(wide.moved[0], scalar.moved[0]) << "width " << w;
            }
        }
    }
}

// The process-wide width override (what these tests use instead of
// $SWARMCL_NOISE_WIDTH) takes only the widths the kernels have.
// The explicit-width kernels' default on CPU devices: 8 lanes where the
// device prefers 8-float vectors (PoCL with AVX2), else 16; 1 on GPUs; a
// forced width wins.  The policy's MLP keeps 16 lanes on CPU devices.
TEST(MinDistance, DefaultWidthFollowsThePreferredFloatVectorWidth) {
    DeviceEntry d = test::shared_context()->device();
    if (kernel_width_forced()) GTEST_SKIP() << "$SWARMCL_NOISE_WIDTH forces the width in this run";
    d.cpu_profile = true;
    d.preferred_float_width = 8;
    EXPECT_EQ(preferred_noise_width(d), 8u);
    d.preferred_float_width = 16;
    EXPECT_EQ(preferred_noise_width(d), 16u);
    d.preferred_float_width = 4;  // no measurement there: the 16 of before
    EXPECT_EQ(preferred_noise_width(d), 16u);
    d.cpu_profile = false;
    d.preferred_float_width = 8;
    EXPECT_EQ(preferred_noise_width(d), 1u);
    {
        test::ScopedKernelWidth w(16);
        d.cpu_profile = true;
        EXPECT_TRUE(kernel_width_forced());
        EXPECT_EQ(preferred_noise_width(d), 16u);
    }
}

TEST(MinDistance, KernelWidthOverrideTakesOnlyKernelWidths) {
    EXPECT_THROW(set_kernel_width_override(4), Error);
    EXPECT_EQ(kernel_width_override(), 0u);
    {
        test::ScopedKernelWidth w(8);
        EXPECT_EQ(kernel_width_override(), 8u);
        EXPECT_EQ(preferred_noise_width(test::shared_context()->device()), 8u);
    }
    EXPECT_EQ(kernel_width_override(), 0u);
}
