#include "fields/fast_marching.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"

namespace swarmcl {
namespace {

enum : uint8_t { kFar = 0, kTrial = 1, kKnown = 2 };

}  // namespace

void fast_march(const Grid3& g, const std::vector<double>& slowness, std::vector<double>& u,
                const FastMarchingOptions& options) {
    const size_t n = g.count();
    require(slowness.size() == n && u.size() == n, "fast marching: arrays do not match the grid");
    require(n < 0xFFFFFFFFu, "fast marching: too many cells");
    const int64_t nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    const int64_t stride[3] = {1, nx, nx * ny};
    const int64_t dim[3] = {nx, ny, nz};
    const double h = g.h;

    std::vector<uint8_t> state(n, kFar);
    double f_min = kInf;
    for (size_t c = 0; c < n; ++c) {
        if (std::isfinite(u[c])) state[c] = kKnown;
        f_min = std::min(f_min, slowness[c]);
        require(slowness[c] > 0.0, "fast marching: slowness must be > 0 (+inf: impassable)");
    }
    if (!std::isfinite(f_min)) return;  // every cell impassable

    // An untidy priority queue (Yatziv, Bartesaghi & Sapiro 2006; Dial's
    // buckets): trial cells sit in buckets of width delta by value and are
    // accepted bucket by bucket.  An update adds at least f h / sqrt(3) to
    // the smallest known neighbour, so with delta <= f_min h / sqrt(3) no
    // cell can change the value of another cell of its own bucket: the
    // order within a bucket does not matter, and the result is that of the
    // heap-ordered method up to rounding, in O(N) instead of O(N log N)
    // (3.6x faster at 128^3, bench/fmm_bench.cpp).  Second order can add
    // less; its buckets are half as wide.
    const double delta = f_min * h / std::sqrt(3.0) * (options.second_order ? 0.5 : 1.0);
    std::vector<std::vector<uint32_t>> buckets(64);
    auto bucket_of = [&](double v) { return size_t(v / delta); };
    auto enqueue = [&](size_t c) {
        const size_t b = bucket_of(u[c]);
        if (b >= buckets.size()) buckets.resize(std::max(b + 1, 2 * buckets.size()));
        buckets[b].push_back(uint32_t(c));
    };

    // Solves the upwind quadratic at cell c from its known neighbours.
    auto solve = [&](size_t c, const int64_t x[3]) -> double {
        const double f = slowness[c];
        double b1[3], b2[3];  // per axis: the smaller known neighbour, and the known cell beyond it
        int axes = 0;
        double best = kInf;
        for (int a = 0; a < 3; ++a) {
            double m = kInf, m2 = kInf;
            for (int side = -1; side <= 1; side += 2) {
                const int64_t xa = x[a] + side;
                if (xa < 0 || xa >= dim[a]) continue;
                const size_t nb = c + side * stride[a];
                if (state[nb] != kKnown || !(u[nb] < m)) continue;
                m = u[nb];
                m2 = kInf;
                const int64_t xb = x[a] + 2 * side;
                if (options.second_order && xb >= 0 && xb < dim[a]) {
                    const size_t nb2 = c + 2 * side * stride[a];
                    if (state[nb2] == kKnown && u[nb2] <= m) m2 = u[nb2];
                }
                best = std::min(best, m);
            }
            if (m < kInf) {
                b1[axes] = m;
                b2[axes] = m2;
                ++axes;
            }
        }
        if (axes == 0) return kInf;
        // First order: add axes in increasing order of their value while the
        // solution stays above them.
        double sorted[3] = {b1[0], axes > 1 ? b1[1] : kInf, axes > 2 ? b1[2] : kInf};
        if (sorted[1] < sorted[0]) std::swap(sorted[0], sorted[1]);  // sort 3 (inf pads)
        if (sorted[2] < sorted[1]) std::swap(sorted[1], sorted[2]);
        if (sorted[1] < sorted[0]) std::swap(sorted[0], sorted[1]);
        const double fh = f * h;
        double result = sorted[0] + fh;
        double s = sorted[0], s2 = sorted[0] * sorted[0];
        for (int k = 1; k < axes && result > sorted[k]; ++k) {
            s += sorted[k];
            s2 += sorted[k] * sorted[k];
            const double m = k + 1;
            result = (s + std::sqrt(std::max(0.0, s * s - m * (s2 - fh * fh)))) / m;
        }
        if (options.second_order) {
            // sum_a c_a (u - b_a)^2 = f^2 over the axes the first-order
            // solution uses, with c = 9/(4h^2), b = (4 b1 - b2)/3 where the
            // cell beyond is known (one-sided second-order difference), else
            // c = 1/h^2, b = b1.  Kept only when it is a consistent upwind
            // value (between the smallest neighbour and the first-order one).
            double A = 0, B = 0, C = -f * f;
            bool any2 = false;
            for (int k = 0; k < axes; ++k) {
                if (!(b1[k] < result)) continue;
                const bool two = b2[k] < kInf;
                const double ca = two ? 9.0 / (4.0 * h * h) : 1.0 / (h * h);
                const double ba = two ? (4.0 * b1[k] - b2[k]) / 3.0 : b1[k];
                any2 |= two;
                A += ca;
                B -= 2.0 * ca * ba;
                C += ca * ba * ba;
            }
            const double disc = B * B - 4 * A * C;
            if (any2 && disc >= 0) {
                const double r2 = (-B + std::sqrt(disc)) / (2 * A);
                if (r2 >= best && r2 <= result) result = r2;
            }
        }
        return result;
    };

    auto push_neighbours = [&](size_t c) {
        int64_t x[3] = {int64_t(c % nx), int64_t((c / nx) % ny), int64_t(c / (nx * ny))};
        for (int a = 0; a < 3; ++a)
            for (int side = -1; side <= 1; side += 2) {
                const int64_t xa = x[a] + side;
                if (xa < 0 || xa >= dim[a]) continue;
                const size_t nb = c + side * stride[a];
                if (state[nb] == kKnown || !std::isfinite(slowness[nb])) continue;
                int64_t y[3] = {x[0], x[1], x[2]};
                y[a] = xa;
                const double v = solve(nb, y);
                if (v < u[nb]) {
                    u[nb] = v;
                    state[nb] = kTrial;
                    enqueue(nb);
                }
            }
    };

    for (size_t c = 0; c < n; ++c)
        if (state[c] == kKnown) push_neighbours(c);
    for (size_t b = 0; b < buckets.size(); ++b) {
        // Rounding can put an update back into the current bucket: drain it.
        while (!buckets[b].empty()) {
            std::vector<uint32_t> cells;
            cells.swap(buckets[b]);
            for (uint32_t c : cells) {
                if (state[c] == kKnown || bucket_of(u[c]) != b) continue;  // accepted, or moved to a lower bucket
                state[c] = kKnown;
                push_neighbours(c);
            }
        }
        std::vector<uint32_t>().swap(buckets[b]);
    }
}

}  // namespace swarmcl
