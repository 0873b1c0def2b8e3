// The seven metrics (noise paper §3.2) kept as a fine histogram and exact
// moments per metric instead of every sample, so a distribution of any
// number of samples takes fixed memory: the streaming result of the device
// path (eval/swarm_metrics.hpp) and, from MetricSamples, of the host path;
// both are the same object, merged and turned into the discrete PDF of
// §3.1 (Step 2-3) alike.
//
// Fine bins: signed and log-spaced, keyed by a float's bits, the same
// integer function on the host and in kernels/metrics.cl: the exponent and
// the top kFineMantissaBits mantissa bits of |x| (bins of relative width at
// most 2^-9 ≈ 0.2%) for |x| in [2^-30, 2^30); one bin below (|x| < 2^-30,
// zero included), one for x <= -2^30 and x >= 2^30 each, one for NaN.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "eval/metrics.hpp"
#include "eval/pdf_distance.hpp"

namespace swarmcl {

namespace fine_bins {
constexpr uint32_t kMantissaBits = 9;                  // bins per octave: 2^9
constexpr uint32_t kShift = 23 - kMantissaBits;        // float bits dropped
constexpr int kMinExponent = -30, kMaxExponent = 30;   // |x| in [2^-30, 2^30)
constexpr uint32_t kLowKey = uint32_t(127 + kMinExponent) << kMantissaBits;
constexpr uint32_t kSide = uint32_t(kMaxExponent - kMinExponent) << kMantissaBits;  // bins per sign
constexpr uint32_t kNegativeOverflow = 0;      // x <= -2^30, -inf
constexpr uint32_t kZero = kSide + 1;          // |x| < 2^-30
constexpr uint32_t kPositiveOverflow = 2 * kSide + 2;  // x >= 2^30, +inf
constexpr uint32_t kNaN = 2 * kSide + 3;
constexpr uint32_t kCount = 2 * kSide + 4;     // bins per metric

// The bin of x (bins increase with x; kNaN for NaN).
uint32_t bin_of(float x);
// A value standing for the bin: the midpoint of its edges (0 for kZero,
// ±2^30 for the overflow bins, NaN for kNaN).
double bin_value(uint32_t bin);
// The bin's value range [lo, hi) (lo = hi = bin_value() for the zero and
// overflow bins, whose samples are taken as points).
void bin_edges(uint32_t bin, double& lo, double& hi);
}  // namespace fine_bins

// Count, mean and M2 = Σ(x - mean)² of the finite samples; merged with
// Chan et al.'s pairwise update in double, in the order merges are made.
struct RawMoments {
    uint64_t count = 0;
    double mean = 0.0;
    double m2 = 0.0;
    void merge(const RawMoments& other);
};

class MetricAccumulator {
public:
    MetricAccumulator();

    // Every sample of every metric (values rounded to float for binning:
    // the device computes in float).  The moments use the double values.
    void add(const MetricSamples& samples);
    // Another accumulator's counts and moments, after this one's.
    void merge(const MetricAccumulator& other);

    // Mean and σ (population) of the finite samples.
    Moments moments(Metric m) const;
    // The median and the (unscaled) median absolute deviation of the finite
    // samples, from the fine bins, each bin's count spread uniformly over its
    // range (within a bin's relative width, 0.2%, of the samples' own); 0
    // for no samples.
    double median(Metric m) const;
    double mad(Metric m) const;
    // The centre and scale of Step 2 under `how` (pdf_distance.hpp).
    Moments location_scale(Metric m, Standardise how) const;
    // All samples counted, non-finite ones included.
    uint64_t count(Metric m) const;
    // Samples that were NaN or ±inf.
    uint64_t nonfinite_count(Metric m) const;

    // Step 2-3 of §3.1 from the fine bins: each fine bin's count spread
    // uniformly over its z-range (z from moments(m)) into the M z-bins, tails
    // into the end bins (as discrete_pdf() of the raw samples).  No samples: all zeros.  Any
    // non-finite sample: Error(InvalidArgument) naming the metric.
    std::vector<double> discrete_pdf(Metric m, const PdfOptions& options) const;

    // Wasserstein-1 between this accumulator's samples of m and other's, in
    // the metric's unit (pdf_distance.hpp, wasserstein1), from the fine bins
    // as piecewise-uniform densities.  Error(InvalidArgument) naming the
    // metric when a side has no samples or one is not finite.
    double wasserstein1(Metric m, const MetricAccumulator& other) const;

    // Raw state, for tests and serialisation: the fine_bins::kCount counts of
    // a metric, and its moments; add_raw() merges such state in (counts may
    // be null: moments only).
    const std::vector<uint64_t>& histogram(Metric m) const { return bins_[size_t(m)]; }
    const RawMoments& raw_moments(Metric m) const { return moments_[size_t(m)]; }
    void add_raw(Metric m, const uint64_t* counts, const RawMoments& moments);

private:
    // Samples of m at or below x (piecewise linear within a bin).
    double cdf_count(Metric m, const std::vector<double>& prefix, double x) const;
    std::vector<double> prefix_counts(Metric m) const;  // [i]: samples in bins below i
    void require_finite(Metric m, const char* what) const;

    std::array<std::vector<uint64_t>, kMetricCount> bins_;
    std::array<RawMoments, kMetricCount> moments_;
};

}  // namespace swarmcl
