#include "shapes/bspline_path.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"

namespace swarmcl {

BSplinePath::BSplinePath(const std::vector<float>& xyz) {
    require(xyz.size() % 3 == 0, "path: control points must be packed xyz (a multiple of 3 floats)");
    const size_t n = xyz.size() / 3;
    require(n >= 4, "path: a cubic B-spline needs at least 4 control points, got " + std::to_string(n));
    for (float v : xyz) require(std::isfinite(v), "path: control points must be finite");
    // Tripling the end points makes the uniform spline pass through them.
    for (int k = 0; k < 2; ++k) ctrl_.push_back({xyz[0], xyz[1], xyz[2]});
    for (size_t i = 0; i < n; ++i) ctrl_.push_back({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
    for (int k = 0; k < 2; ++k) ctrl_.push_back({xyz[3 * n - 3], xyz[3 * n - 2], xyz[3 * n - 1]});
    // Arc-length table: 64 chords per segment, inverted by linear
    // interpolation (error O(h^2) of the chord length).
    const size_t samples = 64 * (ctrl_.size() - 3);
    table_u_.resize(samples + 1);
    table_s_.resize(samples + 1);
    Vec3f prev = at_parameter(0.0);
    for (size_t i = 0; i <= samples; ++i) {
        const double u = double(i) / samples;
        const Vec3f p = at_parameter(u);
        double d2 = 0.0;
        for (int a = 0; a < 3; ++a) d2 += double(p[a] - prev[a]) * (p[a] - prev[a]);
        length_ += i ? std::sqrt(d2) : 0.0;
        table_u_[i] = u;
        table_s_[i] = length_;
        prev = p;
    }
}

Vec3f BSplinePath::at_parameter(double u) const {
    const size_t segments = ctrl_.size() - 3;
    const double x = std::clamp(u, 0.0, 1.0) * segments;
    const size_t k = std::min(size_t(x), segments - 1);
    const double t = x - k, t2 = t * t, t3 = t2 * t;
    // Uniform cubic B-spline basis.
    const double b0 = (1 - 3 * t + 3 * t2 - t3) / 6, b1 = (4 - 6 * t2 + 3 * t3) / 6,
                 b2 = (1 + 3 * t + 3 * t2 - 3 * t3) / 6, b3 = t3 / 6;
    Vec3f p{};
    for (int a = 0; a < 3; ++a)
        p[a] = float(b0 * ctrl_[k][a] + b1 * ctrl_[k + 1][a] + b2 * ctrl_[k + 2][a] + b3 * ctrl_[k + 3][a]);
    return p;
}

Vec3f BSplinePath::at_length(double s) const {
    if (length_ <= 0.0) return at_parameter(0.0);
    s = std::clamp(s, 0.0, length_);
    const size_t i = size_t(std::upper_bound(table_s_.begin(), table_s_.end(), s) - table_s_.begin());
    if (i == 0) return at_parameter(0.0);
    if (i >= table_s_.size()) return at_parameter(1.0);
    const double ds = table_s_[i] - table_s_[i - 1];
    const double f = ds > 0.0 ? (s - table_s_[i - 1]) / ds : 0.0;
    return at_parameter(table_u_[i - 1] + f * (table_u_[i] - table_u_[i - 1]));
}

}  // namespace swarmcl
