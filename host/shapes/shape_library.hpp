// Target shapes the project generates itself (no third-party meshes): the
// shapes of the force model's scenarios (shape-constrained flying insects
// paper, §7, Table 1) and a few more.  All closed, outward oriented, about
// 2 m across, centred near the origin; the model scales them (§5.1).
#pragma once
#include <string>
#include <vector>

#include "shapes/triangle_mesh.hpp"

namespace swarmcl {

// Ring torus in the xy plane.
TriangleMesh torus_mesh(float major_radius, float minor_radius, uint32_t rings = 24, uint32_t segments = 48);
// A crescent moon: a tube bent along 3/4 of a circle in the xy plane whose
// radius swells from the pointed tips to the middle.
TriangleMesh crescent_mesh(float radius, float thickness, uint32_t rings = 64, uint32_t segments = 16);
// A five-pointed star and a heart: outlines in the xy plane extruded along z.
TriangleMesh star_mesh(float outer_radius, float inner_radius, float depth);
TriangleMesh heart_mesh(float size, float depth, uint32_t outline = 96);
// Animals built from ellipsoids (merged, overlapping).  The horse's legs are
// posed by `phase` in [0, 1): one gallop cycle; every phase has the same
// topology (same triangles in the same order), so keyframes of the cycle
// correspond sample by sample.
TriangleMesh mammoth_mesh();
TriangleMesh shark_mesh();
TriangleMesh horse_mesh(float phase);

// The shapes by name: "sphere", "torus", "moon", "star", "heart",
// "mammoth", "shark", "horse" (phase 0) or "horse:<phase>".
// Error(InvalidArgument) naming the known shapes otherwise.
TriangleMesh generated_shape(const std::string& name);
std::vector<std::string> generated_shape_names();

}  // namespace swarmcl
