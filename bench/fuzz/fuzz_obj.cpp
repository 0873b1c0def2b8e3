// OBJ obstacle meshes (host/io/obj_loader.cpp: tinyobjloader, then our checks
// and make_mesh).
#include <cmath>
#include <cstdlib>

#include "fuzz_target.hpp"
#include "io/obj_loader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    return swarmcl::fuzz::expect_error_or_value([&] {
        size_t skipped = 0;
        const swarmcl::TriangleMesh m = swarmcl::parse_obj(swarmcl::fuzz::bytes_of(data, size), "fuzz.obj", &skipped);
        // What a returned mesh promises (the SDF and the force model index with it).
        if (m.triangles.empty()) std::abort();
        for (const auto& v : m.vertices)
            for (int a = 0; a < 3; ++a)
                if (!std::isfinite(v[a])) std::abort();
        for (const auto& t : m.triangles)
            for (uint32_t i : t)
                if (i >= m.vertices.size()) std::abort();
    });
}
