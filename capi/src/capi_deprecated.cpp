// The names before 0.2 (swcl_swarm_set_force_model, ...), kept until 1.0 as
// thin calls of the swcl_swarm_<model>_<verb> functions (swarmcl.h,
// "deprecated names").
#include "swarmcl/swarmcl.h"

#if defined(__GNUC__) || defined(__clang__)
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif

extern "C" {

swcl_status swcl_swarm_set_field_model(swcl_swarm swarm, const swcl_field_model_desc* desc) {
    return swcl_swarm_field_set_model(swarm, desc);
}

swcl_status swcl_swarm_set_path_model(swcl_swarm swarm, const swcl_path_model_desc* desc) {
    return swcl_swarm_path_set_model(swarm, desc);
}

swcl_status swcl_swarm_set_path_goals(swcl_swarm swarm, uint32_t group, const swcl_goal* goals, uint32_t goal_count, double* out_seconds) {
    return swcl_swarm_path_set_goals(swarm, group, goals, goal_count, out_seconds);
}

swcl_status swcl_swarm_get_path_info(swcl_swarm swarm, swcl_path_info* out) {
    return swcl_swarm_path_get_info(swarm, out);
}

swcl_status swcl_swarm_set_energy_model(swcl_swarm swarm, swcl_dataset dataset, const swcl_energy_model_desc* desc) {
    return swcl_swarm_energy_set_model(swarm, dataset, desc);
}

swcl_status swcl_swarm_energy_goals(swcl_swarm swarm, int32_t* out_goals, size_t count) {
    return swcl_swarm_energy_get_goals(swarm, out_goals, count);
}

swcl_status swcl_swarm_set_force_model(swcl_swarm swarm, const swcl_force_model_desc* desc) {
    return swcl_swarm_force_set_model(swarm, desc);
}

swcl_status swcl_swarm_set_force_keyframes(swcl_swarm swarm, const swcl_keyframe* keyframes, uint32_t count, uint32_t period) {
    return swcl_swarm_force_set_keyframes(swarm, keyframes, count, period);
}

swcl_status swcl_swarm_set_force_path(swcl_swarm swarm, const float* points, uint32_t count, float speed) {
    return swcl_swarm_force_set_path(swarm, points, count, speed);
}

swcl_status swcl_swarm_get_force_targets(swcl_swarm swarm, float* out_xyz, size_t count) {
    return swcl_swarm_force_get_targets(swarm, out_xyz, count);
}

}  // extern "C"
