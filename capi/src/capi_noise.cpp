// Noise fields: descriptors and sampling (docs/noise.md).
#include <cstring>

#include "capi_common.hpp"
#include "capi_noise.hpp"
#include "capi_obstacle.hpp"
#include "fields/noise_field.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace swarmcl::capi {

NoiseConfig noise_config_from(const swcl_noise_desc& d) {
    NoiseConfig c;
    const uint32_t type = enum_bits(d.type);  // a C caller's value may be any int
    require(type <= SWCL_NOISE_GAUSSIAN,
            "noise type " + c_enum_text(type) + " is not one of CURL, PERLIN, WHITE, GAUSSIAN");
    c.type = NoiseType(type);
    c.scale = d.scale;
    c.gain = d.gain;
    c.seed = d.seed;
    c.time_scale = d.time_scale;
    c.boundary_distance = d.boundary_distance;
    c.domain_walls = d.domain_walls != 0;
    for (int a = 0; a < 3; ++a) {
        c.region_min[a] = d.region_min[a];
        c.region_max[a] = d.region_max[a];
        c.bake_resolution[a] = d.bake_resolution[a];
    }
    require(d.boundaries != nullptr || d.boundary_count == 0,
            "noise boundaries is NULL but boundary_count is " + std::to_string(d.boundary_count));
    require(d.boundary_count <= 4096, "noise boundary_count above 4096");
    for (uint32_t i = 0; i < d.boundary_count; ++i)
        c.boundaries.push_back(obstacle_boundary(d.boundaries[i], "noise boundaries[" + std::to_string(i) + "]", true));
    c.baked = d.baked != 0;
    c.finite_difference = d.finite_difference != 0;
    c.fd_step = d.fd_step;
    return c;
}

}  // namespace swarmcl::capi

extern "C" {

swcl_noise_desc swcl_noise_desc_default(void) {
    swcl_noise_desc d;
    std::memset(&d, 0, sizeof(d));
    const NoiseConfig c;
    d.struct_size = sizeof(d);
    d.type = SWCL_NOISE_CURL;
    d.scale = c.scale;
    d.gain = c.gain;
    d.time_scale = c.time_scale;
    d.boundary_distance = c.boundary_distance;
    for (int a = 0; a < 3; ++a) d.bake_resolution[a] = c.bake_resolution[a];
    return d;
}

swcl_status swcl_noise_sample(swcl_context context, const swcl_noise_desc* desc, const float* points,
                              size_t count, float time, uint32_t step, float* out_xyz) {
    return guarded(__func__, [&] {
        check_struct_size(desc, sizeof(swcl_noise_desc), "desc");
        auto ctx = contexts().get(context.id);
        NoiseField field(*ctx, noise_config_from(*desc));
        field.sample(points, count, time, step, out_xyz);
    });
}

}  // extern "C"
