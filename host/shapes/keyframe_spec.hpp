// A keyframe shape of the force model (docs/force-model.md) described by where
// its mesh comes from and how it is placed, turned into a mesh in one place
// for the C API's swcl_keyframe (capi/src/capi_force.cpp) and the scenario
// files' "keyframes" (host/scenario/force_section.cpp).  Building is two
// steps so that each front end checks the placement after the mesh, as its
// messages have always come: keyframe_source_mesh, then placed_keyframe_mesh.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>

#include "shapes/triangle_mesh.hpp"

namespace swarmcl {

struct KeyframeSpec {
    enum class Source { Shape, Mesh, Obj } source = Source::Shape;
    std::string name;  // Shape: a generated shape's name (shape_library.hpp); Obj: the OBJ file
    // Mesh: the caller's arrays (packed xyz, 3 indices per triangle), read
    // while building only.
    const float* vertices = nullptr;
    size_t vertex_count = 0;
    const uint32_t* triangles = nullptr;
    size_t triangle_count = 0;
    float scale = 1.0f;  // uniform, about the origin
    Vec3f offset{};      // added after scaling
};

// The described mesh before placement; Error from generated_shape, make_mesh
// or load_obj as they give it.
TriangleMesh keyframe_source_mesh(const KeyframeSpec& spec);

// `source` scaled by spec.scale, then moved by spec.offset.
TriangleMesh placed_keyframe_mesh(const KeyframeSpec& spec, const TriangleMesh& source);

}  // namespace swarmcl
