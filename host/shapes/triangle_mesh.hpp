// A triangle mesh on the host: the one mesh type shared by obstacles (signed
// distance, path field) and target shapes (force model sampling).  Built only
// through make_mesh(), so every mesh in the library is valid: finite
// coordinates, indices in range, no degenerate triangles, at least one
// triangle.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace swarmcl {

using Vec3f = std::array<float, 3>;

struct TriangleMesh {
    std::vector<Vec3f> vertices;
    std::vector<std::array<uint32_t, 3>> triangles;

    size_t triangle_count() const { return triangles.size(); }
    // Corners of triangle t.
    std::array<Vec3f, 3> corners(size_t t) const {
        const auto& f = triangles[t];
        return {vertices[f[0]], vertices[f[1]], vertices[f[2]]};
    }
};

struct MeshBounds {
    Vec3f min{}, max{};
};

// Builds a mesh from packed xyz vertices and packed triangle indices.
// Error(InvalidArgument) for NaN/Inf coordinates (naming the vertex), indices
// out of range (naming the triangle), a vertex array that is not a multiple
// of 3 or an index array not a multiple of 3, and a mesh left with no
// triangle.  Degenerate triangles (repeated index or area below
// `min_area`, default: 1e-12 of the squared bounding-box diagonal) are
// skipped; `skipped` (optional) receives how many.
TriangleMesh make_mesh(const float* xyz, size_t vertex_count, const uint32_t* indices,
                       size_t triangle_count, size_t* skipped = nullptr, double min_area = -1.0);
TriangleMesh make_mesh(const std::vector<float>& xyz, const std::vector<uint32_t>& indices,
                       size_t* skipped = nullptr);

double triangle_area(const Vec3f& a, const Vec3f& b, const Vec3f& c);
double surface_area(const TriangleMesh& mesh);
// Enclosed volume by the divergence theorem: > 0 for a closed, outward-oriented mesh.
double signed_volume(const TriangleMesh& mesh);
MeshBounds bounds(const TriangleMesh& mesh);

// x -> scale * x + offset, per axis.
TriangleMesh transformed(const TriangleMesh& mesh, const Vec3f& scale, const Vec3f& offset);
// All triangles of several meshes in one mesh (vertices are not merged).
TriangleMesh merged(const std::vector<TriangleMesh>& meshes);

// Closed, outward-oriented (counter-clockwise seen from outside) primitives.
TriangleMesh box_mesh(const Vec3f& center, const Vec3f& half_extents);
// UV sphere / ellipsoid: `rings` >= 2 latitude bands, `segments` >= 3.
TriangleMesh ellipsoid_mesh(const Vec3f& center, const Vec3f& radii, uint32_t rings = 16,
                            uint32_t segments = 32);
TriangleMesh sphere_mesh(const Vec3f& center, float radius, uint32_t rings = 16, uint32_t segments = 32);
// Capped cylinder along +z from `base` (the bottom cap's centre).
TriangleMesh cylinder_mesh(const Vec3f& base, float radius, float height, uint32_t segments = 32);

}  // namespace swarmcl
