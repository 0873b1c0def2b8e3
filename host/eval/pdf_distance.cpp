#include "eval/pdf_distance.hpp"

#include <algorithm>
#include <cmath>

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

static void check(const PdfOptions& o) {
    require(o.bins >= 1 && o.bins <= (1u << 20), "pdf: bins must be in 1..1048576");
    require(std::isfinite(o.half_width) && o.half_width > 0.0, "pdf: half_width must be finite and > 0");
}

std::vector<double> discrete_pdf(const std::vector<double>& samples, const Moments& m, const PdfOptions& options) {
    check(options);
    const uint32_t M = options.bins;
    const double u1 = -options.half_width, u2 = options.half_width;
    std::vector<uint64_t> counts(M, 0);
    for (double x : samples) {
        const double z = m.sigma > 0.0 ? (x - m.mean) / m.sigma : 0.0;
        double b = std::floor((z - u1) / (u2 - u1) * M);
        b = std::clamp(b, 0.0, double(M - 1));  // tails into the end bins; NaN never reaches here
        ++counts[size_t(b)];
    }
    std::vector<double> q(M, 0.0);
    if (samples.empty()) return q;
    const double s = double(samples.size());
    for (uint32_t i = 0; i < M; ++i) q[i] = double(counts[i]) * M / (s * (u2 - u1));
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
            for (double x : *set)
                if (!std::isfinite(x))
                    fail(Status::InvalidArgument, std::string("pdf: a sample of ") + metric_name(Metric(k)) + " is not finite");
        if (r.empty() || s.empty()) {
            e[k] = worst;
            continue;
        }
        e[k] = pdf_l1(discrete_pdf(r, moments_of(r), options), discrete_pdf(s, moments_of(s), options));
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

}  // namespace swarmcl
