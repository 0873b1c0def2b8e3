#include "eval/entropy_weights.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace swarmcl {

EntropyWeights entropy_weights(const std::vector<double>& x, size_t m, size_t n) {
    require(m >= 2, "entropy weights: need at least two models (rows)");
    require(n >= 1, "entropy weights: need at least one energy term (column)");
    require(n <= x.size() / m && x.size() == m * n, "entropy weights: the matrix must have m*n values");
    for (double v : x) require(std::isfinite(v), "entropy weights: every energy term must be finite");
    EntropyWeights out;
    out.w.assign(n, 0.0);
    out.p1.assign(n, 0.0);
    out.p2.assign(n, 1.0);
    out.e.assign(n, 1.0);
    const double ln_m = std::log(double(m));
    double total = 0.0;
    for (size_t j = 0; j < n; ++j) {
        double lo = x[j], hi = x[j];
        for (size_t i = 1; i < m; ++i) lo = std::min(lo, x[i * n + j]), hi = std::max(hi, x[i * n + j]);
        out.p1[j] = lo;
        if (hi == lo) continue;  // no information: e = 1
        out.p2[j] = hi - lo;
        // r_ij = 1 - x'_ij, g_ij = r_ij / Σ_i r_ij; the best model (x' = 0)
        // has r = 1, so Σ_i r_ij >= 1.
        double rsum = 0.0;
        for (size_t i = 0; i < m; ++i) rsum += 1.0 - (x[i * n + j] - lo) / out.p2[j];
        double h = 0.0;
        for (size_t i = 0; i < m; ++i) {
            const double g = (1.0 - (x[i * n + j] - lo) / out.p2[j]) / rsum;
            if (g > 0.0) h += g * std::log(g);
        }
        out.e[j] = -h / ln_m;
        total += 1.0 - out.e[j];
    }
    for (size_t j = 0; j < n; ++j) out.w[j] = total > 0.0 ? (1.0 - out.e[j]) / total : 1.0 / double(n);
    return out;
}

}  // namespace swarmcl
