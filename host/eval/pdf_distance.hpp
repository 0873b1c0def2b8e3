// Distances between the distributions of a metric in real and simulated data
// (noise paper §3.1, Eq. 1-3): z-scored samples, discrete densities over a
// common interval, their L1 distance, its normalisation and the score.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "eval/metrics.hpp"

namespace swarmcl {

// Mean and standard deviation of a sample set, summed in sample order (two
// passes, double precision: the same samples give the same bits).  Also the
// centre and scale a data set is standardised with (Step 2): mean and σ, or,
// robustly, median and 1.4826 MAD in the same two fields.
struct Moments {
    double mean = 0.0;
    double sigma = 0.0;
    uint64_t count = 0;
};
Moments moments_of(const std::vector<double>& samples);

// How Step 2 standardises each data set: the paper's z-score, (x - mean) / σ,
// or (ours) (x - median) / (1.4826 MAD), which a few tracking glitches do not
// move (on a real recording they triple σ of acceleration and jerk in one
// half, docs/evaluation.md "Robust normalisation").  1.4826 = 1 / Φ⁻¹(3/4)
// makes the MAD a σ for normal data, so half_width keeps its meaning.
enum class Standardise : uint32_t { MeanSigma = 0, MedianMad = 1 };
constexpr double kMadToSigma = 1.482602218505602;

// The median (the mean of the two middle values for an even count) and the
// median absolute deviation about `median` (unscaled); 0 for no samples.
double median_of(std::vector<double> samples);
double mad_of(const std::vector<double>& samples, double median);
// The centre (as mean) and scale (as sigma) of `samples` under `how`.
Moments location_scale(const std::vector<double>& samples, Standardise how);

// The common interval [u1, u2] and bin count M of Step 3.  The paper takes
// "the interval of the metric"; after each data set is z-scored with its own
// mean and σ (Step 2) both live on the same axis, so the interval is fixed in
// σ units, [-half_width, half_width], shared by the real and simulated data.
// Samples beyond it are counted in the end bins, so every density integrates
// to 1 whatever the tails (jerk and η have long ones).
struct PdfOptions {
    uint32_t bins = 50;        // M
    double half_width = 4.0;   // u2 = -u1, in σ of each data set
    Standardise standardise = Standardise::MeanSigma;
};

// Step 2-3: Q_i = S_i M / (S (u2 - u1)) of the z-scored samples (centre and
// scale in `m`: location_scale).  A data set with scale 0 (all samples equal;
// robustly: more than half of them) puts everything in the bin of z = 0.
std::vector<double> discrete_pdf(const std::vector<double>& samples, const Moments& m, const PdfOptions& options);

// Step 4 (Eq. 2): E_φ = Σ_i |Q_real,i - Q_sim,i|.
double pdf_l1(const std::vector<double>& q_real, const std::vector<double>& q_sim);

// E_φ of every metric (Eq. 2), before normalisation, each side standardised
// as options.standardise says.  A metric with no samples on either side gets
// the largest possible distance, 2M/(u2-u1).
std::array<double, kMetricCount> metric_distances(const MetricSamples& real, const MetricSamples& sim,
                                                  const PdfOptions& options);

// Weights w_φ and normalisation parameters p1_φ, p2_φ of Eq. 1 and Eq. 3.
// The defaults (equal weights 1/7, p1 = 0, p2 = 1) score raw distances.
struct ScoreWeights {
    std::array<double, kMetricCount> w;
    std::array<double, kMetricCount> p1;
    std::array<double, kMetricCount> p2;
    ScoreWeights();
};

// Eq. 3 then Eq. 1: E = 1 - Σ_φ w_φ (E_φ - p1_φ) / p2_φ.
double score(const std::array<double, kMetricCount>& distances, const ScoreWeights& weights);

// The Wasserstein-1 (earth mover's) distance between two sample sets in the
// metric's own unit, ∫ |F_real(x) - F_sim(x)| dx of their empirical CDFs
// (ours, beside the z-scored E_φ, which ignores scale: a swarm ten times too
// fast can match every z-scored PDF).  Exact for the samples.
// Error(InvalidArgument) when a side is empty or a sample is not finite.
double wasserstein1(const std::vector<double>& real, const std::vector<double>& sim);

}  // namespace swarmcl
