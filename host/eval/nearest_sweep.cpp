#include "eval/nearest_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace swarmcl {
namespace {

// Candidate j at squared distance r2 against the best so far: nearer, or as
// near with a lower index.  What wins is the least (r2, j) whatever order
// the candidates come in, so the scans below may take them in any order and
// more than once.  Branch-free: a candidate this near is as likely nearer as
// not.
inline void take(double r2, uint32_t j, double& best, uint32_t& who) {
    const bool nearer = (r2 < best) | ((r2 == best) & (j < who));
    best = nearer ? r2 : best;
    who = nearer ? j : who;
}

// The squared distance of (x, y, z) from q as the brute force's: the
// differences (candidate - q) squared and summed x, y, z in that order, so
// equal distances compare equal.
inline double distance2(double qx, double qy, double qz, double x, double y, double z) {
    const double dx = x - qx, dy = y - qy, dz = z - qz;
    return dx * dx + dy * dy + dz * dz;
}

}  // namespace

void NearestSweep::find(const std::vector<Vec3>& p, const std::vector<uint32_t>* hint, std::vector<uint32_t>& nn) {
    const size_t g = p.size();
    nn.resize(g);
    if (g != order_.size() || frames_since_axis_ >= kAxisEvery) {
        axis_ = widest_axis(p);
        frames_since_axis_ = 0;
        order_.resize(g);
        for (size_t i = 0; i < g; ++i) order_[i] = {p[i][axis_], uint32_t(i)};
        std::sort(order_.begin(), order_.end(), [](const Entry& a, const Entry& b) { return before(a, b); });
        // The pads stay NaN; the frames below write the entries between.
        for (auto& c : xyz_) c.assign(g + 2 * kPad, std::numeric_limits<double>::quiet_NaN());
        for (auto& c : xyz_f_) c.assign(g + 2 * kPad, std::numeric_limits<float>::quiet_NaN());
        index_.assign(g + 2 * kPad, 0);
    } else {
        ++frames_since_axis_;
        for (auto& o : order_) o.key = p[o.index][axis_];
        for (size_t r = 1; r < g; ++r)  // insertion sort: few moves between frames
            for (size_t k = r; k > 0 && before(order_[k], order_[k - 1]); --k) std::swap(order_[k], order_[k - 1]);
    }
    // The scans read the coordinates in axis order, in sequence.
    double extent = 0.0;
    for (size_t r = 0; r < g; ++r) {
        const Vec3& q = p[order_[r].index];
        for (size_t d = 0; d < 3; ++d) {
            xyz_[d][kPad + r] = q[d];
            xyz_f_[d][kPad + r] = float(q[d]);
            extent = std::max(extent, std::abs(q[d]));
        }
        index_[kPad + r] = order_[r].index;
    }
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool avx2 = __builtin_cpu_supports("avx2");
    // Past 1e18 m float squares could overflow and the filter reject a
    // point: such frames take the double scan.
    if (wide_ && avx2 && extent <= 1e18) {
        scan_avx2(p, hint, extent, nn);
        return;
    }
#endif
    scan(p, hint, nn);
}

NearestSweep::Sorted NearestSweep::sorted() const {
    return {xyz_[0].data() + kPad,   xyz_[1].data() + kPad,   xyz_[2].data() + kPad,   xyz_[axis_].data() + kPad,
            xyz_f_[0].data() + kPad, xyz_f_[1].data() + kPad, xyz_f_[2].data() + kPad, index_.data() + kPad,
            long(index_.size() - 2 * kPad)};
}

// Inlined into the scans (a call a point was 6 % of the sweep's samples).
__attribute__((always_inline)) inline void NearestSweep::first_bound(const Sorted& s, long r,
                                                                     const std::vector<Vec3>& p,
                                                                     const std::vector<uint32_t>* hint, double& best,
                                                                     uint32_t& who) {
    best = std::numeric_limits<double>::infinity();
    who = std::numeric_limits<uint32_t>::max();
    const uint32_t i = s.index[r];
    if (hint == nullptr || (*hint)[i] == i) return;
    const Vec3& h = p[(*hint)[i]];
    take(distance2(s.x[r], s.y[r], s.z[r], h[0], h[1], h[2]), (*hint)[i], best, who);
}

void NearestSweep::scan(const std::vector<Vec3>& p, const std::vector<uint32_t>* hint, std::vector<uint32_t>& nn) const {
    const Sorted s = sorted();
    // Candidate k for point r: its distance, and whether its axis gap alone
    // exceeds the best so far.  r2 >= (axis gap)^2 in floating point too
    // (adding non-negative squares never rounds below one of them), so
    // stopping there skips no nearer point, nor an equal one.
    const auto candidate = [&s](long r, long k, double& best, uint32_t& who) {
        const double gap = s.axis[k] - s.axis[r];
        if (gap * gap > best) return false;
        take(distance2(s.x[r], s.y[r], s.z[r], s.x[k], s.y[k], s.z[k]), s.index[k], best, who);
        return true;
    };
    for (long r = 0; r < s.count; ++r) {
        double best;
        uint32_t who;
        first_bound(s, r, p, hint, best, who);
        for (long k = r - 1; k >= 0; --k)
            if (!candidate(r, k, best, who)) break;
        for (long k = r + 1; k < s.count; ++k)
            if (!candidate(r, k, best, who)) break;
        nn[s.index[r]] = who;
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
namespace {
// The float filter's bound for the best squared distance so far: every
// candidate whose squared distance in double (distance2) is at or below
// best has a float squared distance at or below the bound.  Rounding the
// coordinates to float moves a point by at most sqrt(3) u M (u = 2^-24, M
// the frame's largest |coordinate|) and the float differences, squares and
// sums add a few u relative: the float distance is below (sqrt(best) (1 +
// 16 u) + e) (1 + 8 u) with e = 8 u M, whose square is below best (1 +
// 2^-9) + 1040 e^2 (2 sqrt(best) e <= 2^-10 best + 2^10 e^2).  `slack` is
// 1040 e^2 (filter_slack); a few extra candidates reach the double test,
// never one fewer.  Infinite without a best yet.
inline double filter_slack(double extent) {
    const double e = 8.0 * 0x1p-24 * extent;
    return 1040.0 * e * e;
}
__attribute__((target("avx2"), always_inline)) inline __m256 filter_bound(double best, double slack) {
    // (1 + 2^-20): float() rounds down by less than that.
    return _mm256_set1_ps(float((best * (1.0 + 0x1p-9) + slack) * (1.0 + 0x1p-20)));
}

// Candidates k..k+7 against the query (q*f in float, x, y, z in double):
// their float squared distances, (x_f - q_f) squared and summed x, y, z,
// against the filter's bound; the lanes at or below it go through take()
// with the double distance2, and a nearer best lowers the bound.
__attribute__((target("avx2"), always_inline)) inline void take8(const float* XF, const float* YF, const float* ZF,
                                                                const double* X, const double* Y, const double* Z,
                                                                const uint32_t* I, long k, __m256 qxf, __m256 qyf,
                                                                __m256 qzf, double x, double y, double z,
                                                                double slack, __m256& bound, double& best,
                                                                uint32_t& who) {
    const __m256 dx = _mm256_sub_ps(_mm256_loadu_ps(XF + k), qxf);
    const __m256 dy = _mm256_sub_ps(_mm256_loadu_ps(YF + k), qyf);
    const __m256 dz = _mm256_sub_ps(_mm256_loadu_ps(ZF + k), qzf);
    const __m256 r2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
    int near = _mm256_movemask_ps(_mm256_cmp_ps(r2, bound, _CMP_LE_OQ));  // NaN (the pads): never
    if (near == 0) return;
    const double was = best;
    for (; near != 0; near &= near - 1) {
        const long j = k + __builtin_ctz(unsigned(near));
        take(distance2(x, y, z, X[j], Y[j], Z[j]), I[j], best, who);
    }
    if (best != was) bound = filter_bound(best, slack);
}
}  // namespace

// scan() eight candidates at a time, filtered in float (about twice the
// candidates an instruction of the double lanes took): the blocks run from
// r - 8 down and from r + 1 up, never take r itself, and read the NaN pads
// past either end; a block's last candidate decides the stop, on the
// double axis as scan()'s.
__attribute__((target("avx2"))) void NearestSweep::scan_avx2(const std::vector<Vec3>& p,
                                                             const std::vector<uint32_t>* hint, double extent,
                                                             std::vector<uint32_t>& nn) const {
    const Sorted s = sorted();
    const double *X = s.x, *Y = s.y, *Z = s.z, *A = s.axis;
    const float *XF = s.xf, *YF = s.yf, *ZF = s.zf;
    const uint32_t* I = s.index;
    const long g = s.count;
    const double slack = filter_slack(extent);
    for (long r = 0; r < g; ++r) {
        const double a = A[r];
        double best;
        uint32_t who;
        first_bound(s, r, p, hint, best, who);
        __m256 bound = filter_bound(best, slack);
        const __m256 qx = _mm256_set1_ps(XF[r]), qy = _mm256_set1_ps(YF[r]), qz = _mm256_set1_ps(ZF[r]);
        for (long k = r - 8;; k -= 8) {  // r - 8 >= -kPad
            take8(XF, YF, ZF, X, Y, Z, I, k, qx, qy, qz, X[r], Y[r], Z[r], slack, bound, best, who);
            const double gap = a - A[k];
            if (k <= 0 || gap * gap > best) break;
        }
        for (long k = r + 1; k < g; k += 8) {  // k + 7 < g + kPad
            take8(XF, YF, ZF, X, Y, Z, I, k, qx, qy, qz, X[r], Y[r], Z[r], slack, bound, best, who);
            const double gap = A[k + 7] - a;  // NaN past the end: the loop's test stops it
            if (gap * gap > best) break;
        }
        nn[I[r]] = who;
    }
}
#endif

// The axis with the widest interquartile range, so a few far glitches do not
// pick an axis the bulk of the frame is flat on.
size_t NearestSweep::widest_axis(const std::vector<Vec3>& p) {
    auto& c = coords_;
    c.resize(p.size());
    size_t axis = 0;
    double widest = -1.0;
    for (size_t d = 0; d < 3; ++d) {
        for (size_t i = 0; i < p.size(); ++i) c[i] = p[i][d];
        const size_t q1 = c.size() / 4, q3 = (3 * c.size()) / 4;
        std::nth_element(c.begin(), c.begin() + long(q3), c.end());
        const double hi = c[q3];
        std::nth_element(c.begin(), c.begin() + long(q1), c.begin() + long(q3));
        const double iqr = hi - c[q1];
        if (iqr > widest) widest = iqr, axis = d;
    }
    return axis;
}

}  // namespace swarmcl
