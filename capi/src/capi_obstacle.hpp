// swcl_obstacle, the C API's one obstacle type, -> what a model takes: a
// TriangleMesh (the path model, the force model's mesh obstacles) or an
// analytic Boundary (the noise field's boundaries, the force model's Eq. 8-9
// obstacles).
#pragma once
#include <string>

#include "fields/noise_field.hpp"
#include "shapes/triangle_mesh.hpp"
#include "swarmcl/swarmcl.h"

namespace swarmcl::capi {

// Error(status, "<what>: ...") for a bad obstacle (NaN, degenerate mesh,
// unreadable or malformed OBJ file, unknown type).
TriangleMesh obstacle_mesh(const swcl_obstacle& o, const std::string& what);

// SPHERE, BOX and (where allow_plane) PLANE as an analytic Boundary;
// Error(InvalidArgument, "<what>: ...") for any other type.
Boundary obstacle_boundary(const swcl_obstacle& o, const std::string& what, bool allow_plane);

}  // namespace swarmcl::capi
