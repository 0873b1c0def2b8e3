// Entropy weights of the evaluation's energy terms (noise paper §3.3, Eq. 4):
// from the matrix X of the energy terms of m fitted models (rows) and n
// metrics (columns), the weights w_j and the normalisation parameters
// p1_j = min_i x_ij, p2_j = max_i x_ij - min_i x_ij of Eq. 3.
#pragma once
#include <cstddef>
#include <vector>

namespace swarmcl {

struct EntropyWeights {
    std::vector<double> w;   // n weights, summing to 1
    std::vector<double> p1;  // n
    std::vector<double> p2;  // n (a column with max == min gets p2 = 1: its terms normalise to 0)
    std::vector<double> e;   // n entropies e_j in [0, 1]
};

// x is row-major, m rows (models, m >= 2) by n columns (metrics, n >= 1),
// every value finite.  A column where every model scores the same carries no
// information: e_j = 1, w_j = 0.  When no column carries any, the weights are
// equal (1/n).
EntropyWeights entropy_weights(const std::vector<double>& x, size_t m, size_t n);

}  // namespace swarmcl
