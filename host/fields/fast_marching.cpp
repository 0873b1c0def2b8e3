#include "fields/fast_marching.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.hpp"

namespace swarmcl {
namespace {

enum : uint8_t { kFar = 0, kTrial = 1, kKnown = 2 };

struct Entry {
    double value;
    uint32_t cell;
    bool operator<(const Entry& o) const { return value > o.value; }  // min-heap
};

}  // namespace

void fast_march(const Grid3& g, const std::vector<double>& slowness, std::vector<double>& u,
                const FastMarchingOptions& options, std::vector<int8_t>* sign) {
    const size_t n = g.count();
    require(slowness.size() == n && u.size() == n, "fast marching: arrays do not match the grid");
    require(n < 0xFFFFFFFFu, "fast marching: too many cells");
    const int64_t nx = g.dims[0], ny = g.dims[1], nz = g.dims[2];
    const int64_t stride[3] = {1, nx, nx * ny};
    const int64_t dim[3] = {nx, ny, nz};
    const double h = g.h;

    std::vector<uint8_t> state(n, kFar);
    std::vector<Entry> heap;
    heap.reserve(1 << 16);
    for (size_t c = 0; c < n; ++c)
        if (std::isfinite(u[c])) state[c] = kKnown;

    // Solves the upwind quadratic at cell c from its known neighbours;
    // *from_sign: the sign of the smallest of them.
    auto solve = [&](size_t c, const int64_t x[3], int8_t* from_sign) -> double {
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
                if (m < best) {
                    best = m;
                    *from_sign = sign ? (*sign)[nb] : 1;
                }
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
                int8_t s = 1;
                const double v = solve(nb, y, &s);
                if (v < u[nb]) {
                    u[nb] = v;
                    if (sign) (*sign)[nb] = s;
                    state[nb] = kTrial;
                    heap.push_back({v, uint32_t(nb)});
                    std::push_heap(heap.begin(), heap.end());
                }
            }
    };

    for (size_t c = 0; c < n; ++c)
        if (state[c] == kKnown) push_neighbours(c);
    while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end());
        const Entry e = heap.back();
        heap.pop_back();
        if (state[e.cell] == kKnown || e.value != u[e.cell]) continue;  // stale entry
        state[e.cell] = kKnown;
        push_neighbours(e.cell);
    }
}

}  // namespace swarmcl
