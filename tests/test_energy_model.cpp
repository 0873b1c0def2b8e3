// The FASTSWARM energy model (kernels/energy_model.cl): every term of every
// candidate against the double-precision host reference (tests/
// energy_reference.hpp), the argmin against a brute-force host search, the
// position update, the deterministic swarm centre, bitwise determinism, and
// bad configurations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <cstring>
#include <random>

#include "core/error.hpp"
#include "device/kernel_sources.hpp"
#include "energy_reference.hpp"
#include "fields/noise_field.hpp"
#include "models/energy_model.hpp"
#include "test_support.hpp"

using namespace swarmcl;
using namespace swarmcl::test;

namespace {

std::shared_ptr<const Dataset> test_dataset(uint32_t k = 300, uint32_t groups = 10) {
    DatasetOptions o;
    o.k = k;
    o.groups = groups;
    return std::make_shared<const Dataset>(synthetic_dataset(o));
}

SwarmConfig small_config(uint32_t n, uint64_t seed) {
    SwarmConfig c = cube_config(1024, -0.4f, 0.4f, 0.1f);
    c.agent_count = n;
    c.seed = seed;
    c.dt = 0.01f;
    return c;
}

// Random positions in a small cube and velocities near dataset samples.
void random_state(Swarm& s, const Dataset& d, uint32_t n, uint32_t seed, float half = 0.25f) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-half, half), jitter(-0.05f, 0.05f);
    std::vector<float> p(3 * n), v(3 * n);
    for (uint32_t i = 0; i < n; ++i) {
        const auto& dv = d.v[rng() % d.size()];
        for (int a = 0; a < 3; ++a) {
            p[3 * i + a] = u(rng);
            v[3 * i + a] = dv[a] + jitter(rng);
        }
    }
    s.write(Attribute::Position, p.data(), n);
    s.write(Attribute::Velocity, v.data(), n);
}

// A configuration where every term is active.
EnergyModelConfig all_terms_config() {
    EnergyModelConfig c;
    c.weights = {1.0f, 1.0f, 0.5f, 1.0f, 1.0f, 1.0f, 0.7f, 0.8f};
    c.danger_weights = {1.0f, 0.0f, 0.0f, 1.0f, 1.0f, 2.0f, 0.3f, 0.4f};
    c.d_rep = 0.05f;
    c.d_att1 = 0.08f;
    c.d_att2 = 0.2f;
    c.exact_attraction = true;  // Eq. 6 as written (the expansion: AttractionExpansion)
    c.stimuli.push_back({Stimulus::Kind::Attract, {0.3f, 0.0f, 0.1f}, {0.0f, 0.1f, 0.0f}, 0.0f});
    c.stimuli.push_back({Stimulus::Kind::Startle, {-0.1f, 0.05f, 0.0f}, {0.5f, 0.0f, 0.0f}, 0.15f});
    c.keypoints = {{0.2f, 0.0f, 0.0f}, {0.0f, 0.2f, 0.0f}, {-0.2f, 0.0f, 0.0f}, {0.0f, -0.2f, 0.1f}};
    return c;
}

ReferenceState reference_state(Swarm& s, EnergyModel& m, uint64_t step) {
    const uint32_t n = s.agent_count();
    ReferenceState r;
    r.pos.resize(3 * n);
    r.vel.resize(3 * n);
    s.read(Attribute::Position, r.pos.data(), n);
    s.read(Attribute::Velocity, r.vel.data(), n);
    r.dt = s.config().dt;
    const float time = float(double(step) * r.dt);
    for (uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) r.centre[a] += r.pos[3 * i + a] / double(n);
    NoiseField noise(s.context(), m.config().noise, &s.config().domain_min, &s.config().domain_max);
    r.noise.resize(3 * n);
    noise.sample(r.pos.data(), n, time, uint32_t(step), r.noise.data());
    for (const auto& st : m.config().stimuli)
        r.stimuli_pos.push_back({st.position[0] + st.velocity[0] * time, st.position[1] + st.velocity[1] * time,
                                 st.position[2] + st.velocity[2] * time});
    r.accel_time = m.dataset().frame_time > 0 ? float(m.dataset().frame_time) : 0.01f;
    std::vector<int32_t> goal;
    std::vector<uint8_t> back;
    m.goals(s, goal, back);
    r.goal.assign(n, -1);
    // Before the first step the goal is the nearest keypoint.
    for (uint32_t i = 0; i < n; ++i) {
        if (m.config().keypoints.empty()) continue;
        if (goal[i] >= 0) {
            r.goal[i] = goal[i];
            continue;
        }
        float best = INFINITY;
        for (size_t k = 0; k < m.config().keypoints.size(); ++k) {
            const float d = dist2(&r.pos[3 * i], m.config().keypoints[k].data());
            if (d < best) best = d, r.goal[i] = int(k);
        }
    }
    return r;
}

// Term k of agent a's candidate c (a dataset index in [first[a], last[a])).
float term_of(const EnergyTerms& t, const EnergyModel& m, uint32_t a, uint32_t c, int k) {
    return t.terms[(size_t(a) * m.max_candidates() + (c - t.first[a])) * 8 + k];
}

double total(const std::array<double, 8>& e) {
    double t = 0;
    for (double x : e) t += x;
    return t;
}

}  // namespace

TEST(EnergyModel, EveryTermMatchesTheHostReference) {
    auto ctx = shared_context();
    auto data = test_dataset();
    const uint32_t n = 150;
    Swarm s(ctx, small_config(n, 3));
    random_state(s, *data, n, 5, 0.2f);
    EnergyModel m(s, all_terms_config(), data);
    for (uint64_t step : {0ull, 7ull}) {
        const EnergyTerms t = m.evaluate(s, step);
        const ReferenceState r = reference_state(s, m, step);
        uint32_t in_danger = 0, with_rep = 0;
        for (uint32_t a = 0; a < n; ++a) {
            const auto range = reference_candidates(*data, m.config().span, &r.vel[3 * a]);
            ASSERT_EQ(t.first[a], range[0]) << a;
            ASSERT_EQ(t.last[a], range[1]) << a;
            for (uint32_t c = range[0]; c < range[1]; ++c) {
                const auto e = reference_terms(m.config(), *data, r, a, c);
                for (int k = 0; k < 8; ++k) {
                    const float got = term_of(t, m, a, c, k);
                    ASSERT_NEAR(got, e[k], 1e-4 + 2e-4 * std::fabs(e[k]))
                        << "agent " << a << " candidate " << c << " term " << k << " step " << step;
                }
                if (c == range[0]) with_rep += e[0] > 0;
            }
            in_danger += reference_in_danger(m.config(), r, a);
        }
        // The random state exercises the neighbour terms and both weight
        // sets (49-54 of the 150 agents in danger).
        EXPECT_GT(with_rep, 5u);
        EXPECT_GT(in_danger, 5u);
        EXPECT_LT(in_danger, n - 5u);
    }
}

namespace {

// The expanded Eq. 6 (kernels/energy_model.cl) against the exact host sum:
// E_oa within 1.6%, every other term as exact as the reference test's;
// returns the terms.  The largest relative error of E_oa in *worst.
EnergyTerms expect_expansion_within_bound(Swarm& s, EnergyModel& m, const Dataset& data, double* worst) {
    const uint32_t n = s.agent_count();
    const EnergyTerms t = m.evaluate(s, 2);
    const ReferenceState r = reference_state(s, m, 2);
    *worst = 0;
    uint32_t with_oa = 0;
    for (uint32_t a = 0; a < n; ++a)
        for (uint32_t cand = t.first[a]; cand < t.last[a]; ++cand) {
            const auto e = reference_terms(m.config(), data, r, a, cand);
            for (int k = 0; k < 8; ++k) {
                const float got = term_of(t, m, a, cand, k);
                const double tol = k == 1 ? 0.016 * e[k] + 1e-4 : 1e-4 + 2e-4 * std::fabs(e[k]);
                EXPECT_NEAR(got, e[k], tol) << "agent " << a << " candidate " << cand << " term " << k;
                if (k == 1 && e[k] > 0) *worst = std::max(*worst, std::fabs(got - e[k]) / e[k]);
            }
            with_oa += e[1] > 0;
        }
    EXPECT_GT(with_oa, 100u);
    return t;
}

EnergyModelConfig expansion_config() {
    EnergyModelConfig c = all_terms_config();
    c.exact_attraction = false;
    c.d_att1 = 0.1f;
    return c;
}

}  // namespace

TEST(EnergyModel, AttractionExpansionIsWithinItsBound) {
    // The default second-order expansion of Eq. 6 (kernels/energy_model.cl):
    // E_oa within 1.6% of the exact sum, every other term as exact as before.
    auto ctx = shared_context();
    auto data = test_dataset();
    const uint32_t n = 150;
    Swarm s(ctx, small_config(n, 31));
    random_state(s, *data, n, 32, 0.2f);
    EnergyModelConfig c = expansion_config();
    EnergyModel m(s, c, data);
    ASSERT_TRUE(m.taylor_attraction());
    double worst = 0;
    expect_expansion_within_bound(s, m, *data, &worst);
    std::printf("largest relative error of the expanded E_oa: %.2e\n", worst);
    // Too coarse a step for the expansion: the exact sum is used.
    c.d_att1 = 0.02f;
    c.d_rep = 0.01f;
    EXPECT_FALSE(EnergyModel(s, c, data).taylor_attraction());
}

TEST(EnergyModel, EveryWindowWidthKeepsTheExpansionWithinItsBound) {
    // The neighbour windows are 8 lanes where the device's kernels are 8
    // wide (AVX2), else 16 (kernels/energy_model.cl, EM_NW): the expansion's
    // sums are added in another order, so the terms may differ in their last
    // bits, never by more than rounding.
    auto ctx = shared_context();
    auto data = test_dataset();
    const uint32_t n = 150;
    Swarm s(ctx, small_config(n, 31));
    random_state(s, *data, n, 32, 0.2f);
    struct Restore {
        ~Restore() { set_kernel_width_override(0); }
    } restore;
    std::vector<EnergyTerms> terms;
    for (uint32_t w : {1u, 8u, 16u}) {
        SCOPED_TRACE("width " + std::to_string(w));
        set_kernel_width_override(w);
        EnergyModel m(s, expansion_config(), data);
        ASSERT_TRUE(m.taylor_attraction());
        double worst = 0;
        terms.push_back(expect_expansion_within_bound(s, m, *data, &worst));
    }
    for (size_t k = 1; k < terms.size(); ++k) {
        ASSERT_EQ(terms[k].terms.size(), terms[0].terms.size());
        for (size_t q = 0; q < terms[0].terms.size(); ++q)
            ASSERT_NEAR(terms[k].terms[q], terms[0].terms[q], 1e-5 * std::fabs(terms[0].terms[q]) + 1e-6)
                << "term " << q << " width " << (k == 1 ? 8 : 16);
    }
}

TEST(EnergyModel, Exp2LanesAreWithinTwoRoundingsOfTheHost) {
    // kernels/lib/exp2.cl, the energy kernel's 2^x (8 and 16 lanes): within
    // 3e-7 relative of the host's where 2^x is a normal float, clamped to
    // 2^127 above and 2^-126 below, the two widths the same bits.
    auto ctx = shared_context();
    const std::string src = load_kernel_source("lib/exp2.cl") + R"CL(
        __kernel void t_exp2(__global const float* x, __global float* y8, __global float* y16) {
            const size_t i = get_global_id(0);
            vstore8(swcl_exp2_f8(vload8(2 * i, x)), 2 * i, y8);
            vstore8(swcl_exp2_f8(vload8(2 * i + 1, x)), 2 * i + 1, y8);
            vstore16(swcl_exp2_f16(vload16(i, x)), i, y16);
        })CL";
    cl::Program prog(ctx->cl_context(), src);
    try {
        prog.build({ctx->device().device}, "-cl-std=CL1.2 -w");
    } catch (const cl::Error&) {
        FAIL() << prog.getBuildInfo<CL_PROGRAM_BUILD_LOG>(ctx->device().device);
    }
    std::vector<float> x;
    for (int k = 0; k <= 200000; ++k) x.push_back(-125.0f + 252.0f * float(k) / 200000.0f);  // 2^x normal
    for (float v : {-126.0f, 127.0f, 127.5f, 128.0f, 1e6f, -126.5f, -200.0f, -1e6f, 0.0f, -0.0f, 0.5f, -0.5f})
        x.push_back(v);
    while (x.size() % 16) x.push_back(1.0f);
    const size_t n = x.size();
    cl::Buffer bx(ctx->cl_context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, n * sizeof(float), x.data());
    cl::Buffer b8(ctx->cl_context(), CL_MEM_WRITE_ONLY, n * sizeof(float));
    cl::Buffer b16(ctx->cl_context(), CL_MEM_WRITE_ONLY, n * sizeof(float));
    cl::Kernel k(prog, "t_exp2");
    k.setArg(0, bx);
    k.setArg(1, b8);
    k.setArg(2, b16);
    ctx->queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n / 16));
    std::vector<float> y8(n), y16(n);
    ctx->queue().enqueueReadBuffer(b8, CL_TRUE, 0, n * sizeof(float), y8.data());
    ctx->queue().enqueueReadBuffer(b16, CL_TRUE, 0, n * sizeof(float), y16.data());
    double worst = 0;
    for (size_t i = 0; i < n; ++i) {
        ASSERT_EQ(std::memcmp(&y8[i], &y16[i], sizeof(float)), 0) << "x = " << x[i];
        const double v = x[i];
        if (v >= 127.0) {
            EXPECT_EQ(y8[i], std::ldexp(1.0f, 127)) << "x = " << v;
        } else if (v <= -126.0) {
            EXPECT_EQ(y8[i], std::ldexp(1.0f, -126)) << "x = " << v;
        } else {
            const double rel = std::fabs(double(y8[i]) / std::exp2(v) - 1.0);
            worst = std::max(worst, rel);
            EXPECT_LE(rel, 3e-7) << "x = " << v;
        }
    }
    std::printf("largest relative error of swcl_exp2: %.2e\n", worst);
}

TEST(EnergyModel, ArgminMatchesBruteForceHostSearch) {
    auto ctx = shared_context();
    for (uint32_t groups : {10u, 1u}) {  // 1 group: the whole dataset is searched
        auto data = test_dataset(300, groups);
        const uint32_t n = 120;
        Swarm s(ctx, small_config(n, 11 + groups));
        random_state(s, *data, n, 17 + groups);
        EnergyModel m(s, all_terms_config(), data);
        const EnergyTerms t = m.evaluate(s, 3);
        const ReferenceState r = reference_state(s, m, 3);
        uint32_t exact = 0, kept_out = 0, compared = 0;
        for (uint32_t a = 0; a < n; ++a) {
            const auto range = reference_candidates(*data, m.config().span, &r.vel[3 * a]);
            // Keep-out first: only the candidates entering d_danger least compete.
            double least_viol = INFINITY;
            for (uint32_t c = range[0]; c < range[1]; ++c)
                least_viol = std::min(least_viol, reference_violation(m.config(), *data, r, a, c));
            double best = INFINITY, second = INFINITY;
            uint32_t best_c = 0;
            for (uint32_t c = range[0]; c < range[1]; ++c) {
                if (reference_violation(m.config(), *data, r, a, c) > least_viol + 1e-5) continue;
                const double e = total(reference_terms(m.config(), *data, r, a, c));
                if (e < best) {
                    second = best;
                    best = e;
                    best_c = c;
                } else if (e < second) {
                    second = e;
                }
            }
            ASSERT_GE(t.chosen[a], range[0]);
            ASSERT_LT(t.chosen[a], range[1]);
            EXPECT_LE(reference_violation(m.config(), *data, r, a, t.chosen[a]), least_viol + 1e-5) << a;
            if (least_viol > 0) continue;  // every candidate enters: the least entering one, checked above
            for (uint32_t c = range[0]; c < range[1]; ++c)
                if (reference_violation(m.config(), *data, r, a, c) > 0) {
                    ++kept_out;  // some candidates are ruled out
                    break;
                }
            ++compared;
            const double chosen = total(reference_terms(m.config(), *data, r, a, t.chosen[a]));
            // float vs double: the kernel's pick is the minimum up to rounding,
            // and exactly the host's pick wherever the two best are apart.
            EXPECT_LE(chosen, best + 1e-4 * std::fabs(best) + 1e-5) << a;
            if (second - best > 1e-3 * std::fabs(best)) {
                EXPECT_EQ(t.chosen[a], best_c) << a;
                ++exact;
            }
        }
        EXPECT_GT(compared, n * 3 / 4);
        EXPECT_GT(exact, compared * 9 / 10);
        EXPECT_GT(kept_out, 5u) << "the startling stimulus rules out some candidates";
    }
}

TEST(EnergyModel, StepMovesWithTheChosenVelocity) {
    auto ctx = shared_context();
    auto data = test_dataset();
    const uint32_t n = 100;
    Swarm s(ctx, small_config(n, 21));
    random_state(s, *data, n, 23);
    auto m = std::make_shared<EnergyModel>(s, all_terms_config(), data);
    s.set_behavior(m);
    const EnergyTerms t = m->evaluate(s, 0);
    std::vector<float> p0(3 * n), p1(3 * n), v1(3 * n);
    s.read(Attribute::Position, p0.data(), n);
    s.step(1);
    s.read(Attribute::Position, p1.data(), n);
    s.read(Attribute::Velocity, v1.data(), n);
    for (uint32_t a = 0; a < n; ++a)
        for (int k = 0; k < 3; ++k) {
            ASSERT_EQ(v1[3 * a + k], data->v[t.chosen[a]][k]) << a;
            ASSERT_EQ(p1[3 * a + k], p0[3 * a + k] + v1[3 * a + k] * 0.01f) << a;
        }
    // The centre the step used is the mean position.
    const auto c = m->centre(s);
    for (int k = 0; k < 3; ++k) {
        double mean = 0;
        for (uint32_t a = 0; a < n; ++a) mean += p0[3 * a + k] / n;
        EXPECT_NEAR(c[k], mean, 1e-5);
    }
    EXPECT_EQ(c[3], float(n));
}

TEST(EnergyModel, SameSeedSameRunBitwise) {
    auto ctx = shared_context();
    auto data = test_dataset();
    auto run = [&](uint32_t n) {
        Swarm s(ctx, small_config(n, 77));
        random_state(s, *data, n, 78);
        s.set_behavior(std::make_shared<EnergyModel>(s, all_terms_config(), data));
        s.step(40);
        std::vector<float> p(3 * n);
        s.read(Attribute::Position, p.data(), n);
        return p;
    };
    const auto a = run(300), b = run(300);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(0, std::memcmp(a.data(), b.data(), a.size() * sizeof(float)));
}

TEST(EnergyModel, KeypointGoalsAdvanceInOrder) {
    auto ctx = shared_context();
    auto data = test_dataset();
    const uint32_t n = 20;
    Swarm s(ctx, small_config(n, 5));
    EnergyModelConfig c;
    c.weights = {1, 0.5f, 0, 1, 1, 0, 1, 1};  // Table 1, shape constraint
    c.keypoints = {{0.2f, 0, 0}, {0, 0.2f, 0}, {-0.2f, 0, 0}, {0, -0.2f, 0}};
    c.keypoint_reach = 0.06f;
    auto m = std::make_shared<EnergyModel>(s, c, data);
    s.set_behavior(m);
    std::vector<int32_t> prev, goal;
    std::vector<uint8_t> back;
    std::vector<uint32_t> advances(n, 0);
    for (int step = 0; step < 600; ++step) {
        s.step(1);
        m->goals(s, goal, back);
        if (!prev.empty())
            for (uint32_t a = 0; a < n; ++a) {
                if (goal[a] == prev[a]) continue;
                // The next keypoint in the agent's direction, never a skip.
                const int expect = back[a] ? (prev[a] + 3) % 4 : (prev[a] + 1) % 4;
                ASSERT_EQ(goal[a], expect) << "agent " << a << " step " << step;
                EXPECT_EQ(back[a], a & 1u);
                ++advances[a];
            }
        prev = goal;
    }
    uint32_t moving = 0;
    for (uint32_t a = 0; a < n; ++a) moving += advances[a] >= 2;
    EXPECT_GE(moving, n * 3 / 4);
}

// keypoints_closed is in the model's parameter block (energy_select reads
// it there): set_keypoints(..., closed) that changes it uploads the block
// again, so the run equals one configured open from the start.
TEST(EnergyModel, SetKeypointsChangesClosedOnTheDevice) {
    auto ctx = shared_context();
    auto data = test_dataset();
    const uint32_t n = 20;
    EnergyModelConfig c;
    c.weights = {1, 0.5f, 0, 1, 1, 0, 1, 1};  // Table 1, shape constraint
    c.keypoints = {{0.2f, 0, 0}, {0, 0.2f, 0}, {-0.2f, 0, 0}, {0, -0.2f, 0}};
    c.keypoint_reach = 0.06f;
    auto goals_after = [&](bool closed, bool reopen) {
        Swarm s(ctx, small_config(n, 5));
        EnergyModelConfig cc = c;
        cc.keypoints_closed = closed;
        auto m = std::make_shared<EnergyModel>(s, cc, data);
        if (reopen) m->set_keypoints(c.keypoints, false);
        s.set_behavior(m);
        std::vector<int32_t> all, goal;
        std::vector<uint8_t> back;
        for (int step = 0; step < 300; ++step) {
            s.step(1);
            m->goals(s, goal, back);
            all.insert(all.end(), goal.begin(), goal.end());
        }
        return all;
    };
    const auto open = goals_after(false, false);
    EXPECT_EQ(goals_after(true, true), open);
    EXPECT_NE(goals_after(true, false), open) << "closed and open curves should differ within 300 steps";
}

TEST(EnergyModel, BadConfigurationsAreRefused) {
    auto ctx = shared_context();
    auto data = test_dataset();
    Swarm s(ctx, small_config(10, 1));
    auto refused = [&](const std::function<void(EnergyModelConfig&)>& edit) {
        EnergyModelConfig c;
        edit(c);
        try {
            EnergyModel m(s, c, data);
        } catch (const Error& e) {
            return e.status() == Status::InvalidArgument;
        }
        return false;
    };
    EXPECT_TRUE(refused([](EnergyModelConfig& c) { c.keypoints = {{0, 0, 0}}; }));
    EXPECT_TRUE(refused([](EnergyModelConfig& c) { c.weights.rep = -1; }));
    EXPECT_TRUE(refused([](EnergyModelConfig& c) { c.danger_weights.n = NAN; }));
    EXPECT_TRUE(refused([](EnergyModelConfig& c) { c.rho = 0; }));
    EXPECT_TRUE(refused([](EnergyModelConfig& c) { c.d_att1 = c.d_rep / 2; }));
    EXPECT_TRUE(refused([](EnergyModelConfig& c) { c.d_att2 = c.d_att1 / 2; }));
    EXPECT_TRUE(refused([](EnergyModelConfig& c) {
        c.stimuli.push_back({Stimulus::Kind::Startle, {0, 0, 0}, {0, 0, 0}, 0.0f});
    }));
    EXPECT_TRUE(refused([](EnergyModelConfig& c) { c.keypoints = {{0, 0, 0}, {NAN, 0, 0}}; }));
    EXPECT_THROW(EnergyModel(s, EnergyModelConfig{}, nullptr), Error);
    EnergyModel m(s, EnergyModelConfig{}, data);
    EXPECT_THROW(m.set_keypoints({{1, 2, 3}}, true), Error);
    EXPECT_TRUE(m.config().keypoints.empty());
}
