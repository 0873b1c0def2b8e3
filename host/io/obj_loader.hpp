// Wavefront OBJ files as obstacle meshes (tinyobjloader parses; make_mesh
// validates).  Only vertices and faces are read; polygons are triangulated,
// materials, normals and texture coordinates are ignored.
#pragma once
#include <string>

#include "shapes/triangle_mesh.hpp"

namespace swarmcl {

// Error(Io) when the file cannot be read; Error(Parse) naming "path:line" for
// a vertex with a NaN/Inf or missing coordinate, a face index out of range or
// zero, or what tinyobjloader rejects; Error(InvalidArgument) from make_mesh
// for a mesh without a single non-degenerate triangle.  Degenerate triangles
// are skipped (`skipped` receives how many).
TriangleMesh load_obj(const std::string& path, size_t* skipped = nullptr);

// The same from the text of an OBJ file; `name` is used in messages.
TriangleMesh parse_obj(const std::string& text, const std::string& name = "<obj>", size_t* skipped = nullptr);

}  // namespace swarmcl
