// Noise fields and the field model.
#include <cstring>
#include <mutex>
#include <optional>

#include "capi_common.hpp"
#include "capi_noise.hpp"
#include "capi_obstacle.hpp"
#include "fields/noise_field.hpp"
#include "models/field_model.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace swarmcl::capi {

NoiseConfig noise_config_from(const swcl_noise_desc& d) {
    NoiseConfig c;
    require(d.type >= SWCL_NOISE_CURL && d.type <= SWCL_NOISE_GAUSSIAN,
            "noise type " + std::to_string(int(d.type)) + " is not one of CURL, PERLIN, WHITE, GAUSSIAN");
    c.type = NoiseType(int(d.type));
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

swcl_field_model_desc swcl_field_model_desc_default(void) {
    swcl_field_model_desc d;
    std::memset(&d, 0, sizeof(d));
    const FieldModelConfig c;
    d.struct_size = sizeof(d);
    d.noise = swcl_noise_desc_default();
    d.has_goal = 0;
    d.goal_radius = c.goal_radius;
    d.goal_speed = c.goal_speed;
    d.goal_falloff = c.goal_falloff;
    d.min_distance = c.min_distance;
    return d;
}

swcl_status swcl_swarm_field_set_model(swcl_swarm swarm, const swcl_field_model_desc* desc) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_struct_size(desc, sizeof(swcl_field_model_desc), "desc");
        check_struct_size(&desc->noise, sizeof(swcl_noise_desc), "desc->noise");
        FieldModelConfig c;
        c.noise = noise_config_from(desc->noise);
        c.has_goal = desc->has_goal != 0;
        for (int a = 0; a < 3; ++a) c.goal[a] = desc->goal[a];
        c.goal_radius = desc->goal_radius;
        c.goal_speed = desc->goal_speed;
        c.goal_falloff = desc->goal_falloff;
        c.min_distance = desc->min_distance;
        s.set_behavior(std::make_shared<FieldModel>(s, std::move(c)));
    });
}

swcl_status swcl_swarm_clear_model(swcl_swarm swarm) {
    return with_swarm(__func__, swarm, [&](Swarm& s) { s.set_behavior(nullptr); });
}

swcl_status swcl_swarm_take_step_stats(swcl_swarm swarm, swcl_step_stats* out) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_struct_size(out, sizeof(swcl_step_stats), "out");
        swcl_step_stats r;
        std::memset(&r, 0, sizeof(r));
        r.struct_size = sizeof(r);
        r.agents = s.agent_count();
        std::optional<StepStats> st;
        st = s.take_step_stats();
        if (st) {
            r.mde_moved_last = st->mde_moved_last;
            r.mde_moved_total = st->mde_moved_total;
            r.steps = st->steps;
        }
        *out = r;
    });
}

}  // extern "C"
