#include "shapes/triangle_mesh.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"

namespace swarmcl {
namespace {

std::array<double, 3> sub(const Vec3f& a, const Vec3f& b) {
    return {double(a[0]) - b[0], double(a[1]) - b[1], double(a[2]) - b[2]};
}

std::array<double, 3> cross(const std::array<double, 3>& a, const std::array<double, 3>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

}  // namespace

double triangle_area(const Vec3f& a, const Vec3f& b, const Vec3f& c) {
    const auto n = cross(sub(b, a), sub(c, a));
    return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

TriangleMesh make_mesh(const float* xyz, size_t vertex_count, const uint32_t* indices,
                       size_t triangle_count, size_t* skipped, double min_area) {
    require(vertex_count > 0 && xyz != nullptr, "mesh: no vertices");
    require(triangle_count > 0 && indices != nullptr, "mesh: no triangles");
    TriangleMesh mesh;
    mesh.vertices.resize(vertex_count);
    for (size_t v = 0; v < vertex_count; ++v) {
        for (int k = 0; k < 3; ++k) {
            const float x = xyz[3 * v + k];
            require(std::isfinite(x), "mesh: vertex " + std::to_string(v) + " has a NaN or infinite coordinate");
            mesh.vertices[v][k] = x;
        }
    }
    if (min_area < 0.0) {
        const MeshBounds b = bounds(mesh);
        double diag2 = 0.0;
        for (int k = 0; k < 3; ++k) diag2 += double(b.max[k] - b.min[k]) * (b.max[k] - b.min[k]);
        min_area = 1e-12 * diag2;
    }
    size_t dropped = 0;
    mesh.triangles.reserve(triangle_count);
    for (size_t t = 0; t < triangle_count; ++t) {
        std::array<uint32_t, 3> f{indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
        for (uint32_t i : f)
            require(i < vertex_count, "mesh: triangle " + std::to_string(t) + " has vertex index " +
                                          std::to_string(i) + " (only " + std::to_string(vertex_count) +
                                          " vertices)");
        const bool repeated = f[0] == f[1] || f[1] == f[2] || f[0] == f[2];
        if (repeated || !(triangle_area(mesh.vertices[f[0]], mesh.vertices[f[1]], mesh.vertices[f[2]]) > min_area)) {
            ++dropped;
            continue;
        }
        mesh.triangles.push_back(f);
    }
    require(!mesh.triangles.empty(), "mesh: every triangle is degenerate (zero area)");
    if (skipped) *skipped = dropped;
    return mesh;
}

TriangleMesh make_mesh(const std::vector<float>& xyz, const std::vector<uint32_t>& indices, size_t* skipped) {
    require(xyz.size() % 3 == 0, "mesh: vertex array length is not a multiple of 3");
    require(indices.size() % 3 == 0, "mesh: index array length is not a multiple of 3");
    return make_mesh(xyz.data(), xyz.size() / 3, indices.data(), indices.size() / 3, skipped);
}

double surface_area(const TriangleMesh& mesh) {
    double a = 0.0;
    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto c = mesh.corners(t);
        a += triangle_area(c[0], c[1], c[2]);
    }
    return a;
}

double signed_volume(const TriangleMesh& mesh) {
    double v = 0.0;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
        const auto c = mesh.corners(t);
        v += (double(c[0][0]) * (double(c[1][1]) * c[2][2] - double(c[1][2]) * c[2][1]) -
              double(c[0][1]) * (double(c[1][0]) * c[2][2] - double(c[1][2]) * c[2][0]) +
              double(c[0][2]) * (double(c[1][0]) * c[2][1] - double(c[1][1]) * c[2][0])) / 6.0;
    }
    return v;
}

MeshBounds bounds(const TriangleMesh& mesh) {
    MeshBounds b;
    if (mesh.vertices.empty()) return b;
    b.min = b.max = mesh.vertices[0];
    for (const auto& v : mesh.vertices)
        for (int k = 0; k < 3; ++k) {
            b.min[k] = std::fmin(b.min[k], v[k]);
            b.max[k] = std::fmax(b.max[k], v[k]);
        }
    return b;
}

TriangleMesh transformed(const TriangleMesh& mesh, const Vec3f& scale, const Vec3f& offset) {
    TriangleMesh out = mesh;
    for (auto& v : out.vertices)
        for (int k = 0; k < 3; ++k) v[k] = scale[k] * v[k] + offset[k];
    // A reflection (odd number of negative scales) flips the winding back outward.
    if ((scale[0] < 0) ^ (scale[1] < 0) ^ (scale[2] < 0))
        for (auto& f : out.triangles) std::swap(f[1], f[2]);
    return out;
}

TriangleMesh merged(const std::vector<TriangleMesh>& meshes) {
    TriangleMesh out;
    for (const auto& m : meshes) {
        const uint32_t base = uint32_t(out.vertices.size());
        out.vertices.insert(out.vertices.end(), m.vertices.begin(), m.vertices.end());
        for (auto f : m.triangles) out.triangles.push_back({f[0] + base, f[1] + base, f[2] + base});
    }
    return out;
}

TriangleMesh box_mesh(const Vec3f& c, const Vec3f& h) {
    require(h[0] > 0 && h[1] > 0 && h[2] > 0, "box mesh: half extents must be > 0");
    TriangleMesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back({c[0] + ((i & 1) ? h[0] : -h[0]), c[1] + ((i & 2) ? h[1] : -h[1]),
                              c[2] + ((i & 4) ? h[2] : -h[2])});
    // Two counter-clockwise (seen from outside) triangles per face.
    const uint32_t q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& f : q) {
        m.triangles.push_back({f[0], f[1], f[2]});
        m.triangles.push_back({f[0], f[2], f[3]});
    }
    return m;
}

TriangleMesh ellipsoid_mesh(const Vec3f& c, const Vec3f& r, uint32_t rings, uint32_t segments) {
    require(r[0] > 0 && r[1] > 0 && r[2] > 0, "ellipsoid mesh: radii must be > 0");
    require(rings >= 2 && segments >= 3, "ellipsoid mesh: needs rings >= 2 and segments >= 3");
    const double pi = 3.14159265358979323846;
    TriangleMesh m;
    m.vertices.push_back({c[0], c[1], c[2] - r[2]});  // south pole
    for (uint32_t i = 1; i < rings; ++i) {
        const double th = pi * i / rings - pi / 2;
        for (uint32_t j = 0; j < segments; ++j) {
            const double ph = 2 * pi * j / segments;
            m.vertices.push_back({float(c[0] + r[0] * std::cos(th) * std::cos(ph)),
                                  float(c[1] + r[1] * std::cos(th) * std::sin(ph)),
                                  float(c[2] + r[2] * std::sin(th))});
        }
    }
    const uint32_t north = uint32_t(m.vertices.size());
    m.vertices.push_back({c[0], c[1], c[2] + r[2]});
    auto at = [&](uint32_t ring, uint32_t seg) { return 1 + (ring - 1) * segments + seg % segments; };
    for (uint32_t j = 0; j < segments; ++j) m.triangles.push_back({0, at(1, j + 1), at(1, j)});
    for (uint32_t i = 1; i + 1 < rings; ++i)
        for (uint32_t j = 0; j < segments; ++j) {
            m.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    for (uint32_t j = 0; j < segments; ++j) m.triangles.push_back({north, at(rings - 1, j), at(rings - 1, j + 1)});
    return m;
}

TriangleMesh sphere_mesh(const Vec3f& c, float radius, uint32_t rings, uint32_t segments) {
    return ellipsoid_mesh(c, {radius, radius, radius}, rings, segments);
}

TriangleMesh cylinder_mesh(const Vec3f& b, float radius, float height, uint32_t segments) {
    require(radius > 0 && height > 0, "cylinder mesh: radius and height must be > 0");
    require(segments >= 3, "cylinder mesh: needs segments >= 3");
    const double pi = 3.14159265358979323846;
    TriangleMesh m;
    m.vertices.push_back(b);
    m.vertices.push_back({b[0], b[1], b[2] + height});
    for (uint32_t j = 0; j < segments; ++j) {
        const double ph = 2 * pi * j / segments;
        const float x = float(b[0] + radius * std::cos(ph)), y = float(b[1] + radius * std::sin(ph));
        m.vertices.push_back({x, y, b[2]});
        m.vertices.push_back({x, y, b[2] + height});
    }
    auto lo = [&](uint32_t j) { return 2 + 2 * (j % segments); };
    auto hi = [&](uint32_t j) { return 3 + 2 * (j % segments); };
    for (uint32_t j = 0; j < segments; ++j) {
        m.triangles.push_back({0, lo(j + 1), lo(j)});
        m.triangles.push_back({1, hi(j), hi(j + 1)});
        m.triangles.push_back({lo(j), lo(j + 1), hi(j + 1)});
        m.triangles.push_back({lo(j), hi(j + 1), hi(j)});
    }
    return m;
}

}  // namespace swarmcl
