// The evaluation against real insects (issue 14): the seven metrics on the
// host against closed forms and a plain per-frame reference, the discrete
// PDFs and their distances (Eq. 1-3), and the entropy weights (Eq. 4).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>

#include "core/error.hpp"
#include "data/tracks.hpp"
#include "eval/entropy_weights.hpp"
#include "eval/metrics.hpp"
#include "eval/nearest_sweep.hpp"
#include "eval/pdf_distance.hpp"
#include "eval/time_window.hpp"

using namespace swarmcl;

namespace {

Track line_track(const std::string& id, double t0, size_t n, double dt, std::array<double, 3> p0,
                 std::array<double, 3> v) {
    Track s;
    s.id = id;
    for (size_t k = 0; k < n; ++k) {
        const double t = t0 + double(k) * dt;
        s.t.push_back(t);
        s.p.push_back({p0[0] + v[0] * (t - t0), p0[1] + v[1] * (t - t0), p0[2] + v[2] * (t - t0)});
    }
    return s;
}

// The frames written as one track per agent, the way the track loader would
// hold them (frame f at t = f dt).
TrackSet frames_as_tracks(const std::vector<float>& xyz, size_t frames, size_t agents, double dt) {
    TrackSet set;
    set.frame_time = dt;
    for (size_t i = 0; i < agents; ++i) {
        Track s;
        s.id = std::to_string(i);
        for (size_t f = 0; f < frames; ++f) {
            const float* q = &xyz[3 * (f * agents + i)];
            s.t.push_back(double(f) * dt);
            s.p.push_back({q[0], q[1], q[2]});
        }
        set.tracks.push_back(std::move(s));
    }
    return set;
}

void expect_same_samples(const MetricSamples& a, const MetricSamples& b) {
    for (size_t m = 0; m < kMetricCount; ++m) {
        ASSERT_EQ(a.values[m].size(), b.values[m].size()) << metric_name(Metric(m));
        for (size_t k = 0; k < a.values[m].size(); ++k) {
            const double x = a.values[m][k], y = b.values[m][k];
            ASSERT_TRUE(x == y || (std::isnan(x) && std::isnan(y)))  // the same value (NaN where a run blew up)
                << metric_name(Metric(m)) << " sample " << k << ": " << x << " vs " << y;
        }
    }
}

// d and η of every frame against a brute force over all pairs in double, the
// lowest index winning ties (the samples' order: frame by frame, agent by
// agent).
void expect_brute_force_neighbours(const MetricSamples& m, const std::vector<float>& xyz, size_t frames,
                                   size_t agents, double dt) {
    auto at = [&](size_t f, size_t i) { return &xyz[3 * (f * agents + i)]; };
    auto dist2 = [](const float* a, const float* b) {
        double s = 0;
        for (int c = 0; c < 3; ++c) s += (double(b[c]) - a[c]) * (double(b[c]) - a[c]);
        return s;
    };
    auto dist = [&](const float* a, const float* b) { return std::sqrt(dist2(a, b)); };
    ASSERT_EQ(m[Metric::NearestDistance].size(), agents * frames);
    size_t eta_k = 0;
    for (size_t f = 0; f < frames; ++f)
        for (size_t i = 0; i < agents; ++i) {
            double best2 = 1e300;
            size_t nn = 0;
            for (size_t j = 0; j < agents; ++j)
                if (j != i && dist2(at(f, i), at(f, j)) < best2) best2 = dist2(at(f, i), at(f, j)), nn = j;
            const double best = std::sqrt(best2);
            EXPECT_NEAR(m[Metric::NearestDistance][f * agents + i], best, 1e-12);
            if (f + 1 < frames && best > 0.0) {
                const double v = dist(at(f + 1, i), at(f, i)) / dt, vn = dist(at(f + 1, nn), at(f, nn)) / dt;
                ASSERT_LT(eta_k, m[Metric::VelocityDifference].size());
                EXPECT_NEAR(m[Metric::VelocityDifference][eta_k++], std::abs(vn - v) / best, 1e-6)
                    << "frame " << f << " agent " << i;
            }
        }
    EXPECT_EQ(eta_k, m[Metric::VelocityDifference].size());
}

}  // namespace

TEST(EvalMetrics, StraightLineHasConstantSpeedAndNoTurning) {
    TrackSet set;
    set.frame_time = 0.01;
    set.tracks.push_back(line_track("a", 0.0, 10, 0.01, {0, 0, 0}, {0.3, 0.4, 0.0}));
    const auto m = track_metrics(set);
    ASSERT_EQ(m[Metric::Speed].size(), 9u);
    ASSERT_EQ(m[Metric::Acceleration].size(), 8u);
    ASSERT_EQ(m[Metric::AngularVelocity].size(), 8u);
    ASSERT_EQ(m[Metric::AngularAcceleration].size(), 7u);
    ASSERT_EQ(m[Metric::Jerk].size(), 7u);
    for (double v : m[Metric::Speed]) EXPECT_NEAR(v, 0.5, 1e-9);
    for (double a : m[Metric::Acceleration]) EXPECT_NEAR(a, 0.0, 1e-9);
    for (double w : m[Metric::AngularVelocity]) EXPECT_NEAR(w, 0.0, 1e-5);
    EXPECT_TRUE(m[Metric::NearestDistance].empty());  // one insect in view: no d
    EXPECT_TRUE(m[Metric::VelocityDifference].empty());
}

TEST(EvalMetrics, CircleHasTheClosedFormTurnRateAndAcceleration) {
    // Uniform circular motion sampled every dt: consecutive chords turn by
    // Ω dt, so ω = Ω exactly; |Δv| / dt = 2 |v| sin(Ω dt / 2) / dt; α = 0, and
    // the chord accelerations rotate by Ω dt, so μ = 2 |a| sin(Ω dt / 2) / dt.
    const double R = 0.2, Omega = 3.0, dt = 0.01;
    TrackSet set;
    set.frame_time = dt;
    Track s;
    s.id = "c";
    for (int k = 0; k < 50; ++k) {
        const double t = k * dt;
        s.t.push_back(t);
        s.p.push_back({R * std::cos(Omega * t), R * std::sin(Omega * t), 1.0});
    }
    set.tracks.push_back(s);
    const auto m = track_metrics(set);
    const double chord_speed = 2 * R * std::sin(Omega * dt / 2) / dt;
    const double acc = 2 * chord_speed * std::sin(Omega * dt / 2) / dt;
    const double jerk = 2 * acc * std::sin(Omega * dt / 2) / dt;
    for (double v : m[Metric::Speed]) EXPECT_NEAR(v, chord_speed, 1e-9);
    for (double a : m[Metric::Acceleration]) EXPECT_NEAR(a, acc, 1e-6);
    for (double w : m[Metric::AngularVelocity]) EXPECT_NEAR(w, Omega, 1e-5);
    for (double al : m[Metric::AngularAcceleration]) EXPECT_NEAR(al, 0.0, 1e-2);
    for (double j : m[Metric::Jerk]) EXPECT_NEAR(j, jerk, 1e-3 * jerk);
}

TEST(EvalMetrics, NoDifferenceCrossesAGapBetweenSegments) {
    // One insect seen twice with a gap: two segments.  A jump across the gap
    // would show as a huge speed if differenced; it must not appear.
    TrackSet set;
    set.frame_time = 0.01;
    set.tracks.push_back(line_track("a", 0.0, 5, 0.01, {0, 0, 0}, {1, 0, 0}));
    set.tracks.push_back(line_track("a", 0.2, 5, 0.01, {50, 0, 0}, {1, 0, 0}));
    const auto m = track_metrics(set);
    ASSERT_EQ(m[Metric::Speed].size(), 8u);
    for (double v : m[Metric::Speed]) EXPECT_NEAR(v, 1.0, 1e-9);
    EXPECT_TRUE(m[Metric::NearestDistance].empty());  // the segments never share a frame
}

TEST(EvalMetrics, NearestDistanceOnlyAmongInsectsInViewOnTheSameFrame) {
    // a: frames 0..9; b: frames 5..14, 0.3 m away; c: frames 12..19, far.
    TrackSet set;
    set.frame_time = 0.01;
    set.tracks.push_back(line_track("a", 0.00, 10, 0.01, {0, 0, 0}, {1, 0, 0}));
    set.tracks.push_back(line_track("b", 0.05, 10, 0.01, {0.05, 0.3, 0}, {2, 0, 0}));
    set.tracks.push_back(line_track("c", 0.12, 8, 0.01, {5, 5, 5}, {0, 0, 1}));
    const auto m = track_metrics(set);
    // Frames 5..9 have a and b (2 d each); frames 12..14 have b and c.
    ASSERT_EQ(m[Metric::NearestDistance].size(), 2u * 5 + 2u * 3);
    // Frame 5: a at x=0.05, b at x=0.05 + 0 -> 0.3 apart; a's speed 1, b's 2.
    EXPECT_NEAR(m[Metric::NearestDistance][0], 0.3, 1e-9);
    EXPECT_NEAR(m[Metric::VelocityDifference][0], 1.0 / 0.3, 1e-6);
    // η needs both velocities: a's last sample (frame 9) has none, so frame 9
    // gives d twice but no η; b's last sample is frame 14: no η there either.
    EXPECT_EQ(m[Metric::VelocityDifference].size(), 2u * 4 + 2u * 2);
}

TEST(EvalMetrics, FrameMetricsEqualTheTrackPathAndABruteForceReference) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    const size_t frames = 12, agents = 60;
    std::vector<float> xyz(frames * agents * 3);
    for (size_t i = 0; i < agents; ++i) {
        float p[3] = {u(rng), u(rng), u(rng)};
        for (size_t f = 0; f < frames; ++f)
            for (int c = 0; c < 3; ++c) xyz[3 * (f * agents + i) + c] = p[c] += 0.02f * u(rng);
    }
    const double dt = 0.02;
    const auto m = frame_metrics(xyz.data(), frames, agents, dt);
    ASSERT_EQ(m[Metric::Speed].size(), agents * (frames - 1));
    expect_brute_force_neighbours(m, xyz, frames, agents, dt);
    // The dense path gives the track path's samples bitwise, in its order.
    expect_same_samples(m, track_metrics(frames_as_tracks(xyz, frames, agents, dt)));
}

// Exact ties and degenerate frames for the nearest-neighbour sweep: a lattice
// (six neighbours at one distance), coincident pairs, a flat layer (every
// point on one x) and a far glitch that stretches one axis.  d and η (which
// depends on which neighbour is taken: the lowest index) against the brute
// force, and the track path bitwise.
TEST(EvalMetrics, FrameNeighboursKeepTiesAndDegenerateLayouts) {
    std::vector<std::array<float, 3>> base;
    for (int z = 0; z < 5; ++z)
        for (int y = 0; y < 5; ++y)
            for (int x = 0; x < 5; ++x) base.push_back({0.125f * x, 0.125f * y, 0.125f * z});
    for (int k = 0; k < 40; ++k) base.push_back({2.0f, 0.05f * float(k % 8), 0.05f * float(k / 8)});  // flat layer
    base.push_back(base[3]);                 // coincident with a lattice point
    base.push_back(base[130]);               // and with a layer point
    base.push_back({90.0f, -40.0f, 7.0f});   // a tracking glitch far away
    const size_t agents = base.size(), frames = 40;
    std::mt19937 rng(3);
    std::uniform_int_distribution<int> coin(0, 3);
    std::vector<float> xyz;
    for (size_t f = 0; f < frames; ++f)
        for (size_t i = 0; i < agents; ++i) {
            // Whole lattice steps (exact in float) on some frames keep ties.
            const float shift = 0.125f * float(coin(rng) == 0 && i < 125);
            for (int c = 0; c < 3; ++c) xyz.push_back(base[i][c] + (c == 0 ? shift : 0.0f) + 0.25f * float(f));
        }
    const double dt = 0.05;
    const auto m = frame_metrics(xyz.data(), frames, agents, dt);
    expect_brute_force_neighbours(m, xyz, frames, agents, dt);
    expect_same_samples(m, track_metrics(frames_as_tracks(xyz, frames, agents, dt)));
}

// A swarm that shrinks 100-fold and spreads again (the last frame's
// neighbour, the sweep's first bound, far from the nearest; the axis chosen
// every few frames), far from the origin (1e4 m: coordinates of few bits in
// float, so many exact ties) and in a plane on some frames, against the
// brute force.
TEST(EvalMetrics, FrameNeighboursStayExactAsTheSwarmShrinksAndSpreads) {
    const size_t agents = 300, frames = 70;
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::vector<std::array<float, 3>> base(agents);
    for (auto& b : base) b = {u(rng), u(rng), u(rng)};
    std::vector<float> xyz;
    for (size_t f = 0; f < frames; ++f) {
        const double scale = f < 35 ? std::pow(0.877, double(f)) : std::pow(0.877, 70.0 - double(f));
        for (size_t i = 0; i < agents; ++i)
            for (int c = 0; c < 3; ++c) {
                const float flat = (f % 9 == 4 && c == 2) ? 0.0f : 1.0f;  // every 9th frame in a plane
                xyz.push_back(float(1e4 + scale * flat * (base[i][c] + 0.01f * u(rng))));
            }
    }
    const double dt = 0.01;
    const auto m = frame_metrics(xyz.data(), frames, agents, dt);
    expect_brute_force_neighbours(m, xyz, frames, agents, dt);
}

// The brute force's nearest other point of each point: the least (r2,
// index), r2 the differences (other - point) squared and summed x, y, z.
static std::vector<uint32_t> brute_nearest(const std::vector<NearestSweep::Vec3>& p) {
    std::vector<uint32_t> nn(p.size());
    for (size_t i = 0; i < p.size(); ++i) {
        double best = std::numeric_limits<double>::infinity();
        for (size_t j = 0; j < p.size(); ++j) {
            const double dx = p[j][0] - p[i][0], dy = p[j][1] - p[i][1], dz = p[j][2] - p[i][2];
            const double r2 = dx * dx + dy * dy + dz * dz;
            if (j != i && r2 < best) best = r2, nn[i] = uint32_t(j);
        }
    }
    return nn;
}

// The sweep's two scans, eight candidates at a time (AVX2, where the CPU has
// it) and one at a time, against the brute force's least (r2, index): frames
// of 2 to 70 points (fewer than a block, a block and a bit), random and on a
// lattice (exact ties), with no hint, random hints and last frame's answers.
TEST(EvalMetrics, NearestSweepScansGiveTheBruteForcesNeighbour) {
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    std::uniform_int_distribution<int> cell(0, 3);
    for (size_t g : {size_t(2), size_t(3), size_t(4), size_t(5), size_t(8), size_t(9), size_t(33), size_t(70)})
        for (int lattice = 0; lattice < 2; ++lattice) {
            NearestSweep wide(true), narrow(false);
            std::vector<uint32_t> last_wide, last_narrow;
            for (int frame = 0; frame < 40; ++frame) {  // past kAxisEvery: the axis is chosen again
                std::vector<NearestSweep::Vec3> p(g);
                for (auto& q : p)
                    for (double& c : q) c = lattice ? 0.25 * cell(rng) : double(u(rng));
                const std::vector<uint32_t> expect = brute_nearest(p);
                std::vector<uint32_t> random_hint(g);
                for (size_t i = 0; i < g; ++i) random_hint[i] = uint32_t(rng() % g);
                const bool use_last = frame % 3 != 0 && !last_wide.empty();
                const std::vector<uint32_t>* hw = frame % 3 == 0 ? nullptr : use_last ? &last_wide : &random_hint;
                const std::vector<uint32_t>* hn = frame % 3 == 0 ? nullptr : use_last ? &last_narrow : &random_hint;
                std::vector<uint32_t> a, b;
                wide.find(p, hw, a);
                narrow.find(p, hn, b);
                ASSERT_EQ(a, expect) << g << " points, lattice " << lattice << ", frame " << frame;
                ASSERT_EQ(b, expect) << g << " points, lattice " << lattice << ", frame " << frame;
                last_wide = a, last_narrow = b;
            }
        }
}

// The wide scan filters candidates in float and confirms them in double: on
// double coordinates that float rounds (far from the origin, spacings below
// a float's resolution there, exact ties on a lattice) and past the float
// range (1e20: the double scan), it still answers as the brute force.
TEST(EvalMetrics, NearestSweepsFloatFilterKeepsEveryCandidateItMustTest) {
    std::mt19937 rng(31);
    for (const double offset : {0.0, 1e3, 1e6, 1e20})
        for (const double spread : {1e-4, 1.0})
            for (int lattice = 0; lattice < 2; ++lattice) {
                std::uniform_real_distribution<double> u(-spread, spread);
                std::uniform_int_distribution<int> cell(0, 4);
                NearestSweep wide(true), narrow(false);
                for (int frame = 0; frame < 6; ++frame) {
                    std::vector<NearestSweep::Vec3> p(90);
                    for (auto& q : p)
                        for (double& c : q) c = offset + (lattice ? spread * 0.25 * cell(rng) : u(rng));
                    const std::vector<uint32_t> expect = brute_nearest(p);
                    std::vector<uint32_t> a, b;
                    wide.find(p, nullptr, a);
                    narrow.find(p, nullptr, b);
                    ASSERT_EQ(a, expect) << "offset " << offset << ", spread " << spread << ", lattice " << lattice;
                    ASSERT_EQ(b, expect) << "offset " << offset << ", spread " << spread << ", lattice " << lattice;
                }
            }
}

// One sweep across frames of changing size (its arrays laid out again, the
// pads past either end kept NaN) answers as the brute force.
TEST(EvalMetrics, OneNearestSweepServesFramesOfChangingSize) {
    std::mt19937 rng(29);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (const bool wide_scan : {true, false}) {
        NearestSweep sweep(wide_scan);
        std::vector<uint32_t> last;
        size_t last_g = 0;
        for (size_t g : {size_t(33), size_t(9), size_t(9), size_t(2), size_t(70), size_t(33), size_t(5)}) {
            std::vector<NearestSweep::Vec3> p(g);
            for (auto& q : p)
                for (double& c : q) c = u(rng);
            const std::vector<uint32_t> expect = brute_nearest(p);
            std::vector<uint32_t> nn;
            sweep.find(p, g == last_g ? &last : nullptr, nn);
            ASSERT_EQ(nn, expect) << g << " points, wide " << wide_scan;
            last = nn, last_g = g;
        }
    }
}

TEST(EvalMetrics, BadInputIsRefused) {
    TrackSet set;
    set.frame_time = 0.0;
    EXPECT_THROW(track_metrics(set), Error);
    EXPECT_THROW(frame_metrics(nullptr, 2, 2, 0.1), Error);
    float p[6] = {};
    EXPECT_THROW(frame_metrics(p, 1, 2, -1.0), Error);
}

TEST(EvalPdf, DensitiesIntegrateToOneAndTailsGoToTheEndBins) {
    std::vector<double> x;
    for (int i = 0; i < 1000; ++i) x.push_back(i % 17 == 0 ? 1e6 : double(i % 10));
    PdfOptions o;
    o.bins = 20;
    const auto q = discrete_pdf(x, moments_of(x), o);
    double mass = 0;
    for (double v : q) mass += v * (2 * o.half_width) / o.bins;
    EXPECT_NEAR(mass, 1.0, 1e-12);
    EXPECT_GT(q.back(), 0.0);  // the 1e6 outliers
}

// Step 2-3 as written: z, floor, clamp, one count per sample.
static std::vector<double> pdf_by_definition(const std::vector<double>& x, const Moments& m, const PdfOptions& o) {
    const double u1 = -o.half_width, u2 = o.half_width;
    std::vector<uint64_t> counts(o.bins, 0);
    for (double v : x) {
        const double z = m.sigma > 0.0 ? (v - m.mean) / m.sigma : 0.0;
        const double b = std::clamp(std::floor((z - u1) / (u2 - u1) * o.bins), 0.0, double(o.bins - 1));
        ++counts[size_t(b)];
    }
    std::vector<double> q(o.bins, 0.0);
    for (uint32_t i = 0; i < o.bins && !x.empty(); ++i) q[i] = double(counts[i]) * o.bins / (double(x.size()) * (u2 - u1));
    return q;
}

TEST(EvalPdf, DensitiesAreTheDefinitionsBitForBit) {
    std::mt19937 rng(11);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (const size_t n : {size_t(0), size_t(1), size_t(3), size_t(1027), size_t(5003)}) {
        std::vector<double> x;
        for (size_t i = 0; i < n; ++i) {
            // Runs of one value (an insect hovering), far tails both sides,
            // and the bulk.
            const double v = i % 7 == 0 ? 2.5 : i % 11 == 0 ? (i % 2 ? 1e9 : -1e9) : normal(rng);
            x.push_back(v);
        }
        for (const uint32_t bins : {1u, 2u, 50u, 333u}) {
            PdfOptions o;
            o.bins = bins;
            for (const auto how : {Standardise::MeanSigma, Standardise::MedianMad}) {
                o.standardise = how;
                const Moments m = location_scale(x, how);
                EXPECT_EQ(discrete_pdf(x, m, o), pdf_by_definition(x, m, o)) << n << " " << bins;
            }
            // Samples on the bins' edges: z = 0 and 1 with mean 0, sigma 1.
            Moments unit;
            unit.mean = 0.0, unit.sigma = 1.0, unit.count = x.size();
            std::vector<double> edges;
            for (uint32_t b = 0; b <= bins; ++b) edges.push_back(-o.half_width + 2.0 * o.half_width * b / bins);
            EXPECT_EQ(discrete_pdf(edges, unit, o), pdf_by_definition(edges, unit, o)) << bins;
            // Scale 0: everything in the bin of z = 0.
            const Moments flat{};
            EXPECT_EQ(discrete_pdf(x, flat, o), pdf_by_definition(x, flat, o)) << bins;
        }
    }
    // A sample that is not finite is refused by name.
    MetricSamples a, b;
    for (size_t k = 0; k < kMetricCount; ++k) a.values[k] = b.values[k] = {1.0, 2.0, 3.0};
    b.values[size_t(Metric::Jerk)][1] = std::numeric_limits<double>::infinity();
    try {
        metric_distances(a, b, PdfOptions{});
        ADD_FAILURE() << "an infinite sample was taken";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(metric_name(Metric::Jerk)), std::string::npos) << e.what();
    }
}

TEST(EvalPdf, ZScoringMakesTheDistanceBlindToShiftAndScale) {
    std::mt19937 rng(3);
    std::gamma_distribution<double> g(2.0, 1.0);
    MetricSamples a, b, c;
    for (size_t k = 0; k < kMetricCount; ++k)
        for (int i = 0; i < 5000; ++i) {
            const double x = g(rng);
            a.values[k].push_back(x);
            b.values[k].push_back(3.0 * x + 7.0);             // same shape
            c.values[k].push_back(std::normal_distribution<double>(0, 1)(rng));  // another shape
        }
    const auto same = metric_distances(a, b, PdfOptions{});
    const auto other = metric_distances(a, c, PdfOptions{});
    for (size_t k = 0; k < kMetricCount; ++k) {
        EXPECT_LT(same[k], 1e-9);
        EXPECT_GT(other[k], 0.1);
    }
    // Equal weights, p1 = 0, p2 = 1: E = 1 - mean of the distances.
    EXPECT_DOUBLE_EQ(score(same, ScoreWeights{}), 1.0 - [&] { double s = 0; for (double e : same) s += e / 7; return s; }());
    EXPECT_LT(score(other, ScoreWeights{}), score(same, ScoreWeights{}));
    // Deterministic to the bit.
    const auto again = metric_distances(a, c, PdfOptions{});
    EXPECT_EQ(0, std::memcmp(again.data(), other.data(), sizeof(other)));
}

TEST(EvalPdf, EmptyMetricGetsTheWorstDistanceAndBadOptionsAreRefused) {
    MetricSamples a, b;
    a[Metric::Speed] = {1, 2, 3};
    PdfOptions o;
    const auto e = metric_distances(a, b, o);
    EXPECT_DOUBLE_EQ(e[0], 2.0 * o.bins / (2 * o.half_width));
    o.bins = 0;
    EXPECT_THROW(metric_distances(a, a, o), Error);
    b[Metric::Speed] = {1, NAN};
    EXPECT_THROW(metric_distances(a, b, PdfOptions{}), Error);
    ScoreWeights w;
    w.p2[3] = 0;
    EXPECT_THROW(score(e, w), Error);
}

TEST(EvalEntropyWeights, MatchTheHandComputedEquation4) {
    // m = 3 models, n = 2 terms.  Column 0: 0, 1, 2 -> x' = 0, .5, 1 -> r = 1, .5, 0
    // -> g = 2/3, 1/3, 0.  Column 1 equal: no information, weight 0.
    const std::vector<double> x = {0, 5, 1, 5, 2, 5};
    const auto w = entropy_weights(x, 3, 2);
    const double e0 = -(2.0 / 3 * std::log(2.0 / 3) + 1.0 / 3 * std::log(1.0 / 3)) / std::log(3.0);
    EXPECT_NEAR(w.e[0], e0, 1e-12);
    EXPECT_DOUBLE_EQ(w.e[1], 1.0);
    EXPECT_DOUBLE_EQ(w.w[0], 1.0);
    EXPECT_DOUBLE_EQ(w.w[1], 0.0);
    EXPECT_DOUBLE_EQ(w.p1[0], 0.0);
    EXPECT_DOUBLE_EQ(w.p2[0], 2.0);
    EXPECT_DOUBLE_EQ(w.p1[1], 5.0);
}

TEST(EvalEntropyWeights, SumToOneAndFavourTermsThatSeparateModels) {
    // Term 0 separates the models sharply (one good, the rest bad); term 1
    // spreads them evenly; term 2 barely.
    const std::vector<double> x = {0.0, 0.0, 0.50,   //
                                   1.0, 0.5, 0.51,   //
                                   1.0, 1.0, 0.52,   //
                                   1.0, 0.7, 0.49};
    const auto w = entropy_weights(x, 4, 3);
    double sum = 0;
    for (double v : w.w) {
        sum += v;
        EXPECT_GE(v, 0.0);
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    EXPECT_GT(w.w[0], w.w[1]);  // lower entropy, more weight
    EXPECT_THROW(entropy_weights(x, 1, 12), Error);
    EXPECT_THROW(entropy_weights(x, 4, 2), Error);
    EXPECT_THROW(entropy_weights({0, 1, NAN, 2}, 2, 2), Error);
    // No column informative: equal weights.
    const auto flat = entropy_weights({1, 2, 1, 2}, 2, 2);
    EXPECT_DOUBLE_EQ(flat.w[0], 0.5);
}

TEST(EvalMetrics, MosquitoTracksGiveThePublishedSpeedRange) {
    const std::filesystem::path csv =
        std::filesystem::path(SWARMCL_SOURCE_DIR) / ".." / "shared" / "data" / "anopheles-coluzzii-swarm.csv";
    if (!std::filesystem::exists(csv)) GTEST_SKIP() << "no ../shared/data (the real tracks are not in the repository)";
    TrackLoadOptions o;
    o.columns = {"id", "datetime", "x_cm", "y_cm", "z_cm"};
    o.unit_scale = 0.01;
    const auto set = load_tracks_csv(csv.string(), o);
    const auto m = track_metrics(set);
    auto speeds = m[Metric::Speed];
    ASSERT_GT(speeds.size(), 10000u);
    std::sort(speeds.begin(), speeds.end());
    // The data README: median speed 0.55 m/s (the recorder's own scalar).
    EXPECT_NEAR(speeds[speeds.size() / 2], 0.55, 0.15);
    // On average 3.3 insects in view: plenty of d samples, each positive.
    EXPECT_GT(m[Metric::NearestDistance].size(), 5000u);
    for (double d : m[Metric::NearestDistance]) ASSERT_GT(d, 0.0);
}

TEST(EvalTimeWindow, HalvesSplitTheSamplesByTimeAtTheMedianSampleTime) {
    // Uneven in time like the mosquito recording: one track early, three late.
    TrackSet set;
    set.frame_time = 0.01;
    set.tracks.push_back(line_track("early", 0.0, 40, 0.01, {0, 0, 0}, {1, 0, 0}));
    for (int i = 0; i < 3; ++i)
        set.tracks.push_back(line_track("late" + std::to_string(i), 100.0, 40, 0.01, {0, 0, double(i)}, {1, 0, 0}));
    const auto first = time_window(set, 0.0, 0.5), second = time_window(set, 0.5, 1.0);
    auto count = [](const TrackSet& s) {
        size_t n = 0;
        for (const auto& t : s.tracks) n += t.t.size();
        return n;
    };
    EXPECT_EQ(count(first) + count(second), 160u);
    // The 80th of the 160 sample times is the late tracks' 14th frame (three
    // samples share each late time): the cut is there, inside the late
    // tracks (a cut at half the span would leave the first half 40 samples).
    EXPECT_EQ(count(first), 40u + 3 * 13);
    for (const auto& t : first.tracks)
        for (double x : t.t) EXPECT_LT(x, second.tracks.front().t.front());
    EXPECT_EQ(count(time_window(set, 0.0, 1.0)), 160u);
    EXPECT_THROW(time_window(set, 0.5, 0.5), Error);
    EXPECT_THROW(time_window(set, -0.1, 0.5), Error);
    EXPECT_THROW(time_window(set, 0.0, NAN), Error);
}

// ---- physical scale and robust standardisation (issue 26, item 3) ----------

TEST(EvalWasserstein, IsTheShiftBetweenShiftedSetsAndSeesScaleThatZScoresDoNot) {
    std::mt19937 rng(11);
    std::normal_distribution<double> g(0.5, 0.1);
    std::vector<double> a(4000);
    for (double& x : a) x = g(rng);
    std::vector<double> shifted = a, ten = a;
    for (double& x : shifted) x += 0.25;
    for (double& x : ten) x *= 10.0;
    // Same set: 0; a shift by c: exactly c; a set ten times faster: 9 mean speeds.
    EXPECT_DOUBLE_EQ(wasserstein1(a, a), 0.0);
    EXPECT_NEAR(wasserstein1(a, shifted), 0.25, 1e-12);
    double mean = 0.0;
    for (double x : a) mean += x / double(a.size());
    EXPECT_NEAR(wasserstein1(a, ten), 9.0 * mean, 1e-9);
    // ... while the z-scored distance cannot tell a from ten times a.
    MetricSamples ra, rt;
    ra[Metric::Speed] = a;
    rt[Metric::Speed] = ten;
    EXPECT_LT(metric_distances(ra, rt, PdfOptions{})[size_t(Metric::Speed)], 1e-9);
    // Unequal sizes: W1 of {0} and {0, 1} is 1/2.
    EXPECT_DOUBLE_EQ(wasserstein1({0.0}, {0.0, 1.0}), 0.5);
    EXPECT_THROW(wasserstein1({}, a), Error);
    EXPECT_THROW(wasserstein1(a, {1.0, NAN}), Error);
}

TEST(EvalRobust, MedianAndMadMatchHandValues) {
    EXPECT_DOUBLE_EQ(median_of({3, 1, 2}), 2.0);
    EXPECT_DOUBLE_EQ(median_of({4, 1, 3, 2}), 2.5);
    // |x - 2.5| = 1.5, 0.5, 0.5, 1.5, 97.5: median 1.5.
    EXPECT_DOUBLE_EQ(mad_of({1, 2, 3, 4, 100}, 2.5), 1.5);
    const Moments r = location_scale({1, 2, 3, 4, 100}, Standardise::MedianMad);
    EXPECT_DOUBLE_EQ(r.mean, 3.0);
    EXPECT_DOUBLE_EQ(r.sigma, kMadToSigma * 1.0);
    EXPECT_EQ(r.count, 5u);
}

TEST(EvalRobust, AFewGlitchesMoveTheZScoredDistanceButNotTheRobustOne) {
    // One recording and the same with 1% of its samples replaced by tracking
    // glitches 30σ out: σ grows about threefold, which squeezes the z-scored
    // PDF; the median and MAD barely move.  (E_φ of a whole density against
    // a disjoint one is 2M/(u2-u1) = 12.5; 1% of the mass moved is 0.125.)
    std::mt19937 rng(5);
    std::normal_distribution<double> g(2.0, 0.5);
    MetricSamples clean, glitched;
    for (int i = 0; i < 20000; ++i) {
        const double x = g(rng);
        clean[Metric::Acceleration].push_back(x);
        glitched[Metric::Acceleration].push_back(i % 100 == 0 ? 2.0 + 30.0 * 0.5 : x);
    }
    PdfOptions robust;
    robust.standardise = Standardise::MedianMad;
    const size_t k = size_t(Metric::Acceleration);
    const double plain = metric_distances(clean, glitched, PdfOptions{})[k];
    const double rob = metric_distances(clean, glitched, robust)[k];
    EXPECT_GT(plain, 4.0) << "the glitches should squeeze the z-scored PDF";
    EXPECT_LT(rob, 0.4) << "the robust PDF should move by about the glitches' mass";
    PdfOptions bad;
    bad.standardise = Standardise(7);
    EXPECT_THROW(metric_distances(clean, glitched, bad), Error);
}

// A run that blew up: points with NaN or infinite coordinates have no
// nearest neighbour (d is NaN) and are no one's; the finite points' d is
// the brute force over the finite points alone; the track path agrees and
// nothing crashes (the sweep sorts coordinates, the kd-tree splits on them).
TEST(EvalMetrics, NonFinitePositionsGiveNaNDistancesAndNoCrash) {
    for (const size_t agents : {size_t(20), size_t(300), size_t(2500)}) {  // brute-force size, sweep, kd-tree
        std::mt19937 rng(11);
        std::uniform_real_distribution<float> u(-1.f, 1.f);
        const size_t frames = 4;
        std::vector<float> xyz(frames * agents * 3);
        for (float& v : xyz) v = u(rng);
        const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
        xyz[3 * (1 * agents + 2) + 1] = nan;           // frame 1: one agent's y
        xyz[3 * (2 * agents + 5) + 0] = inf;           // frame 2: one at infinity
        for (size_t i = 0; i + 1 < agents; ++i)        // frame 3: all but the last
            xyz[3 * (3 * agents + i) + 2] = nan;
        const double dt = 0.1;
        const auto m = frame_metrics(xyz.data(), frames, agents, dt);
        const auto& d = m[Metric::NearestDistance];
        ASSERT_EQ(d.size(), frames * agents);
        auto finite_at = [&](size_t f, size_t i) {
            const float* q = &xyz[3 * (f * agents + i)];
            return std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]);
        };
        for (size_t f = 0; f < frames; ++f)
            for (size_t i = 0; i < agents; ++i) {
                const float* a = &xyz[3 * (f * agents + i)];
                double best = std::numeric_limits<double>::infinity();
                for (size_t j = 0; j < agents; ++j) {
                    if (j == i || !finite_at(f, j) || !finite_at(f, i)) continue;
                    const float* b = &xyz[3 * (f * agents + j)];
                    double s = 0;
                    for (int c = 0; c < 3; ++c) s += (double(b[c]) - a[c]) * (double(b[c]) - a[c]);
                    best = std::min(best, s);
                }
                if (std::isinf(best)) EXPECT_TRUE(std::isnan(d[f * agents + i])) << agents << " " << f << " " << i;
                else EXPECT_NEAR(d[f * agents + i], std::sqrt(best), 1e-12) << agents << " " << f << " " << i;
            }
        expect_same_samples(m, track_metrics(frames_as_tracks(xyz, frames, agents, dt)));
    }
}
