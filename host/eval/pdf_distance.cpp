#include "eval/pdf_distance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"

namespace swarmcl {

Moments moments_of(const std::vector<double>& samples) {
    Moments m;
    m.count = samples.size();
    if (samples.empty()) return m;
    double sum = 0.0;
    for (double x : samples) sum += x;
    m.mean = sum / double(samples.size());
    double ss = 0.0;
    for (double x : samples) ss += (x - m.mean) * (x - m.mean);
    m.sigma = std::sqrt(ss / double(samples.size()));
    return m;
}

double median_of(std::vector<double> v) {
    if (v.empty()) return 0.0;
    const size_t h = v.size() / 2;
    std::nth_element(v.begin(), v.begin() + long(h), v.end());
    const double upper = v[h];
    if (v.size() % 2 == 1) return upper;
    const double lower = *std::max_element(v.begin(), v.begin() + long(h));
    return lower + (upper - lower) / 2.0;
}

double mad_of(const std::vector<double>& samples, double median) {
    std::vector<double> d(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) d[i] = std::abs(samples[i] - median);
    return median_of(std::move(d));
}

Moments location_scale(const std::vector<double>& samples, Standardise how) {
    if (how == Standardise::MeanSigma) return moments_of(samples);
    Moments m;
    m.count = samples.size();
    m.mean = median_of(samples);
    m.sigma = kMadToSigma * mad_of(samples, m.mean);
    return m;
}

static void check(const PdfOptions& o) {
    require(o.bins >= 1 && o.bins <= (1u << 20), "pdf: bins must be in 1..1048576");
    require(std::isfinite(o.half_width) && o.half_width > 0.0, "pdf: half_width must be finite and > 0");
    require(o.standardise == Standardise::MeanSigma || o.standardise == Standardise::MedianMad,
            "pdf: standardise must be 0 (mean and sigma) or 1 (median and MAD)");
}

namespace {

// Whether every sample is finite, without a branch a sample (vectorises).
bool all_finite(const std::vector<double>& v) {
    bool ok = true;
    for (double x : v) ok &= std::fabs(x) <= std::numeric_limits<double>::max();
    return ok;
}

// The bin of each sample of x[0, n) (Step 3), with discrete_pdf's arithmetic:
// z = (x - mean) / sigma, or 0 where sigma is not > 0, and
// floor((z - u1) / (u2 - u1) M) clamped to [0, M - 1].  Clamping first and
// truncating after gives the same bin (both are the identity on [0, M - 1],
// and below 0 or above M - 1 both end in the end bin) without floor(), so the
// loop vectorises; the AVX2 clone takes four samples a step (distances() of a
// fit's world 2x faster: bench/results/eval/pdf_bins_ab.json).
#if defined(__x86_64__) && defined(__GNUC__) && defined(__ELF__)
__attribute__((target_clones("avx2", "default")))
#endif
void bins_of(const double* x, size_t n, double mean, double sigma, double u1, double u2, uint32_t M, int32_t* bin) {
    const double top = double(M - 1);
    const bool scaled = sigma > 0.0;
    for (size_t i = 0; i < n; ++i) {
        const double z = scaled ? (x[i] - mean) / sigma : 0.0;
        double b = (z - u1) / (u2 - u1) * M;
        b = b > 0.0 ? b : 0.0;  // NaN never reaches here
        b = b < top ? b : top;
        bin[i] = int32_t(b);
    }
}

}  // namespace

std::vector<double> discrete_pdf(const std::vector<double>& samples, const Moments& m, const PdfOptions& options) {
    check(options);
    const uint32_t M = options.bins;
    const double u1 = -options.half_width, u2 = options.half_width;
    // Four tallies, summed after: consecutive samples (one insect's frames)
    // often share a bin, and one tally would wait on its own last store.
    constexpr size_t kTallies = 4, kBlock = 1024;
    std::vector<uint64_t> counts(kTallies * M, 0);
    int32_t bin[kBlock];
    for (size_t at = 0; at < samples.size(); at += kBlock) {
        const size_t len = std::min(kBlock, samples.size() - at);
        bins_of(samples.data() + at, len, m.mean, m.sigma, u1, u2, M, bin);
        size_t i = 0;
        for (; i + kTallies <= len; i += kTallies)
            for (size_t t = 0; t < kTallies; ++t) ++counts[t * M + size_t(bin[i + t])];
        for (; i < len; ++i) ++counts[size_t(bin[i])];
    }
    std::vector<double> q(M, 0.0);
    if (samples.empty()) return q;
    const double s = double(samples.size());
    for (uint32_t i = 0; i < M; ++i) {
        uint64_t c = 0;
        for (size_t t = 0; t < kTallies; ++t) c += counts[t * M + i];
        q[i] = double(c) * M / (s * (u2 - u1));
    }
    return q;
}

double pdf_l1(const std::vector<double>& q_real, const std::vector<double>& q_sim) {
    require(q_real.size() == q_sim.size(), "pdf: the two densities have different bin counts");
    double e = 0.0;
    for (size_t i = 0; i < q_real.size(); ++i) e += std::abs(q_real[i] - q_sim[i]);
    return e;
}

std::array<double, kMetricCount> metric_distances(const MetricSamples& real, const MetricSamples& sim,
                                                  const PdfOptions& options) {
    check(options);
    std::array<double, kMetricCount> e{};
    const double worst = 2.0 * options.bins / (2.0 * options.half_width);
    for (size_t k = 0; k < kMetricCount; ++k) {
        const auto& r = real.values[k];
        const auto& s = sim.values[k];
        for (const auto* set : {&r, &s})
            if (!all_finite(*set))
                fail(Status::InvalidArgument, std::string("pdf: a sample of ") + metric_name(Metric(k)) + " is not finite");
        if (r.empty() || s.empty()) {
            e[k] = worst;
            continue;
        }
        e[k] = pdf_l1(discrete_pdf(r, location_scale(r, options.standardise), options),
                      discrete_pdf(s, location_scale(s, options.standardise), options));
    }
    return e;
}

ScoreWeights::ScoreWeights() {
    w.fill(1.0 / double(kMetricCount));
    p1.fill(0.0);
    p2.fill(1.0);
}

double score(const std::array<double, kMetricCount>& distances, const ScoreWeights& weights) {
    double sum = 0.0;
    for (size_t k = 0; k < kMetricCount; ++k) {
        require(std::isfinite(weights.p2[k]) && weights.p2[k] > 0.0, "score: every p2 must be > 0");
        sum += weights.w[k] * (distances[k] - weights.p1[k]) / weights.p2[k];
    }
    return 1.0 - sum;
}

double wasserstein1(const std::vector<double>& real, const std::vector<double>& sim) {
    require(!real.empty() && !sim.empty(), "wasserstein: a side has no samples");
    std::vector<double> a = real, b = sim;
    for (const auto* v : {&a, &b})
        require(all_finite(*v), "wasserstein: a sample is not finite");
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    // Sweep the merged values: between consecutive ones both CDFs are flat.
    const double na = double(a.size()), nb = double(b.size());
    size_t i = 0, j = 0;
    double w = 0.0, x = std::min(a[0], b[0]);
    while (i < a.size() || j < b.size()) {
        const double next = j == b.size() || (i < a.size() && a[i] <= b[j]) ? a[i] : b[j];
        w += std::abs(double(i) / na - double(j) / nb) * (next - x);
        x = next;
        while (i < a.size() && a[i] == x) ++i;
        while (j < b.size() && b[j] == x) ++j;
    }
    return w;
}

}  // namespace swarmcl
