// The field model (the curl-noise paper's local field, docs/field-model.md).
#include <cstddef>
#include <cstring>

#include "capi_common.hpp"
#include "capi_noise.hpp"
#include "models/field_model.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

extern "C" {

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
    d.max_speed = c.max_speed;
    return d;
}

swcl_status swcl_swarm_field_set_model(swcl_swarm swarm, const swcl_field_model_desc* desc) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        // Callers built before max_speed pass the smaller struct.
        check_struct_size(desc, offsetof(swcl_field_model_desc, max_speed), "desc");
        check_struct_size(&desc->noise, sizeof(swcl_noise_desc), "desc->noise");
        FieldModelConfig c;
        c.noise = noise_config_from(desc->noise);
        c.has_goal = desc->has_goal != 0;
        for (int a = 0; a < 3; ++a) c.goal[a] = desc->goal[a];
        c.goal_radius = desc->goal_radius;
        c.goal_speed = desc->goal_speed;
        c.goal_falloff = desc->goal_falloff;
        c.min_distance = desc->min_distance;
        if (desc->struct_size >= offsetof(swcl_field_model_desc, max_speed) + sizeof(float)) c.max_speed = desc->max_speed;
        s.set_behavior(std::make_shared<FieldModel>(s, std::move(c)));
    });
}

}  // extern "C"
