// swcl_obstacle (the path section's mesh obstacle) -> TriangleMesh, shared by
// the path model and the force model's mesh obstacles.
#pragma once
#include <string>

#include "shapes/triangle_mesh.hpp"
#include "swarmcl/swarmcl.h"

namespace swarmcl::capi {

// Error(status, "<what>: ...") for a bad obstacle (NaN, degenerate mesh,
// unreadable or malformed OBJ file, unknown type).
TriangleMesh obstacle_mesh(const swcl_obstacle& o, const std::string& what);

}  // namespace swarmcl::capi
