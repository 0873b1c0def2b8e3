// swcl_obstacle -> TriangleMesh (capi_obstacle.hpp): checked here, built by
// shapes/obstacle_spec as the scenario files' obstacles are.
#include "capi_obstacle.hpp"

#include <cmath>

#include "capi_common.hpp"
#include "core/error.hpp"
#include "shapes/obstacle_spec.hpp"

namespace swarmcl::capi {

TriangleMesh obstacle_mesh(const swcl_obstacle& o, const std::string& what) {
    const uint32_t type = enum_bits(o.type);  // a C caller's value may be any int
    try {
        if (type != SWCL_OBSTACLE_MESH && type != SWCL_OBSTACLE_OBJ)
            for (int a = 0; a < 3; ++a) require(std::isfinite(o.center[a]), "center must be finite");
        ObstacleSpec spec;
        spec.center = {o.center[0], o.center[1], o.center[2]};
        switch (type) {
            case SWCL_OBSTACLE_MESH:
                spec.kind = ObstacleSpec::Kind::Mesh;
                spec.vertices = o.vertices;
                spec.vertex_count = o.vertex_count;
                spec.indices = o.indices;
                spec.triangle_count = o.triangle_count;
                return swarmcl::obstacle_mesh(spec);
            case SWCL_OBSTACLE_OBJ:
                require(o.path != nullptr && *o.path, "path is NULL or empty");
                spec.kind = ObstacleSpec::Kind::Obj;
                spec.path = o.path;
                return swarmcl::obstacle_mesh(spec);
            case SWCL_OBSTACLE_BOX:
                spec.kind = ObstacleSpec::Kind::Box;
                spec.half_extents = {o.half_extents[0], o.half_extents[1], o.half_extents[2]};
                return swarmcl::obstacle_mesh(spec);
            case SWCL_OBSTACLE_SPHERE:
                require(std::isfinite(o.radius) && o.radius > 0, "sphere radius must be > 0");
                spec.kind = ObstacleSpec::Kind::Sphere;
                spec.radius = o.radius;
                return swarmcl::obstacle_mesh(spec);
            case SWCL_OBSTACLE_CYLINDER:
                require(std::isfinite(o.radius) && o.radius > 0 && std::isfinite(o.height) && o.height > 0,
                        "cylinder radius and height must be > 0");
                spec.kind = ObstacleSpec::Kind::Cylinder;
                spec.radius = o.radius;
                spec.height = o.height;
                return swarmcl::obstacle_mesh(spec);
            case SWCL_OBSTACLE_PLANE:
                fail(Status::InvalidArgument, "a PLANE is not a mesh (only the noise field's boundaries take planes)");
            case SWCL_OBSTACLE_TYPE_MAX_ENUM: break;  // not a type
        }
    } catch (const Error& e) {
        throw Error(e.status(), what + ": " + e.what());
    }
    fail(Status::InvalidArgument, what + ": unknown obstacle type " + c_enum_text(type));
}

Boundary obstacle_boundary(const swcl_obstacle& o, const std::string& what, bool allow_plane) {
    Boundary b;
    const uint32_t type = enum_bits(o.type);
    switch (type) {
        case SWCL_OBSTACLE_SPHERE: b.kind = Boundary::Kind::Sphere; break;
        case SWCL_OBSTACLE_BOX: b.kind = Boundary::Kind::Box; break;
        case SWCL_OBSTACLE_PLANE:
            if (allow_plane) {
                b.kind = Boundary::Kind::Plane;
                break;
            }
            [[fallthrough]];
        default:
            fail(Status::InvalidArgument, what + ": type " + c_enum_text(type) + " is not one of SPHERE, BOX" +
                                              (allow_plane ? ", PLANE" : "") +
                                              " (meshes, OBJ files and cylinders go where a model builds a "
                                              "signed distance grid)");
    }
    for (int a = 0; a < 3; ++a) {
        b.center[a] = o.center[a];
        b.half_extents[a] = o.half_extents[a];
        b.normal[a] = o.normal[a];
    }
    b.radius = o.radius;
    b.offset = o.offset;
    return b;
}

}  // namespace swarmcl::capi
