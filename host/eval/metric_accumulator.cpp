#include "eval/metric_accumulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/error.hpp"

namespace swarmcl {

namespace fine_bins {

uint32_t bin_of(float x) {
    if (std::isnan(x)) return kNaN;
    uint32_t bits;
    const float a = std::fabs(x);
    std::memcpy(&bits, &a, sizeof bits);
    const uint32_t key = bits >> kShift;  // exponent and top mantissa bits: monotone in |x|
    if (key < kLowKey) return kZero;
    const uint32_t k = key - kLowKey;
    if (k >= kSide) return x < 0.0f ? kNegativeOverflow : kPositiveOverflow;
    return x < 0.0f ? kSide - k : kSide + 2 + k;
}

namespace {
float key_value(uint32_t key) {
    const uint32_t bits = key << kShift;
    float f;
    std::memcpy(&f, &bits, sizeof f);
    return f;
}
}  // namespace

void bin_edges(uint32_t bin, double& lo, double& hi) {
    if (bin == kZero || bin == kNegativeOverflow || bin == kPositiveOverflow || bin >= kNaN) {
        lo = hi = bin_value(bin);
        return;
    }
    const bool negative = bin < kZero;
    const uint32_t k = negative ? kSide - bin : bin - kSide - 2;
    const double a = key_value(kLowKey + k), b = key_value(kLowKey + k + 1);
    lo = negative ? -b : a;
    hi = negative ? -a : b;
}

double bin_value(uint32_t bin) {
    const double limit = std::ldexp(1.0, kMaxExponent);
    if (bin == kNaN || bin >= kCount) return std::numeric_limits<double>::quiet_NaN();
    if (bin == kZero) return 0.0;
    if (bin == kNegativeOverflow) return -limit;
    if (bin == kPositiveOverflow) return limit;
    const bool negative = bin < kZero;
    const uint32_t k = negative ? kSide - bin : bin - kSide - 2;
    const double mid = 0.5 * (double(key_value(kLowKey + k)) + double(key_value(kLowKey + k + 1)));
    return negative ? -mid : mid;
}

}  // namespace fine_bins

void RawMoments::merge(const RawMoments& o) {
    if (o.count == 0) return;
    if (count == 0) {
        *this = o;
        return;
    }
    const double na = double(count), nb = double(o.count), n = na + nb;
    const double delta = o.mean - mean;
    mean += delta * (nb / n);
    m2 += o.m2 + delta * delta * (na * nb / n);
    count += o.count;
}

MetricAccumulator::MetricAccumulator() {
    for (auto& b : bins_) b.assign(fine_bins::kCount, 0);
}

void MetricAccumulator::add(const MetricSamples& samples) {
    for (size_t k = 0; k < kMetricCount; ++k) {
        const auto& v = samples.values[k];
        // Two passes over the batch (as moments_of), then one merge.
        RawMoments batch;
        double sum = 0.0;
        for (double x : v) {
            ++bins_[k][fine_bins::bin_of(float(x))];
            if (std::isfinite(x)) {
                sum += x;
                ++batch.count;
            }
        }
        if (batch.count == 0) continue;
        batch.mean = sum / double(batch.count);
        for (double x : v)
            if (std::isfinite(x)) batch.m2 += (x - batch.mean) * (x - batch.mean);
        moments_[k].merge(batch);
    }
}

void MetricAccumulator::merge(const MetricAccumulator& other) {
    for (size_t k = 0; k < kMetricCount; ++k) add_raw(Metric(k), other.bins_[k].data(), other.moments_[k]);
}

void MetricAccumulator::add_raw(Metric m, const uint64_t* counts, const RawMoments& moments) {
    require(size_t(m) < kMetricCount, "metrics: unknown metric");
    if (counts) {
        auto& b = bins_[size_t(m)];
        for (uint32_t i = 0; i < fine_bins::kCount; ++i) b[i] += counts[i];
    }
    moments_[size_t(m)].merge(moments);
}

Moments MetricAccumulator::moments(Metric m) const {
    const RawMoments& r = moments_.at(size_t(m));
    Moments out;
    out.count = r.count;
    if (r.count == 0) return out;
    out.mean = r.mean;
    out.sigma = std::sqrt(std::max(0.0, r.m2) / double(r.count));
    return out;
}

uint64_t MetricAccumulator::count(Metric m) const {
    uint64_t c = 0;
    for (uint64_t x : bins_.at(size_t(m))) c += x;
    return c;
}

uint64_t MetricAccumulator::nonfinite_count(Metric m) const {
    // ±inf sit in the overflow bins with the finite values beyond ±2^30: the
    // moments' count tells them apart.
    return count(m) - moments_.at(size_t(m)).count;
}

void MetricAccumulator::require_finite(Metric m, const char* what) const {
    require(nonfinite_count(m) == 0, std::string(what) + ": a sample of " + metric_name(m) + " is not finite");
}

std::vector<double> MetricAccumulator::prefix_counts(Metric m) const {
    const auto& b = bins_.at(size_t(m));
    std::vector<double> prefix(fine_bins::kNaN + 1, 0.0);
    for (uint32_t i = 0; i < fine_bins::kNaN; ++i) prefix[i + 1] = prefix[i] + double(b[i]);
    return prefix;
}

double MetricAccumulator::cdf_count(Metric m, const std::vector<double>& prefix, double x) const {
    const uint32_t i = fine_bins::bin_of(float(x));
    if (i >= fine_bins::kNaN) return prefix[fine_bins::kNaN];
    double lo, hi;
    fine_bins::bin_edges(i, lo, hi);
    const double in = double(bins_[size_t(m)][i]);
    double f = hi > lo ? (x - lo) / (hi - lo) : (x >= lo ? 1.0 : 0.0);
    f = std::clamp(f, 0.0, 1.0);  // x rounded to float may sit in a neighbouring bin
    return prefix[i] + in * f;
}

double MetricAccumulator::median(Metric m) const {
    require_finite(m, "median");
    const std::vector<double> prefix = prefix_counts(m);
    const double total = prefix.back();
    if (total == 0.0) return 0.0;
    const double target = total / 2.0;
    const auto& b = bins_[size_t(m)];
    for (uint32_t i = 0; i < fine_bins::kNaN; ++i) {
        if (b[i] == 0 || prefix[i + 1] < target) continue;
        double lo, hi;
        fine_bins::bin_edges(i, lo, hi);
        return lo + (hi - lo) * (target - prefix[i]) / double(b[i]);
    }
    return fine_bins::bin_value(fine_bins::kPositiveOverflow);
}

double MetricAccumulator::mad(Metric m) const {
    const double med = median(m);
    const std::vector<double> prefix = prefix_counts(m);
    const double total = prefix.back();
    if (total == 0.0) return 0.0;
    // The smallest t with half of the samples within [med - t, med + t]:
    // the mass there grows with t, so bisect.
    double lo = 0.0, hi = 1.0;
    while (cdf_count(m, prefix, med + hi) - cdf_count(m, prefix, med - hi) < total / 2.0 && hi < 4.0 * (1u << 30))
        hi *= 2.0;
    for (int k = 0; k < 100 && hi - lo > 1e-12 * hi; ++k) {
        const double t = lo + (hi - lo) / 2.0;
        (cdf_count(m, prefix, med + t) - cdf_count(m, prefix, med - t) < total / 2.0 ? lo : hi) = t;
    }
    return hi;
}

Moments MetricAccumulator::location_scale(Metric m, Standardise how) const {
    if (how == Standardise::MeanSigma) return moments(m);
    Moments out;
    out.count = moments(m).count;
    if (out.count == 0) return out;
    out.mean = median(m);
    out.sigma = kMadToSigma * mad(m);
    return out;
}

double MetricAccumulator::wasserstein1(Metric m, const MetricAccumulator& other) const {
    for (const MetricAccumulator* a : {this, &other}) {
        a->require_finite(m, "wasserstein");
        require(a->moments(m).count > 0,
                std::string("wasserstein: ") + metric_name(m) + " has no samples on the " +
                    (a == this ? "first (real)" : "second (simulated)") + " side");
    }
    const std::vector<double> pa = prefix_counts(m), pb = other.prefix_counts(m);
    const double na = pa.back(), nb = pb.back();
    // Both CDFs are linear within each fine bin (the bins are shared), so
    // ∫|F_a - F_b| over a bin is that of a linear function: exact for the
    // piecewise-uniform densities.  Point bins (zero, overflow) only jump.
    double w = 0.0;
    for (uint32_t i = 0; i < fine_bins::kNaN; ++i) {
        double lo, hi;
        fine_bins::bin_edges(i, lo, hi);
        if (!(hi > lo)) continue;
        const double d0 = pa[i] / na - pb[i] / nb, d1 = pa[i + 1] / na - pb[i + 1] / nb;
        const double width = hi - lo;
        if ((d0 >= 0.0) == (d1 >= 0.0)) w += width * (std::abs(d0) + std::abs(d1)) / 2.0;
        else w += width * (d0 * d0 + d1 * d1) / (2.0 * (std::abs(d0) + std::abs(d1)));
    }
    return w;
}

std::vector<double> MetricAccumulator::discrete_pdf(Metric m, const PdfOptions& options) const {
    require(options.bins >= 1 && options.bins <= (1u << 20), "pdf: bins must be in 1..1048576");
    require(std::isfinite(options.half_width) && options.half_width > 0.0, "pdf: half_width must be finite and > 0");
    require(nonfinite_count(m) == 0, std::string("pdf: a sample of ") + metric_name(m) + " is not finite");
    const uint32_t M = options.bins;
    const double u1 = -options.half_width, u2 = options.half_width;
    const Moments mo = location_scale(m, options.standardise);
    std::vector<double> counts(M, 0.0);
    if (mo.count == 0) return counts;
    // Position on the z-bin axis (bin i is [i, i + 1)) of a value.
    auto at = [&](double x) {
        const double z = mo.sigma > 0.0 ? (x - mo.mean) / mo.sigma : 0.0;
        return (z - u1) / (u2 - u1) * M;
    };
    auto point = [&](double u, double c) { counts[size_t(std::clamp(std::floor(u), 0.0, double(M - 1)))] += c; };
    const auto& b = bins_[size_t(m)];
    for (uint32_t i = 0; i < fine_bins::kNaN; ++i) {
        if (b[i] == 0) continue;
        const double c = double(b[i]);
        double lo, hi;
        fine_bins::bin_edges(i, lo, hi);
        const double a = at(lo), e = at(hi), w = e - a;
        if (!(w > 0.0)) {  // a point (zero, overflow) or σ = 0
            point(at(fine_bins::bin_value(i)), c);
            continue;
        }
        // Spread uniformly over the fine bin's z-interval (so a fine bin
        // astride a z-bin edge is split, not moved whole); tails into the
        // end bins.
        if (a < 0.0) counts[0] += c * std::min(1.0, -a / w);
        if (e > M) counts[M - 1] += c * std::min(1.0, (e - M) / w);
        const double from = std::max(a, 0.0), to = std::min(e, double(M));
        for (double k = std::floor(from); k < to; k += 1.0)
            counts[size_t(k)] += c * (std::min(e, k + 1.0) - std::max(a, k)) / w;
    }
    const double s = double(mo.count);
    for (uint32_t i = 0; i < M; ++i) counts[i] *= M / (s * (u2 - u1));
    return counts;
}

}  // namespace swarmcl
