// The local behaviour of the curl-noise paper (§4 and §6, Eq. 9 without the
// global path field): each agent's velocity is the noise field at its position
// plus, outside an optional goal sphere, a pull towards the goal at speed s0
// (optionally ramped up over a falloff distance);
// then p += v dt (explicit Euler, the paper's position update).
#include "noise_field.cl"

__kernel void field_model_advance(__global float4* pos, __global float4* vel, __global const uint* ids,
                                  uint n, float dt, float t, uint step, NOISE_PARAMS, float4 goal,
                                  float goal_speed, float goal_falloff) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const NoiseField f = NOISE_MAKE();
    const float3 p = pos[i].xyz;
    float3 v = noise_velocity(&f, p, t, ids[i], step);
    // goal.w: goal radius, negative when there is no goal.
    if (goal.w >= 0.0f) {
        const float3 to_goal = goal.xyz - p;
        const float dist = length(to_goal);
        // The pull grows from 0 on the goal sphere to s0 over goal_falloff
        // metres (0: at once, the paper's V_g); a gradual pull does not
        // pile insects up on the sphere.
        if (dist > goal.w && dist > 0.0f) {
            const float ramp = goal_falloff > 0.0f ? fmin(1.0f, (dist - goal.w) / goal_falloff) : 1.0f;
            v += goal_speed * ramp * to_goal / dist;
        }
    }
    vel[i] = (float4)(v, 0.0f);
    pos[i] = (float4)(p + v * dt, 0.0f);
}
