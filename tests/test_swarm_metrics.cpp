// The device path of the seven metrics (eval/swarm_metrics.hpp,
// kernels/metrics.cl) against the host reference (eval/metrics.cpp's
// frame_metrics on the same sampled positions, read back every sample) and
// a brute-force nearest neighbour; the fine-histogram accumulator
// (eval/metric_accumulator.hpp) against the raw samples; determinism, fixed
// memory and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "core/error.hpp"
#include "eval/metric_accumulator.hpp"
#include "eval/metrics.hpp"
#include "eval/pdf_distance.hpp"
#include "eval/swarm_metrics.hpp"
#include "models/field_model.hpp"
#include "test_support.hpp"

using namespace swarmcl;
using namespace swarmcl::test;

namespace {

constexpr float kDt = 1.0f / 60.0f;

std::unique_ptr<Swarm> noisy_swarm(uint32_t agents, uint64_t seed) {
    SwarmConfig c = cube_config(agents, -1.0f, 1.0f, 0.1f);
    c.agent_count = agents;
    c.seed = seed;
    c.dt = kDt;
    auto swarm = std::make_unique<Swarm>(shared_context(), c);
    FieldModelConfig m;
    m.noise.type = NoiseType::Curl;
    m.noise.seed = seed;
    m.noise.time_scale = 0.5f;
    m.noise.gain = 0.5f;
    m.has_goal = true;
    m.goal = {0.2f, 0.0f, -0.1f};
    m.goal_speed = 0.3f;
    swarm->set_behavior(std::make_shared<FieldModel>(*swarm, m));
    return swarm;
}

// Steps `frames` samples `k` steps apart, sampling on the device and
// recording the positions for the host reference.
std::vector<float> run(Swarm& swarm, SwarmMetrics& metrics, uint32_t frames, uint32_t k) {
    const uint32_t n = swarm.agent_count();
    std::vector<float> xyz(size_t(frames) * n * 3);
    for (uint32_t f = 0; f < frames; ++f) {
        if (f) swarm.step(k);
        metrics.sample();
        swarm.read(Attribute::Position, &xyz[size_t(f) * n * 3], n);
    }
    return xyz;
}

uint64_t matching_counts(const std::vector<uint64_t>& a, const std::vector<uint64_t>& b) {
    uint64_t m = 0;
    for (size_t i = 0; i < a.size(); ++i) m += std::min(a[i], b[i]);
    return m;
}

void expect_same_distributions(const MetricAccumulator& dev, const MetricAccumulator& host, const MetricSamples& raw) {
    for (size_t k = 0; k < kMetricCount; ++k) {
        const Metric m = Metric(k);
        SCOPED_TRACE(metric_name(m));
        ASSERT_EQ(host.count(m), raw[m].size());
        ASSERT_GT(host.count(m), 0u);
        ASSERT_EQ(dev.count(m), host.count(m));
        EXPECT_EQ(dev.nonfinite_count(m), 0u);
        // Counts equal but for values within float rounding of a fine edge.
        const uint64_t same = matching_counts(dev.histogram(m), host.histogram(m));
        const Moments md = dev.moments(m), mh = host.moments(m), mr = moments_of(raw[m]);
        EXPECT_GE(double(same), 0.999 * double(host.count(m))) << same << " of " << host.count(m);
        EXPECT_EQ(md.count, mh.count);
        // Relative to the larger of |mean| and σ: α's mean is near 0 (σ ~ 100).
        EXPECT_NEAR(md.mean, mh.mean, 1e-5 * std::max(std::abs(mh.mean), mh.sigma));
        EXPECT_NEAR(md.sigma, mh.sigma, 1e-5 * mh.sigma);
        EXPECT_NEAR(mh.mean, mr.mean, 1e-12 * std::abs(mr.mean));
        EXPECT_NEAR(mh.sigma, mr.sigma, 1e-9 * mr.sigma);
        const PdfOptions o;
        EXPECT_LT(pdf_l1(dev.discrete_pdf(m, o), host.discrete_pdf(m, o)), 1e-3);
    }
}

}  // namespace

TEST(FineBins, MonotoneSignedAndTheirValuesLieInside) {
    using namespace fine_bins;
    EXPECT_EQ(bin_of(0.0f), kZero);
    EXPECT_EQ(bin_of(-0.0f), kZero);
    EXPECT_EQ(bin_of(1e-12f), kZero);
    EXPECT_EQ(bin_of(std::ldexp(1.0f, -30)), kZero + 1);
    EXPECT_EQ(bin_of(-std::ldexp(1.0f, -30)), kZero - 1);
    EXPECT_EQ(bin_of(std::ldexp(1.0f, 30)), kPositiveOverflow);
    EXPECT_EQ(bin_of(-std::numeric_limits<float>::infinity()), kNegativeOverflow);
    EXPECT_EQ(bin_of(std::numeric_limits<float>::quiet_NaN()), kNaN);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> e(-29.9, 29.9);
    for (int t = 0; t < 20000; ++t) {
        const float x = float((t % 2 ? -1.0 : 1.0) * std::pow(2.0, e(rng)));
        const float y = std::nextafter(x, std::numeric_limits<float>::infinity());
        EXPECT_LE(bin_of(x), bin_of(y));
        const uint32_t b = bin_of(x);
        const double v = bin_value(b);
        EXPECT_EQ(bin_of(float(v)), b) << x;
        EXPECT_LE(std::abs(v - x), std::abs(x) * std::ldexp(1.0, -int(kMantissaBits))) << x;
    }
}

TEST(MetricAccumulator, PdfFromFineBinsIsCloseToTheRawSamplesPdfAndMergeIsAdd) {
    std::mt19937 rng(7);
    std::lognormal_distribution<double> ln(0.0, 0.8);
    std::normal_distribution<double> nd(0.3, 2.0);
    MetricSamples a, b;
    for (int i = 0; i < 20000; ++i) {
        for (size_t k = 0; k < kMetricCount; ++k) {
            const double x = Metric(k) == Metric::AngularAcceleration ? nd(rng) : ln(rng);
            (i % 3 ? a : b).values[k].push_back(x);
        }
    }
    MetricAccumulator acc_a, acc_b, all;
    acc_a.add(a);
    acc_b.add(b);
    MetricSamples ab = a;
    for (size_t k = 0; k < kMetricCount; ++k) ab.values[k].insert(ab.values[k].end(), b.values[k].begin(), b.values[k].end());
    all.add(ab);
    acc_a.merge(acc_b);
    for (size_t k = 0; k < kMetricCount; ++k) {
        const Metric m = Metric(k);
        EXPECT_EQ(acc_a.histogram(m), all.histogram(m));
        EXPECT_NEAR(acc_a.moments(m).mean, all.moments(m).mean, 1e-12);
        EXPECT_NEAR(acc_a.moments(m).sigma, all.moments(m).sigma, 1e-12);
        const PdfOptions o;
        const double e = pdf_l1(all.discrete_pdf(m, o), discrete_pdf(ab[m], moments_of(ab[m]), o));
        EXPECT_LT(e, 0.02) << metric_name(m);  // fine bins of 0.2% moved across z-bin edges only
    }
}

TEST(MetricAccumulator, MedianMadAndWassersteinFromFineBinsMatchTheSamples) {
    std::mt19937 rng(3);
    std::lognormal_distribution<double> ln(-0.5, 0.6);
    std::normal_distribution<double> nd(0.2, 1.5);
    MetricSamples a, b;
    for (int i = 0; i < 30000; ++i) {
        a[Metric::Speed].push_back(ln(rng));
        b[Metric::Speed].push_back(1.3 * ln(rng) + 0.05);
        a[Metric::AngularAcceleration].push_back(nd(rng));  // both signs, through zero
        b[Metric::AngularAcceleration].push_back(nd(rng) - 0.4);
    }
    MetricAccumulator acc_a, acc_b;
    acc_a.add(a);
    acc_b.add(b);
    for (Metric m : {Metric::Speed, Metric::AngularAcceleration}) {
        const double med = median_of(a[m]), mad = mad_of(a[m], med);
        // Within a fine bin's relative width (2^-9) of the samples' own.
        EXPECT_NEAR(acc_a.median(m), med, 4e-3 * std::abs(med) + 1e-6) << metric_name(m);
        EXPECT_NEAR(acc_a.mad(m), mad, 4e-3 * mad) << metric_name(m);
        const double exact = wasserstein1(a[m], b[m]);
        EXPECT_GT(exact, 0.05) << metric_name(m);
        EXPECT_NEAR(acc_a.wasserstein1(m, acc_b), exact, 5e-3 * exact) << metric_name(m);
        EXPECT_NEAR(acc_a.wasserstein1(m, acc_a), 0.0, 1e-12);
    }
    // No samples on a side: a clear error naming the metric.
    try {
        acc_a.wasserstein1(Metric::Jerk, acc_b);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("jerk"), std::string::npos) << e.what();
    }
    EXPECT_EQ(acc_a.median(Metric::Jerk), 0.0);
}

TEST(MetricAccumulator, NonFiniteSamplesRefuseAPdf) {
    MetricSamples s;
    s[Metric::Speed] = {1.0, 2.0, std::numeric_limits<double>::quiet_NaN()};
    MetricAccumulator acc;
    acc.add(s);
    EXPECT_EQ(acc.count(Metric::Speed), 3u);
    EXPECT_EQ(acc.nonfinite_count(Metric::Speed), 1u);
    EXPECT_THROW(acc.discrete_pdf(Metric::Speed, PdfOptions{}), Error);
    EXPECT_EQ(acc.discrete_pdf(Metric::Jerk, PdfOptions{}), std::vector<double>(50, 0.0));  // empty
}

TEST(SwarmMetrics, DeviceMatchesTheHostReferenceOnTheSameTrajectories) {
    auto swarm = noisy_swarm(700, 11);
    const uint32_t k = 3;
    SwarmMetrics dev(*swarm, double(k) * kDt);
    const uint32_t frames = 30;
    const auto xyz = run(*swarm, dev, frames, k);
    const MetricSamples raw = frame_metrics(xyz.data(), frames, swarm->agent_count(), double(k) * kDt);
    MetricAccumulator host;
    host.add(raw);
    expect_same_distributions(dev.result(), host, raw);
    EXPECT_EQ(dev.samples(), frames);
}

TEST(SwarmMetrics, ResultCanBeTakenWhileSamplingGoesOn) {
    auto swarm = noisy_swarm(300, 5);
    SwarmMetrics dev(*swarm, kDt);
    const auto xyz1 = run(*swarm, dev, 6, 1);
    const MetricAccumulator early = dev.result();
    EXPECT_EQ(early.count(Metric::NearestDistance), 6u * 300u);
    EXPECT_EQ(early.count(Metric::Jerk), 3u * 300u);
    const auto xyz2 = run(*swarm, dev, 10, 1);
    std::vector<float> xyz = xyz1;
    // The second run's first frame is the first run's last sampled again
    // (no step between): zero speeds, so no ω there.
    xyz.insert(xyz.end(), xyz2.begin(), xyz2.end());
    const MetricSamples raw = frame_metrics(xyz.data(), 16, 300, kDt);
    MetricAccumulator host;
    host.add(raw);
    expect_same_distributions(dev.result(), host, raw);
}

// Nearest neighbours over points with exact ties (a lattice: 6 at the same
// distance), coincident pairs and a far cluster: d of every frame and η
// (which depends on which neighbour is taken: the lowest index) against a
// brute force in float, written as the kernel computes; `cloud_points`
// random points beside the lattice.
static void expect_nearest_matches_brute_force(uint32_t cloud_points) {
    std::vector<float> p0;
    for (int z = 0; z < 6; ++z)
        for (int y = 0; y < 6; ++y)
            for (int x = 0; x < 6; ++x) p0.insert(p0.end(), {0.125f * x, 0.125f * y, 0.125f * z});
    const auto cloud = random_points(cloud_points, -0.9f, -0.3f, 9);
    p0.insert(p0.end(), cloud.begin(), cloud.end());
    p0.insert(p0.end(), {0.7f, 0.7f, 0.7f, 0.7f, 0.7f, 0.7f, 5.0f, 5.0f, 5.0f});  // a coincident pair, one far away
    const uint32_t n = uint32_t(p0.size() / 3);
    std::vector<float> p1 = p0;
    std::mt19937 rng(4);
    std::uniform_real_distribution<float> u(-0.01f, 0.01f);
    for (auto& v : p1) v += u(rng);
    SwarmConfig c = cube_config(n, -1.0f, 1.0f, 0.1f);
    c.agent_count = n;
    Swarm swarm(shared_context(), c);
    const float dt = 0.05f;
    SwarmMetrics dev(swarm, dt);
    swarm.write(Attribute::Position, p0.data(), n);
    dev.sample();
    swarm.write(Attribute::Position, p1.data(), n);
    dev.sample();
    const MetricAccumulator r = dev.result();

    std::vector<uint64_t> d_hist(fine_bins::kCount, 0), eta_hist(fine_bins::kCount, 0);
    auto nearest = [&](const std::vector<float>& p, uint32_t i, float& d2_best) {
        uint32_t best = 0;
        d2_best = std::numeric_limits<float>::infinity();
        for (uint32_t j = 0; j < n; ++j) {
            if (j == i) continue;
            const float d2 = dist2(&p[3 * i], &p[3 * j]);
            if (d2 < d2_best) d2_best = d2, best = j;  // ascending j: ties keep the lowest
        }
        return best;
    };
    // Speeds in double (as the kernel where the device has doubles, and the host reference).
    auto speed = [&](uint32_t i) {
        const double dx = double(p1[3 * i]) - p0[3 * i], dy = double(p1[3 * i + 1]) - p0[3 * i + 1],
                     dz = double(p1[3 * i + 2]) - p0[3 * i + 2];
        return std::sqrt(dx * dx + dy * dy + dz * dz) / double(dt);
    };
    uint64_t etas = 0;
    for (uint32_t i = 0; i < n; ++i) {
        float d2;
        const uint32_t j = nearest(p0, i, d2);
        const float d = std::sqrt(d2);
        ++d_hist[fine_bins::bin_of(d)];
        if (d > 0.0f) {
            ++eta_hist[fine_bins::bin_of(float(std::fabs(speed(j) - speed(i)) / d))];
            ++etas;
        }
        nearest(p1, i, d2);
        ++d_hist[fine_bins::bin_of(std::sqrt(d2))];
    }
    EXPECT_EQ(r.histogram(Metric::NearestDistance), d_hist);
    EXPECT_EQ(r.count(Metric::VelocityDifference), etas);
    EXPECT_EQ(etas, n - 2u);  // the coincident pair has d = 0: no η
    EXPECT_GE(double(matching_counts(r.histogram(Metric::VelocityDifference), eta_hist)), 0.999 * double(etas));
}

TEST(SwarmMetrics, NearestNeighbourMatchesBruteForce) { expect_nearest_matches_brute_force(400); }

// 919 points at 8 lanes: a row of the 1,024 cells is expected to hold 9, so
// the 8-lane kernel takes a box a row each (MN_ROWS_APART; Oclgrind runs
// this case in the CPU profile).
TEST(SwarmMetrics, NearestNeighbourMatchesBruteForceWithTheRowsApart) {
    ScopedKernelWidth w(8);
    expect_nearest_matches_brute_force(700);
}

TEST(SwarmMetrics, SameSeedGivesBitwiseTheSameHistogramsAndMoments) {
    MetricAccumulator r[2];
    for (int t = 0; t < 2; ++t) {
        auto swarm = noisy_swarm(500, 21);
        SwarmMetrics dev(*swarm, 2.0 * kDt);
        for (int f = 0; f < 12; ++f) {
            swarm->step(2);
            dev.sample();
        }
        r[t] = dev.result();
    }
    for (size_t k = 0; k < kMetricCount; ++k) {
        const Metric m = Metric(k);
        EXPECT_EQ(r[0].histogram(m), r[1].histogram(m)) << metric_name(m);
        EXPECT_EQ(r[0].raw_moments(m).count, r[1].raw_moments(m).count);
        EXPECT_EQ(r[0].raw_moments(m).mean, r[1].raw_moments(m).mean);
        EXPECT_EQ(r[0].raw_moments(m).m2, r[1].raw_moments(m).m2);
    }
}

// The nearest-neighbour and per-agent kernels at 8 and 16 lanes
// (metrics_nearest_w and metrics_sample_w, the CPU devices' default) against
// one point a work-item: the same neighbours and the same arithmetic, so
// bitwise the same values of every metric (v, a, ω and α in double lanes, μ,
// d, η), for a swarm of `agents`: a swarm the goal gathers (dense cells), a
// few agents far out (a box grown to the grid's edge) and five points a line
// of equal gaps (ties).  1003 agents: the last work-item's lanes past the end.
static void expect_every_width_agrees(uint32_t agents) {
    // Any device runs the wide kernel when the width is forced (the GPU
    // profile too, with its atomic histograms).
    std::vector<MetricAccumulator> r;
    for (const uint32_t width : {1u, 8u, 16u}) {
        ScopedKernelWidth w(width);
        auto swarm = noisy_swarm(agents, 8);
        std::vector<float> p(3 * agents);
        swarm->read(Attribute::Position, p.data(), agents);
        for (uint32_t i = 0; i < 5; ++i) p[3 * i] = 0.95f, p[3 * i + 1] = 0.95f - 0.01f * float(i);
        swarm->write(Attribute::Position, p.data(), agents);
        SwarmMetrics dev(*swarm, 2.0 * kDt);
        for (int f = 0; f < 10; ++f) {
            swarm->step(2);
            dev.sample();
        }
        r.push_back(dev.result());
    }
    for (size_t w = 1; w < r.size(); ++w)
        for (size_t k = 0; k < kMetricCount; ++k) {
            const Metric m = Metric(k);
            SCOPED_TRACE(std::string(metric_name(m)) + (w == 1 ? ", 8 lanes" : ", 16 lanes"));
            ASSERT_GT(r[0].count(m), 0u);
            EXPECT_EQ(r[w].histogram(m), r[0].histogram(m));
            EXPECT_EQ(r[w].raw_moments(m).count, r[0].raw_moments(m).count);
            EXPECT_EQ(r[w].raw_moments(m).mean, r[0].raw_moments(m).mean);
            EXPECT_EQ(r[w].raw_moments(m).m2, r[0].raw_moments(m).m2);
        }
}

TEST(SwarmMetrics, EveryKernelWidthGivesTheScalarKernelsResults) { expect_every_width_agrees(1003); }

// 12,000 agents: a row of the point grid's cells holds about 23 points, so
// the 16-lane nearest neighbours take a box a row each (MN_ROWS_APART; at
// 1,003 agents only the 8-lane kernel does), and enough lanes of a group's
// first rows go on alone that a later row's lanes overwriting theirs fails.
TEST(SwarmMetrics, EveryKernelWidthAgreesWithTheRowsApart) { expect_every_width_agrees(12000); }

// The 32-bit device counters folded into the host's every few samples
// (as they are before one could overflow) give the same result.
TEST(SwarmMetrics, FoldingTheDeviceCountersChangesNothing) {
    MetricAccumulator r[2];
    for (int t = 0; t < 2; ++t) {
        auto swarm = noisy_swarm(200, 8);
        SwarmMetrics dev(*swarm, kDt);
        if (t) dev.set_fold_limit(700);  // a fold every 3 samples
        for (int f = 0; f < 20; ++f) {
            swarm->step(1);
            dev.sample();
        }
        r[t] = dev.result();
    }
    for (size_t k = 0; k < kMetricCount; ++k) {
        EXPECT_EQ(r[0].histogram(Metric(k)), r[1].histogram(Metric(k))) << metric_name(Metric(k));
        EXPECT_EQ(r[0].raw_moments(Metric(k)).m2, r[1].raw_moments(Metric(k)).m2);
    }
    EXPECT_EQ(r[1].count(Metric::NearestDistance), 20u * 200u);
}

TEST(SwarmMetrics, MemoryDoesNotGrowWithFrames) {
    auto swarm = noisy_swarm(200, 2);
    SwarmMetrics dev(*swarm, kDt);
    const size_t bytes = dev.device_bytes();
    EXPECT_LT(bytes, size_t(200) * 200 + 8u * 1024 * 1024);  // the histograms and O(agents)
    for (int f = 0; f < 400; ++f) {
        swarm->step(1);
        dev.sample();
    }
    EXPECT_EQ(dev.device_bytes(), bytes);
    const MetricAccumulator r = dev.result();
    EXPECT_EQ(r.count(Metric::NearestDistance), 400u * 200u);
    EXPECT_EQ(r.count(Metric::Speed), 399u * 200u);
    EXPECT_EQ(r.histogram(Metric::Speed).size(), size_t(fine_bins::kCount));
}

// A diverged run (positions not finite) is counted, never crashes, and
// refuses a PDF of the metrics it spoils.
TEST(SwarmMetrics, NonFinitePositionsAreCountedAndRefuseAPdf) {
    const uint32_t n = 50;
    auto p = random_points(n, -1.0f, 1.0f, 12);
    SwarmConfig c = cube_config(n, -1.0f, 1.0f, 0.1f);
    c.agent_count = n;
    Swarm swarm(shared_context(), c);
    SwarmMetrics dev(swarm, 0.1);
    for (int f = 0; f < 4; ++f) {
        if (f == 2) p[0] = p[1] = p[2] = std::numeric_limits<float>::quiet_NaN();
        for (auto& v : p) v += 0.01f;
        // Straight into the device state: Swarm::write refuses non-finite values.
        std::vector<cl_float4> q(n);
        for (uint32_t i = 0; i < n; ++i) q[i] = cl_float4{{p[3 * i], p[3 * i + 1], p[3 * i + 2], 0.0f}};
        swarm.positions().upload(swarm.context(), q.data(), n);
        dev.sample();
    }
    const MetricAccumulator r = dev.result();
    EXPECT_EQ(r.count(Metric::NearestDistance), 4u * n);
    EXPECT_GT(r.nonfinite_count(Metric::NearestDistance), 0u);
    EXPECT_GT(r.nonfinite_count(Metric::Speed), 0u);
    EXPECT_THROW(r.discrete_pdf(Metric::Speed, PdfOptions{}), Error);
    EXPECT_TRUE(std::isfinite(r.moments(Metric::Speed).mean));
}

TEST(SwarmMetrics, BadInputIsAClearError) {
    auto swarm = noisy_swarm(10, 1);
    for (double dt : {0.0, -1.0, std::nan(""), std::numeric_limits<double>::infinity(), 1e-60}) {
        try {
            SwarmMetrics m(*swarm, dt);
            ADD_FAILURE() << "dt " << dt << " accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("time between samples"), std::string::npos) << e.what();
        }
    }
    SwarmConfig c = cube_config(4, -1.0f, 1.0f, 0.1f);
    c.agent_count = 1;
    Swarm one(shared_context(), c);
    try {
        SwarmMetrics m(one, 0.1);
        ADD_FAILURE() << "a swarm of 1 agent accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("at least 2 agents"), std::string::npos) << e.what();
    }
}
