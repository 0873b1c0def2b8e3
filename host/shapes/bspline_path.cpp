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
    for (float v : xyz) scale_ = std::max(scale_, double(std::fabs(v)));
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
    build_frames();
}

Vec3f BSplinePath::at_parameter(double u) const {
    const D3 p = point(u);
    return {float(p[0]), float(p[1]), float(p[2])};
}

BSplinePath::D3 BSplinePath::point(double u) const {
    const size_t segments = ctrl_.size() - 3;
    const double x = std::clamp(u, 0.0, 1.0) * segments;
    const size_t k = std::min(size_t(x), segments - 1);
    const double t = x - k, t2 = t * t, t3 = t2 * t;
    // Uniform cubic B-spline basis.
    const double b0 = (1 - 3 * t + 3 * t2 - t3) / 6, b1 = (4 - 6 * t2 + 3 * t3) / 6,
                 b2 = (1 + 3 * t + 3 * t2 - 3 * t3) / 6, b3 = t3 / 6;
    D3 p{};
    for (int a = 0; a < 3; ++a)
        p[a] = b0 * ctrl_[k][a] + b1 * ctrl_[k + 1][a] + b2 * ctrl_[k + 2][a] + b3 * ctrl_[k + 3][a];
    return p;
}

double BSplinePath::param_at_length(double s) const {
    if (length_ <= 0.0) return 0.0;
    s = std::clamp(s, 0.0, length_);
    const size_t i = size_t(std::upper_bound(table_s_.begin(), table_s_.end(), s) - table_s_.begin());
    if (i == 0) return 0.0;
    if (i >= table_s_.size()) return 1.0;
    const double ds = table_s_[i] - table_s_[i - 1];
    const double f = ds > 0.0 ? (s - table_s_[i - 1]) / ds : 0.0;
    return table_u_[i - 1] + f * (table_u_[i] - table_u_[i - 1]);
}

Vec3f BSplinePath::at_length(double s) const { return at_parameter(param_at_length(s)); }

// ---- the frame along the path ------------------------------------------------

namespace {

using D3 = BSplinePath::D3;

double dot(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
D3 sub(const D3& a, const D3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
D3 axpy(const D3& x, double a, const D3& y) { return {x[0] + a * y[0], x[1] + a * y[1], x[2] + a * y[2]}; }

// v made normal to the unit vector t and normalised; false if v is (nearly)
// parallel to t.
bool normal_to(D3& v, const D3& t) {
    v = axpy(v, -dot(v, t), t);
    const double l = std::sqrt(dot(v, v));
    if (!(l > 1e-9)) return false;
    for (double& x : v) x /= l;
    return true;
}

// One step of the double-reflection method (Wang, Jüttler, Zheng, Liu,
// "Computation of rotation minimizing frames", ACM TOG 2008, Alg. 1): the
// up vector r at (x0, t0) carried to (x1, t1).  Reflecting in the bisector
// plane of x0 x1, then in the one that takes the reflected tangent to t1,
// approximates the rotation-minimising frame to O(h^4) per step.
D3 carry_up(const D3& x0, const D3& t0, const D3& r0, const D3& x1, const D3& t1) {
    const D3 v1 = sub(x1, x0);
    const double c1 = dot(v1, v1);
    D3 r = r0, t = t0;
    if (c1 > 0.0) {
        r = axpy(r0, -2.0 / c1 * dot(v1, r0), v1);
        t = axpy(t0, -2.0 / c1 * dot(v1, t0), v1);
    }
    const D3 v2 = sub(t1, t);
    const double c2 = dot(v2, v2);
    if (c2 > 0.0) r = axpy(r, -2.0 / c2 * dot(v2, r), v2);
    if (!normal_to(r, t1)) r = r0;  // cannot happen for unit tangents; keep the frame
    return r;
}

}  // namespace

BSplinePath::D3 BSplinePath::tangent_at_parameter(double u) const {
    const size_t segments = ctrl_.size() - 3;
    const double x = std::clamp(u, 0.0, 1.0) * segments;
    const size_t k = std::min(size_t(x), segments - 1);
    const double t = x - k, t2 = t * t;
    // First, second and third derivatives of the uniform cubic basis.  With
    // the end points tripled the first and second vanish at both ends; the
    // third (constant on a segment) is then the direction the curve leaves
    // the first point / reaches the last by.
    const double basis[3][4] = {{-(1 - t) * (1 - t) / 2, (3 * t2 - 4 * t) / 2, (1 + 2 * t - 3 * t2) / 2, t2 / 2},
                                {1 - t, 3 * t - 2, 1 - 3 * t, t},
                                {-1, 3, -3, 1}};
    for (const auto& b : basis) {
        D3 d{};
        for (int a = 0; a < 3; ++a)
            d[a] = b[0] * ctrl_[k][a] + b[1] * ctrl_[k + 1][a] + b[2] * ctrl_[k + 2][a] + b[3] * ctrl_[k + 3][a];
        const double l = std::sqrt(dot(d, d));
        if (l > 1e-12 * scale_) return {d[0] / l, d[1] / l, d[2] / l};
    }
    return {1.0, 0.0, 0.0};  // all control points equal: no direction, keep the shape's own
}

void BSplinePath::build_frames() {
    // The start: world +z made normal to the tangent.  A path that starts
    // vertically has no such up; there the shape is pitched by the smallest
    // rotation taking its forward axis +x to the tangent t = (0, 0, +-1),
    // which takes +z to (-t_z, 0, 0).
    const D3 t0 = tangent_at_parameter(0.0);
    D3 up{0.0, 0.0, 1.0};
    if (!normal_to(up, t0)) up = {t0[2] > 0.0 ? -1.0 : 1.0, 0.0, 0.0};
    table_up_.assign(table_u_.size(), up);
    D3 x = point(0.0), t = t0;
    for (size_t i = 1; i < table_u_.size(); ++i) {
        const D3 x1 = point(table_u_[i]), t1 = tangent_at_parameter(table_u_[i]);
        table_up_[i] = carry_up(x, t, table_up_[i - 1], x1, t1);
        x = x1;
        t = t1;
    }
}

BSplinePath::Frame BSplinePath::frame_at_length(double s) const {
    const double u = param_at_length(s);
    // The last table sample at or before u, then one double-reflection step
    // from it: continuous in s (it reaches the next sample's frame there).
    const size_t i = std::min(size_t(std::upper_bound(table_u_.begin(), table_u_.end(), u) - table_u_.begin()),
                              table_u_.size()) - 1;
    Frame f;
    f.point = point(u);
    f.tangent = tangent_at_parameter(u);
    f.up = carry_up(point(table_u_[i]), tangent_at_parameter(table_u_[i]), table_up_[i], f.point, f.tangent);
    return f;
}

}  // namespace swarmcl
