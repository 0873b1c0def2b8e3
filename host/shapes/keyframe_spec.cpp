#include "shapes/keyframe_spec.hpp"

#include "core/error.hpp"
#include "io/obj_loader.hpp"
#include "shapes/shape_library.hpp"

namespace swarmcl {

TriangleMesh keyframe_source_mesh(const KeyframeSpec& k) {
    switch (k.source) {
        case KeyframeSpec::Source::Shape: return generated_shape(k.name);
        case KeyframeSpec::Source::Mesh: return make_mesh(k.vertices, k.vertex_count, k.triangles, k.triangle_count);
        case KeyframeSpec::Source::Obj: return load_obj(k.name);
    }
    fail(Status::InvalidArgument, "unknown keyframe source");
}

TriangleMesh placed_keyframe_mesh(const KeyframeSpec& k, const TriangleMesh& source) {
    return transformed(source, {k.scale, k.scale, k.scale}, k.offset);
}

}  // namespace swarmcl
