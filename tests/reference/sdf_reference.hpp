// Plain C++ references for the path field (kernels/sdf.cl and the host
// fields): brute-force signed distance in double over every triangle.
#pragma once
#include <array>
#include <cmath>
#include <vector>

#include "fields/grid3.hpp"
#include "fields/sdf.hpp"
#include "shapes/triangle_mesh.hpp"

namespace swarmcl::test {

using D3 = std::array<double, 3>;

inline D3 d3(const Vec3f& v) { return {v[0], v[1], v[2]}; }
inline D3 operator-(const D3& a, const D3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline D3 operator+(const D3& a, const D3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline D3 operator*(double s, const D3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dotd(const D3& a, const D3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Closest point on a triangle and its feature (0 face, 1-3 vertices, 4-6
// edges ab, bc, ca), as sdf_closest in kernels/sdf.cl.
inline D3 closest_on_triangle(const D3& p, const D3& a, const D3& b, const D3& c, int* feature) {
    const D3 ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dotd(ab, ap), d2 = dotd(ac, ap);
    if (d1 <= 0 && d2 <= 0) { *feature = 1; return a; }
    const D3 bp = p - b;
    const double d3_ = dotd(ab, bp), d4 = dotd(ac, bp);
    if (d3_ >= 0 && d4 <= d3_) { *feature = 2; return b; }
    const double vc = d1 * d4 - d3_ * d2;
    if (vc <= 0 && d1 >= 0 && d3_ <= 0) { *feature = 4; return a + (d1 / (d1 - d3_)) * ab; }
    const D3 cp = p - c;
    const double d5 = dotd(ab, cp), d6 = dotd(ac, cp);
    if (d6 >= 0 && d5 <= d6) { *feature = 3; return c; }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) { *feature = 6; return a + (d2 / (d2 - d6)) * ac; }
    const double va = d3_ * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3_) >= 0 && (d5 - d6) >= 0) {
        *feature = 5;
        return b + ((d4 - d3_) / ((d4 - d3_) + (d5 - d6))) * (c - b);
    }
    const double denom = 1.0 / (va + vb + vc);
    *feature = 0;
    return a + (vb * denom) * ab + (vc * denom) * ac;
}

// Signed distance at every cell centre: the closest triangle over all of
// them, the sign of the closest feature's pseudonormal (Eq. 5, [BA05]).
inline std::vector<double> sdf_brute_force(const TriangleMesh& mesh, const Grid3& g) {
    const auto normals = pseudonormals(mesh);
    std::vector<double> phi(g.count());
    for (uint32_t k = 0; k < g.dims[2]; ++k)
        for (uint32_t j = 0; j < g.dims[1]; ++j)
            for (uint32_t i = 0; i < g.dims[0]; ++i) {
                const D3 p = g.center(i, j, k);
                double best = INFINITY;
                D3 q{};
                size_t bt = 0;
                int bf = 0;
                for (size_t t = 0; t < mesh.triangle_count(); ++t) {
                    const auto c = mesh.corners(t);
                    int f;
                    const D3 x = closest_on_triangle(p, d3(c[0]), d3(c[1]), d3(c[2]), &f);
                    const double d2 = dotd(p - x, p - x);
                    if (d2 < best) { best = d2; q = x; bt = t; bf = f; }
                }
                const double s = dotd(p - q, normals[bt][bf]) < 0 ? -1.0 : 1.0;
                phi[g.index(i, j, k)] = s * std::sqrt(best);
            }
    return phi;
}

}  // namespace swarmcl::test
