// A mesh obstacle described by its kind and parameters, turned into a
// TriangleMesh in one place for every front end: the C API's swcl_obstacle
// (capi/src/capi_obstacle.cpp) and the scenario files' "obstacles" of the path
// and force models (host/scenario/obstacle_section.cpp).  The front ends
// check their own input (with their own messages) before building.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "shapes/triangle_mesh.hpp"

namespace swarmcl {

struct ObstacleSpec {
    enum class Kind { Box, Sphere, Cylinder, Mesh, Obj } kind = Kind::Box;
    Vec3f center{};        // Box, Sphere; Cylinder: the centre of its base
    Vec3f half_extents{};  // Box
    float radius = 0.0f;   // Sphere, Cylinder
    float height = 0.0f;   // Cylinder
    // Mesh: the caller's arrays (packed xyz, 3 indices per triangle), read
    // while building only.
    const float* vertices = nullptr;
    size_t vertex_count = 0;
    const uint32_t* indices = nullptr;
    size_t triangle_count = 0;
    std::string path;  // Obj: the OBJ file
    // Obj: scale then offset applied to the loaded mesh when `place` is set
    // (scenario files always place; the C API loads the file as it is).
    bool place = false;
    Vec3f scale{1.0f, 1.0f, 1.0f}, offset{};
};

// Tessellations of the primitives: spheres 24 rings x 48 segments, cylinders
// 48 segments.  Error from make_mesh / load_obj as they give it.
TriangleMesh obstacle_mesh(const ObstacleSpec& spec);

}  // namespace swarmcl
