// Signed distance from a grid's cell centres to obstacle meshes (curl-noise
// paper §5.1, Eq. 5): negative inside, exact within a narrow band of the
// surface (OpenCL, kernels/sdf.cl), extended beyond it by propagating the
// band's closest surface points (host, a vector distance transform).  The
// sign comes from angle-weighted pseudonormals (Baerentzen & Aanaes 2005,
// the paper's [BA05]) near the surface and travels with the closest points,
// so a mesh with a small hole still has an inside.  With no mesh within the
// band of any cell (a mesh outside the grid), every cell is +inf.
#pragma once
#include <array>
#include <vector>

#include "device/context.hpp"
#include "fields/grid3.hpp"
#include "shapes/triangle_mesh.hpp"

namespace swarmcl {

struct SdfGrid {
    Grid3 grid;
    std::vector<float> phi;  // per cell, Grid3::index order; +inf where no mesh is in reach
};

// Exact band half-width in cells (>= 1).  3 covers the repulsion of Eq. 6,
// which vanishes at phi = 2a = 2 sqrt(2) l.
constexpr double kSdfDefaultBandCells = 3.0;

SdfGrid compute_sdf(Context& ctx, const TriangleMesh& mesh, const Grid3& grid,
                    double band_cells = kSdfDefaultBandCells);

// Per triangle the unit pseudonormals of its 7 features, in the order of
// kernels/sdf.cl: face, vertices a, b, c, edges ab, bc, ca.  Vertices are
// welded by position first, so meshes that repeat vertices per face get the
// same normals as indexed ones.  An edge used by one triangle only (a hole's
// rim) takes that face's normal.
std::vector<std::array<std::array<double, 3>, 7>> pseudonormals(const TriangleMesh& mesh);

}  // namespace swarmcl
