// The evaluation through the C API: metric sets from tracks and frames, time
// windows, PDFs, distances, scores, entropy weights, and their errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstddef>
#include <fstream>
#include <numeric>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "c_enum_callers.h"
#include "data/tracks.hpp"
#include "eval/metric_table.hpp"
#include "eval/metrics.hpp"
#include "eval/pdf_distance.hpp"
#include "swarmcl/swarmcl.h"

namespace {

// Synthetic tracks as C arrays (swcl_metrics_from_tracks's layout).
struct TrackArrays {
    std::vector<uint32_t> counts;
    std::vector<double> t;
    std::vector<float> xyz;
};

TrackArrays arrays_of(const swarmcl::TrackSet& set) {
    TrackArrays a;
    for (const auto& s : set.tracks) {
        a.counts.push_back(uint32_t(s.t.size()));
        for (size_t k = 0; k < s.t.size(); ++k) {
            a.t.push_back(s.t[k]);
            for (int c = 0; c < 3; ++c) a.xyz.push_back(float(s.p[k][c]));
        }
    }
    return a;
}

swcl_dataset_desc desc_for(double frame_time) {
    swcl_dataset_desc d = swcl_dataset_desc_default();
    d.frame_time = frame_time;
    return d;
}

}  // namespace

// swcl_metric (a stable ABI) is the metric table (eval/metric_table.hpp):
// swarmcl.h's enumerators, read from the header as a binding reads them, are
// SWCL_METRIC_<NAME> = the row's index for every row and nothing else;
// swcl_metric_name gives the rows' names; the kernel defines name every row.
TEST(EvalCapi, TheHeadersMetricEnumIsTheMetricTable) {
    std::ifstream in(std::string(SWARMCL_SOURCE_DIR) + "/capi/include/swarmcl/swarmcl.h");
    ASSERT_TRUE(in.good());
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string h = ss.str();
    const std::regex enumerator(R"(\b(SWCL_METRIC_\w+)\s*=\s*(\w+))");
    std::vector<std::pair<std::string, std::string>> found;
    for (auto it = std::sregex_iterator(h.begin(), h.end(), enumerator); it != std::sregex_iterator(); ++it)
        found.emplace_back((*it)[1], (*it)[2]);
    std::vector<std::pair<std::string, std::string>> want;
    for (size_t k = 0; k < swarmcl::kMetricCount; ++k) {
        std::string upper = swarmcl::kMetrics[k].name;
        for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
        want.emplace_back("SWCL_METRIC_" + upper, std::to_string(k));
        EXPECT_STREQ(swcl_metric_name(swcl_metric(k)), swarmcl::kMetrics[k].name);
        EXPECT_STREQ(swarmcl::metric_name(swarmcl::Metric(k)), swarmcl::kMetrics[k].name);
        EXPECT_NE(swarmcl::metric_kernel_defines().find(" -DM_" + std::string(swarmcl::kMetrics[k].kernel) + "=" +
                                                        std::to_string(k)),
                  std::string::npos);
    }
    want.emplace_back("SWCL_METRIC_COUNT", std::to_string(swarmcl::kMetricCount));
    want.emplace_back("SWCL_METRIC_MAX_ENUM", "0x7FFFFFFF");
    EXPECT_EQ(found, want);
    EXPECT_EQ(swcl_metric_name(SWCL_METRIC_COUNT), nullptr);
    EXPECT_EQ(swcl_metric_name(SWCL_METRIC_MAX_ENUM), nullptr);
    // -1 is a value only a C caller can pass (C++ cannot without undefined behaviour).
    EXPECT_EQ(c_metric_name_of(-1), nullptr);
    EXPECT_EQ(c_metric_name_of(INT32_MIN), nullptr);
    EXPECT_STREQ(swarmcl::metric_name(swarmcl::Metric(99)), "unknown");
}

TEST(EvalCapi, FramesGiveTheSameSamplesAsTheHostMetrics) {
    const size_t frames = 20, agents = 10;
    std::vector<float> xyz(frames * agents * 3);
    for (size_t f = 0; f < frames; ++f)
        for (size_t i = 0; i < agents; ++i) {
            const double a = 0.3 * f + i;
            xyz[3 * (f * agents + i) + 0] = float(std::cos(a) + 0.5 * i);
            xyz[3 * (f * agents + i) + 1] = float(std::sin(a));
            xyz[3 * (f * agents + i) + 2] = float(0.01 * f * i);
        }
    swcl_metrics m{};
    ASSERT_EQ(swcl_metrics_from_frames(xyz.data(), frames, agents, 0.05, &m), SWCL_OK) << swcl_last_error();
    const auto ref = swarmcl::frame_metrics(xyz.data(), frames, agents, 0.05);
    for (int k = 0; k < SWCL_METRIC_COUNT; ++k) {
        swcl_metric_info info;
        info.struct_size = sizeof(info);
        ASSERT_EQ(swcl_metrics_get_info(m, swcl_metric(k), &info), SWCL_OK);
        const auto mo = swarmcl::moments_of(ref.values[k]);
        EXPECT_EQ(info.count, mo.count);
        EXPECT_EQ(info.mean, mo.mean);
        EXPECT_EQ(info.sigma, mo.sigma);
        swcl_pdf_options o = swcl_pdf_options_default();
        std::vector<double> q(o.bins);
        ASSERT_EQ(swcl_metrics_pdf(m, swcl_metric(k), &o, q.data(), q.size()), SWCL_OK);
        EXPECT_EQ(q, swarmcl::discrete_pdf(ref.values[k], mo, swarmcl::PdfOptions{}));
    }
    double e[SWCL_METRIC_COUNT];
    ASSERT_EQ(swcl_metrics_distances(m, m, nullptr, e, SWCL_METRIC_COUNT), SWCL_OK);
    for (double v : e) EXPECT_EQ(v, 0.0);
    double s = 0;
    ASSERT_EQ(swcl_score(e, SWCL_METRIC_COUNT, nullptr, &s), SWCL_OK);
    EXPECT_EQ(s, 1.0);
    EXPECT_EQ(swcl_metrics_destroy(m), SWCL_OK);
    EXPECT_EQ(swcl_metrics_destroy(m), SWCL_ERROR_INVALID_HANDLE);
}

namespace {
// Frames of `agents` agents on circles of their own (phase `shift`).
std::vector<float> circling(size_t frames, size_t agents, double shift) {
    std::vector<float> xyz(frames * agents * 3);
    for (size_t f = 0; f < frames; ++f)
        for (size_t i = 0; i < agents; ++i) {
            const double a = 0.3 * f + i + shift;
            xyz[3 * (f * agents + i) + 0] = float(std::cos(a) * (1 + 0.1 * i) + 0.5 * i);
            xyz[3 * (f * agents + i) + 1] = float(std::sin(a) + shift);
            xyz[3 * (f * agents + i) + 2] = float(0.02 * f * i);
        }
    return xyz;
}
}  // namespace

// Pooled runs (issue 26): merged metrics hold the parts' samples one after
// the other (d and eta each part's own), so their PDFs are those of the
// concatenated samples; parts on another clock, no parts and a dead handle
// are refused with out untouched.
TEST(EvalCapi, MergedMetricsPoolThePartsSamples) {
    const auto a = circling(20, 10, 0.0), b = circling(15, 7, 2.0), c = circling(15, 7, 1.0);
    swcl_metrics ma{}, mb{}, mc{};
    ASSERT_EQ(swcl_metrics_from_frames(a.data(), 20, 10, 0.05, &ma), SWCL_OK);
    ASSERT_EQ(swcl_metrics_from_frames(b.data(), 15, 7, 0.05, &mb), SWCL_OK);
    ASSERT_EQ(swcl_metrics_from_frames(c.data(), 15, 7, 0.04, &mc), SWCL_OK);
    const swcl_metrics parts[2] = {ma, mb};
    swcl_metrics pooled{};
    ASSERT_EQ(swcl_metrics_merge(parts, 2, &pooled), SWCL_OK) << swcl_last_error();
    const auto ra = swarmcl::frame_metrics(a.data(), 20, 10, 0.05), rb = swarmcl::frame_metrics(b.data(), 15, 7, 0.05);
    for (int k = 0; k < SWCL_METRIC_COUNT; ++k) {
        std::vector<double> all = ra.values[k];
        all.insert(all.end(), rb.values[k].begin(), rb.values[k].end());
        ASSERT_GT(rb.values[k].size(), 0u) << k;
        swcl_metric_info info{sizeof(info)};
        ASSERT_EQ(swcl_metrics_get_info(pooled, swcl_metric(k), &info), SWCL_OK);
        const auto mo = swarmcl::moments_of(all);
        EXPECT_EQ(info.count, all.size()) << k;
        EXPECT_EQ(info.mean, mo.mean) << k;
        EXPECT_EQ(info.sigma, mo.sigma) << k;
        swcl_pdf_options o = swcl_pdf_options_default();
        std::vector<double> q(o.bins);
        ASSERT_EQ(swcl_metrics_pdf(pooled, swcl_metric(k), &o, q.data(), q.size()), SWCL_OK);
        EXPECT_EQ(q, swarmcl::discrete_pdf(all, mo, swarmcl::PdfOptions{})) << k;
    }
    double t = 0;
    ASSERT_EQ(swcl_metrics_frame_time(pooled, &t), SWCL_OK);
    EXPECT_EQ(t, 0.05);
    // One part alone is that part again.
    swcl_metrics one{};
    ASSERT_EQ(swcl_metrics_merge(&ma, 1, &one), SWCL_OK);
    double e[SWCL_METRIC_COUNT];
    ASSERT_EQ(swcl_metrics_distances(ma, one, nullptr, e, SWCL_METRIC_COUNT), SWCL_OK);
    for (double v : e) EXPECT_EQ(v, 0.0);
    // Bad input: out untouched, nothing made.
    swcl_metrics out{12345};
    const swcl_metrics other_clock[2] = {ma, mc};
    EXPECT_EQ(swcl_metrics_merge(other_clock, 2, &out), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("parts[1]"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_metrics_merge(nullptr, 2, &out), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_metrics_merge(parts, 0, &out), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_metrics_merge(parts, 2, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    const swcl_metrics dead[2] = {ma, swcl_metrics{999}};
    EXPECT_EQ(swcl_metrics_merge(dead, 2, &out), SWCL_ERROR_INVALID_HANDLE);
    EXPECT_EQ(out.id, 12345u);
    for (auto m : {ma, mb, mc, pooled, one}) EXPECT_EQ(swcl_metrics_destroy(m), SWCL_OK);
}

// One world's frames read in place from a swarm of worlds' frames
// (swcl_metrics_from_frames_strided) are the same samples as the world's
// frames packed; a stride below a frame's floats is refused.
TEST(EvalCapi, StridedFramesAreTheWorldsPackedFrames) {
    const size_t frames = 12, agents = 6, worlds = 3;
    std::vector<float> all(frames * worlds * agents * 3);
    for (size_t w = 0; w < worlds; ++w) {
        const auto one = circling(frames, agents, 0.7 * double(w));
        for (size_t f = 0; f < frames; ++f)
            std::copy_n(one.begin() + 3 * f * agents, 3 * agents, all.begin() + 3 * (f * worlds + w) * agents);
    }
    for (size_t w = 0; w < worlds; ++w) {
        const auto one = circling(frames, agents, 0.7 * double(w));
        swcl_metrics packed{}, strided{};
        ASSERT_EQ(swcl_metrics_from_frames(one.data(), frames, agents, 0.05, &packed), SWCL_OK);
        ASSERT_EQ(swcl_metrics_from_frames_strided(all.data() + 3 * w * agents, frames, agents, 3 * agents * worlds,
                                                   0.05, &strided),
                  SWCL_OK)
            << swcl_last_error();
        for (int k = 0; k < SWCL_METRIC_COUNT; ++k) {
            swcl_metric_info a{sizeof(a)}, b{sizeof(b)};
            ASSERT_EQ(swcl_metrics_get_info(packed, swcl_metric(k), &a), SWCL_OK);
            ASSERT_EQ(swcl_metrics_get_info(strided, swcl_metric(k), &b), SWCL_OK);
            EXPECT_EQ(a.count, b.count) << k;
            EXPECT_EQ(a.mean, b.mean) << k;
            EXPECT_EQ(a.sigma, b.sigma) << k;
            EXPECT_EQ(a.median, b.median) << k;
        }
        swcl_metrics_destroy(packed);
        swcl_metrics_destroy(strided);
    }
    swcl_metrics out{4242};
    EXPECT_EQ(swcl_metrics_from_frames_strided(all.data(), frames, agents, 3 * agents - 1, 0.05, &out),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("frame_stride"), std::string::npos);
    EXPECT_EQ(swcl_metrics_from_frames_strided(all.data(), frames, agents, 3 * agents, -1.0, &out),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(out.id, 4242u);
}

// Physical scale and robust standardisation (issue 26): the median, MAD and
// Wasserstein-1 of the C API are the host's on the same samples; an older
// caller's smaller structs are read and written as far as they reach.
TEST(EvalCapi, MedianMadWassersteinAndRobustPdfs) {
    const size_t frames = 30, agents = 12;
    std::vector<float> slow(frames * agents * 3), fast;
    for (size_t f = 0; f < frames; ++f)
        for (size_t i = 0; i < agents; ++i) {
            const double a = 0.2 * f + 0.7 * i;
            slow[3 * (f * agents + i) + 0] = float(std::cos(a) + 0.6 * i);
            slow[3 * (f * agents + i) + 1] = float(std::sin(a));
            slow[3 * (f * agents + i) + 2] = float(0.02 * f * (i % 3));
        }
    fast = slow;
    for (float& v : fast) v *= 2.0f;  // twice the size: twice the speeds and distances
    swcl_metrics a{}, b{};
    ASSERT_EQ(swcl_metrics_from_frames(slow.data(), frames, agents, 0.05, &a), SWCL_OK);
    ASSERT_EQ(swcl_metrics_from_frames(fast.data(), frames, agents, 0.05, &b), SWCL_OK);
    const auto ra = swarmcl::frame_metrics(slow.data(), frames, agents, 0.05);
    const auto rb = swarmcl::frame_metrics(fast.data(), frames, agents, 0.05);
    for (int k = 0; k < SWCL_METRIC_COUNT; ++k) {
        const auto& x = ra.values[k];
        swcl_metric_info info;
        info.struct_size = sizeof(info);
        ASSERT_EQ(swcl_metrics_get_info(a, swcl_metric(k), &info), SWCL_OK);
        const double med = swarmcl::median_of(x);
        EXPECT_EQ(info.median, med);
        EXPECT_EQ(info.mad, swarmcl::mad_of(x, med));
        double w = -1;
        ASSERT_EQ(swcl_metrics_wasserstein(a, b, swcl_metric(k), &w), SWCL_OK) << swcl_last_error();
        EXPECT_EQ(w, swarmcl::wasserstein1(x, rb.values[k]));
        swcl_pdf_options o = swcl_pdf_options_default();
        EXPECT_EQ(o.standardise, SWCL_STANDARDISE_MEAN_SIGMA);
        o.standardise = SWCL_STANDARDISE_MEDIAN_MAD;
        std::vector<double> q(o.bins);
        ASSERT_EQ(swcl_metrics_pdf(a, swcl_metric(k), &o, q.data(), q.size()), SWCL_OK);
        swarmcl::PdfOptions ho;
        ho.standardise = swarmcl::Standardise::MedianMad;
        EXPECT_EQ(q, swarmcl::discrete_pdf(x, swarmcl::location_scale(x, ho.standardise), ho));
    }
    // Speeds twice as large: W1 is the mean speed (m/s), the unit says so.
    double w = 0;
    ASSERT_EQ(swcl_metrics_wasserstein(a, b, SWCL_METRIC_SPEED, &w), SWCL_OK);
    EXPECT_NEAR(w, swarmcl::moments_of(ra.values[0]).mean, 1e-5 * w);
    EXPECT_STREQ(swcl_metric_unit(SWCL_METRIC_SPEED), "m/s");
    EXPECT_STREQ(swcl_metric_unit(SWCL_METRIC_NEAREST_DISTANCE), "m");
    EXPECT_EQ(swcl_metric_unit(swcl_metric(7)), nullptr);
    // An older caller: structs without the added fields.
    swcl_pdf_options old = swcl_pdf_options_default();
    old.struct_size = offsetof(swcl_pdf_options, standardise);
    old.standardise = swcl_standardise(99);  // beyond its struct: not read
    std::vector<double> q(old.bins);
    EXPECT_EQ(swcl_metrics_pdf(a, SWCL_METRIC_SPEED, &old, q.data(), q.size()), SWCL_OK);
    swcl_metric_info small;
    small.struct_size = offsetof(swcl_metric_info, median);
    small.median = -7;
    ASSERT_EQ(swcl_metrics_get_info(a, SWCL_METRIC_SPEED, &small), SWCL_OK);
    EXPECT_EQ(small.median, -7);  // not written
    // Bad input: a bad standardise, a metric with no samples (one agent: no
    // nearest distances), NULL out.
    swcl_pdf_options bad = swcl_pdf_options_default();
    bad.standardise = swcl_standardise(5);
    EXPECT_EQ(swcl_metrics_pdf(a, SWCL_METRIC_SPEED, &bad, q.data(), q.size()), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("standardise"), std::string::npos) << swcl_last_error();
    c_pdf_standardise(&bad, INT32_MIN);  // only C can pass a negative value
    EXPECT_EQ(swcl_metrics_pdf(a, SWCL_METRIC_SPEED, &bad, q.data(), q.size()), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("standardise (-2147483648)"), std::string::npos)
        << swcl_last_error();
    swcl_dataset_desc tracks = swcl_dataset_desc_default();
    c_dataset_time_format(&tracks, -1);
    size_t segments = 0, samples = 0;
    EXPECT_EQ(swcl_tracks_read_csv("no-such-file.csv", &tracks, 0.0, 0.0, nullptr, nullptr, 0, nullptr, nullptr, 0,
                                   &segments, &samples, nullptr),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("time_format (-1)"), std::string::npos) << swcl_last_error();
    swcl_metrics one{};
    ASSERT_EQ(swcl_metrics_from_frames(slow.data(), frames, 1, 0.05, &one), SWCL_OK);
    EXPECT_EQ(swcl_metrics_wasserstein(a, one, SWCL_METRIC_NEAREST_DISTANCE, &w), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("nearest_distance has no samples in sim"), std::string::npos)
        << swcl_last_error();
    EXPECT_EQ(swcl_metrics_wasserstein(a, b, SWCL_METRIC_SPEED, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_metrics_wasserstein(a, b, swcl_metric(9), &w), SWCL_ERROR_INVALID_ARGUMENT);
    for (swcl_metrics m : {a, b, one}) swcl_metrics_destroy(m);
}

// A CSV with ';' between its fields: read with desc.delimiter as the same
// tracks with ','; an older descriptor (no delimiter field) reads ','.
TEST(EvalCapi, TracksWithAnotherDelimiter) {
    const auto set = swarmcl::synthetic_tracks(4, 30, 0.01, 0.5f, 2);
    std::string comma = swarmcl::tracks_to_csv(set), semi = comma;
    std::replace(semi.begin(), semi.end(), ',', ';');
    const std::string dir = ::testing::TempDir();
    const std::string pc = dir + "/swcl_delim_comma.csv", ps = dir + "/swcl_delim_semi.csv";
    std::ofstream(pc) << comma;
    std::ofstream(ps) << semi;
    swcl_dataset_desc d = swcl_dataset_desc_default();
    EXPECT_EQ(d.delimiter, ',');
    swcl_metrics a{}, b{}, c{};
    ASSERT_EQ(swcl_metrics_from_csv(pc.c_str(), &d, 0, 1, &a), SWCL_OK) << swcl_last_error();
    d.delimiter = ';';
    ASSERT_EQ(swcl_metrics_from_csv(ps.c_str(), &d, 0, 1, &b), SWCL_OK) << swcl_last_error();
    double e[SWCL_METRIC_COUNT];
    ASSERT_EQ(swcl_metrics_distances(a, b, nullptr, e, SWCL_METRIC_COUNT), SWCL_OK);
    for (double v : e) EXPECT_EQ(v, 0.0);
    d.struct_size = offsetof(swcl_dataset_desc, delimiter);  // an older caller: ','
    EXPECT_EQ(swcl_metrics_from_csv(ps.c_str(), &d, 0, 1, &c), SWCL_ERROR_INVALID_ARGUMENT);  // no "id" column
    d = swcl_dataset_desc_default();
    d.delimiter = '\n';
    EXPECT_EQ(swcl_metrics_from_csv(ps.c_str(), &d, 0, 1, &c), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("delimiter"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(c.id, 0u);
    swcl_metrics_destroy(a);
    swcl_metrics_destroy(b);
    std::remove(pc.c_str());
    std::remove(ps.c_str());
}

// The tracks of a CSV as the metrics take them: sizes first, then the
// segments, which laid out again give the same metrics as the file (float
// positions: to float rounding); a capacity too small changes nothing.
TEST(EvalCapi, TracksReadFromACsvAreTheMetricsSamples) {
    const auto set = swarmcl::synthetic_tracks(5, 40, 0.01, 0.5f, 3);
    const std::string path = ::testing::TempDir() + "/swcl_read_tracks.csv";
    std::ofstream(path) << swarmcl::tracks_to_csv(set);
    size_t segments = 0, samples = 0;
    double frame_time = 0;
    ASSERT_EQ(swcl_tracks_read_csv(path.c_str(), nullptr, 0, 0.5, nullptr, nullptr, 0, nullptr, nullptr, 0, &segments,
                                   &samples, &frame_time), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(segments, 5u);
    EXPECT_GT(samples, 5u * 15);
    EXPECT_NEAR(frame_time, 0.01, 1e-9);
    std::vector<uint32_t> counts(segments, 7), insects(segments, 7);
    std::vector<double> t(samples, -1.0);
    std::vector<float> xyz(3 * samples);
    EXPECT_EQ(swcl_tracks_read_csv(path.c_str(), nullptr, 0, 0.5, counts.data(), insects.data(), segments, t.data(),
                                   xyz.data(), samples - 1, &segments, &samples, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("capacity too small"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(counts[0], 7u);
    EXPECT_EQ(t[0], -1.0);
    ASSERT_EQ(swcl_tracks_read_csv(path.c_str(), nullptr, 0, 0.5, counts.data(), insects.data(), segments, t.data(),
                                   xyz.data(), samples, &segments, &samples, nullptr), SWCL_OK) << swcl_last_error();
    EXPECT_EQ(std::accumulate(counts.begin(), counts.end(), size_t(0)), samples);
    for (uint32_t k = 0; k < segments; ++k) EXPECT_EQ(insects[k], k);
    swcl_dataset_desc d = swcl_dataset_desc_default();
    d.frame_time = frame_time;
    swcl_metrics again{}, file{};
    ASSERT_EQ(swcl_metrics_from_tracks(counts.data(), segments, t.data(), xyz.data(), &d, 0, 1, &again), SWCL_OK)
        << swcl_last_error();
    ASSERT_EQ(swcl_metrics_from_csv(path.c_str(), nullptr, 0, 0.5, &file), SWCL_OK);
    for (int m = 0; m < SWCL_METRIC_COUNT; ++m) {
        swcl_metric_info a{sizeof(a)}, b{sizeof(b)};
        ASSERT_EQ(swcl_metrics_get_info(again, swcl_metric(m), &a), SWCL_OK);
        ASSERT_EQ(swcl_metrics_get_info(file, swcl_metric(m), &b), SWCL_OK);
        EXPECT_EQ(a.count, b.count) << swcl_metric_name(swcl_metric(m));
        EXPECT_NEAR(a.mean, b.mean, 1e-3 * std::fabs(b.mean) + 1e-6) << swcl_metric_name(swcl_metric(m));
    }
    swcl_metrics_destroy(again);
    swcl_metrics_destroy(file);
    EXPECT_EQ(swcl_tracks_read_csv(path.c_str(), nullptr, 0, 1, counts.data(), nullptr, segments, t.data(),
                                   xyz.data(), samples, &segments, &samples, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_tracks_read_csv("/no/such/file.csv", nullptr, 0, 1, nullptr, nullptr, 0, nullptr, nullptr, 0,
                                   &segments, &samples, nullptr), SWCL_ERROR_IO);
    EXPECT_EQ(swcl_tracks_read_csv(path.c_str(), nullptr, 0, 1, nullptr, nullptr, 0, nullptr, nullptr, 0, nullptr,
                                   &samples, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    std::remove(path.c_str());
}

TEST(EvalCapi, HalvesOfARecordingSplitTheSamplesByTime) {
    const auto set = swarmcl::synthetic_tracks(6, 200, 0.01, 0.5f, 9);
    const auto a = arrays_of(set);
    const auto d = desc_for(0.01);
    swcl_metrics all{}, first{}, second{};
    ASSERT_EQ(swcl_metrics_from_tracks(a.counts.data(), a.counts.size(), a.t.data(), a.xyz.data(), &d, 0, 1, &all),
              SWCL_OK) << swcl_last_error();
    ASSERT_EQ(swcl_metrics_from_tracks(a.counts.data(), a.counts.size(), a.t.data(), a.xyz.data(), &d, 0, 0.5, &first),
              SWCL_OK);
    ASSERT_EQ(swcl_metrics_from_tracks(a.counts.data(), a.counts.size(), a.t.data(), a.xyz.data(), &d, 0.5, 1, &second),
              SWCL_OK);
    swcl_metric_info ia{sizeof(ia)}, i1{sizeof(i1)}, i2{sizeof(i2)};
    ASSERT_EQ(swcl_metrics_get_info(all, SWCL_METRIC_SPEED, &ia), SWCL_OK);
    ASSERT_EQ(swcl_metrics_get_info(first, SWCL_METRIC_SPEED, &i1), SWCL_OK);
    ASSERT_EQ(swcl_metrics_get_info(second, SWCL_METRIC_SPEED, &i2), SWCL_OK);
    // 6 tracks of 200 samples all at once: 199 speeds each; cut in two, one
    // speed per track is lost at the cut (the difference across it).
    EXPECT_EQ(ia.count, 6u * 199);
    EXPECT_EQ(i1.count + i2.count, 6u * 198);
    EXPECT_NEAR(double(i1.count), double(i2.count), 6.0);
    for (auto h : {all, first, second}) swcl_metrics_destroy(h);
}

TEST(EvalCapi, BadInputGetsAClearErrorAndNoHandle) {
    swcl_metrics m{};
    EXPECT_EQ(swcl_metrics_from_csv("/no/such/file.csv", nullptr, 0, 1, &m), SWCL_ERROR_IO);
    EXPECT_EQ(m.id, 0u);
    const float p[6] = {0, 0, 0, 1, 1, 1};
    EXPECT_EQ(swcl_metrics_from_frames(p, 1, 2, 0.0, &m), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("dt"), std::string::npos) << swcl_last_error();
    EXPECT_EQ(swcl_metrics_from_frames(p, 1, 2, 0.1, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    const auto set = swarmcl::synthetic_tracks(2, 20, 0.01, 0.5f, 1);
    const auto a = arrays_of(set);
    const auto d = desc_for(0.01);
    EXPECT_EQ(swcl_metrics_from_tracks(a.counts.data(), a.counts.size(), a.t.data(), a.xyz.data(), &d, 0.6, 0.4, &m),
              SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_NE(std::string(swcl_last_error()).find("from < to"), std::string::npos) << swcl_last_error();
    ASSERT_EQ(swcl_metrics_from_frames(p, 1, 2, 0.1, &m), SWCL_OK);
    double q[10];
    EXPECT_EQ(swcl_metrics_pdf(m, SWCL_METRIC_SPEED, nullptr, q, 10), SWCL_ERROR_INVALID_ARGUMENT);  // 50 bins
    EXPECT_EQ(swcl_metrics_pdf(m, swcl_metric(9), nullptr, q, 50), SWCL_ERROR_INVALID_ARGUMENT);
    double q50[50];
    EXPECT_EQ(c_metrics_pdf_of(m, -1, nullptr, q50, 50), SWCL_ERROR_INVALID_ARGUMENT);  // only C can pass -1
    EXPECT_NE(std::string(swcl_last_error()).find("not a swcl_metric"), std::string::npos) << swcl_last_error();
    swcl_pdf_options o = swcl_pdf_options_default();
    o.half_width = -1;
    double e[SWCL_METRIC_COUNT];
    EXPECT_EQ(swcl_metrics_distances(m, m, &o, e, SWCL_METRIC_COUNT), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_metrics_distances(m, swcl_metrics{12345}, nullptr, e, SWCL_METRIC_COUNT),
              SWCL_ERROR_INVALID_HANDLE);
    swcl_score_weights w = swcl_score_weights_default();
    w.p2[2] = 0;
    double s = 0;
    const double zeros[SWCL_METRIC_COUNT] = {};
    EXPECT_EQ(swcl_score(zeros, SWCL_METRIC_COUNT, &w, &s), SWCL_ERROR_INVALID_ARGUMENT);
    const double x[4] = {0, 1, 1, 0};
    double wout[2];
    EXPECT_EQ(swcl_entropy_weights(x, 1, 4, wout, nullptr, nullptr), SWCL_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ(swcl_entropy_weights(x, 2, 2, wout, nullptr, nullptr), SWCL_OK);
    EXPECT_NEAR(wout[0] + wout[1], 1.0, 1e-12);
    swcl_metrics_destroy(m);
}

// Streamed metrics of a running swarm against the host path on the same
// positions (read back at every sample).
TEST(EvalCapi, AttachedMetricsMatchTheFramesOfTheSameRun) {
    const std::string text = R"({"name": "attach", "seed": 5, "dt": 0.02, "steps": 30,
        "domain": {"min": [0, 0, 0], "max": [2, 2, 2]}, "interaction_radius": 0.2,
        "agents": {"count": 200, "initial": {"type": "uniform", "min": [0.5, 0.5, 0.5], "max": [1.5, 1.5, 1.5]}},
        "model": {"type": "field", "noise": {"type": "curl", "scale": 0.5, "gain": 0.4, "seed": 1, "domain_walls": true},
                  "goal": {"center": [1, 1, 1], "speed": 0.3}}})";
    swcl_scenario scn{};
    ASSERT_EQ(swcl_scenario_parse(text.c_str(), text.size(), &scn), SWCL_OK) << swcl_last_error();
    swcl_context_desc cd = swcl_context_desc_default();
    swcl_context ctx{};
    ASSERT_EQ(swcl_context_create(&cd, &ctx), SWCL_OK);
    swcl_swarm swarm{};
    ASSERT_EQ(swcl_scenario_create_swarm(scn, ctx, &swarm), SWCL_OK);
    swcl_metrics live{};
    ASSERT_EQ(swcl_metrics_attach(swarm, 0.04, &live), SWCL_OK) << swcl_last_error();
    const size_t n = 200, frames = 40;
    std::vector<float> xyz;
    for (size_t f = 0; f < frames; ++f) {
        if (f) ASSERT_EQ(swcl_swarm_step(swarm, 2), SWCL_OK);
        ASSERT_EQ(swcl_metrics_sample(live), SWCL_OK) << swcl_last_error();
        xyz.resize(xyz.size() + 3 * n);
        ASSERT_EQ(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_POSITION, xyz.data() + xyz.size() - 3 * n, n), SWCL_OK);
    }
    swcl_metrics host{};
    ASSERT_EQ(swcl_metrics_from_frames(xyz.data(), frames, n, 0.04, &host), SWCL_OK);
    // The swarm may go first: the metrics keep it alive.
    EXPECT_EQ(swcl_swarm_destroy(swarm), SWCL_OK);
    for (int k = 0; k < SWCL_METRIC_COUNT; ++k) {
        swcl_metric_info a{sizeof(a)}, b{sizeof(b)};
        ASSERT_EQ(swcl_metrics_get_info(live, swcl_metric(k), &a), SWCL_OK) << swcl_last_error();
        ASSERT_EQ(swcl_metrics_get_info(host, swcl_metric(k), &b), SWCL_OK);
        EXPECT_EQ(a.count, b.count) << k;
        EXPECT_NEAR(a.mean, b.mean, 1e-4 * std::max(std::abs(b.mean), b.sigma)) << k;
    }
    double e[SWCL_METRIC_COUNT];
    ASSERT_EQ(swcl_metrics_distances(live, host, nullptr, e, SWCL_METRIC_COUNT), SWCL_OK) << swcl_last_error();
    for (double v : e) EXPECT_LT(v, 0.05);
    double t = 0;
    ASSERT_EQ(swcl_metrics_frame_time(live, &t), SWCL_OK);
    EXPECT_EQ(t, 0.04);
    // Streamed and exact parts pool as fine histograms: every sample counted.
    const swcl_metrics both[2] = {live, host};
    swcl_metrics pooled{};
    ASSERT_EQ(swcl_metrics_merge(both, 2, &pooled), SWCL_OK) << swcl_last_error();
    for (int k = 0; k < SWCL_METRIC_COUNT; ++k) {
        swcl_metric_info a{sizeof(a)}, b{sizeof(b)}, p{sizeof(p)};
        ASSERT_EQ(swcl_metrics_get_info(live, swcl_metric(k), &a), SWCL_OK);
        ASSERT_EQ(swcl_metrics_get_info(host, swcl_metric(k), &b), SWCL_OK);
        ASSERT_EQ(swcl_metrics_get_info(pooled, swcl_metric(k), &p), SWCL_OK);
        EXPECT_EQ(p.count, a.count + b.count) << k;
        EXPECT_NEAR(p.mean, b.mean, 1e-4 * std::max(std::abs(b.mean), b.sigma)) << k;
    }
    swcl_metrics_destroy(pooled);
    EXPECT_EQ(swcl_metrics_sample(host), SWCL_ERROR_INVALID_ARGUMENT);
    EXPECT_EQ(swcl_metrics_attach(swcl_swarm{777}, 0.1, &host), SWCL_ERROR_INVALID_HANDLE);
    swcl_metrics_destroy(live);
    swcl_metrics_destroy(host);
    swcl_context_destroy(ctx);
    swcl_scenario_destroy(scn);
}
