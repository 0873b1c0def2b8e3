#include "shapes/obstacle_spec.hpp"

#include "core/error.hpp"
#include "io/obj_loader.hpp"

namespace swarmcl {

TriangleMesh obstacle_mesh(const ObstacleSpec& o) {
    switch (o.kind) {
        case ObstacleSpec::Kind::Box: return box_mesh(o.center, o.half_extents);
        case ObstacleSpec::Kind::Sphere: return sphere_mesh(o.center, o.radius, 24, 48);
        case ObstacleSpec::Kind::Cylinder: return cylinder_mesh(o.center, o.radius, o.height, 48);
        case ObstacleSpec::Kind::Mesh: return make_mesh(o.vertices, o.vertex_count, o.indices, o.triangle_count);
        case ObstacleSpec::Kind::Obj: {
            TriangleMesh m = load_obj(o.path);
            return o.place ? transformed(m, o.scale, o.offset) : m;
        }
    }
    fail(Status::InvalidArgument, "unknown obstacle kind");
}

}  // namespace swarmcl
