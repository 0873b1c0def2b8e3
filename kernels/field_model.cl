// The local behaviour of the curl-noise paper (§4 and §6, Eq. 9 without the
// global path field): each agent's velocity is the noise field at its position
// plus, outside an optional goal sphere, a pull towards the goal at speed s0
// (optionally ramped up over a falloff distance);
// then p += v dt (explicit Euler, the paper's position update).
// Built per noise configuration like noise_field.cl (NOISE_* defines); plain
// scalar code so that PoCL vectorises it across agents.
#include "lib/noise_field.cl"

__kernel void field_model_advance(__global float4* pos, __global float4* vel, __global const uint* ids,
                                  uint n, float dt, float t, uint step, NOISE_PARAMS, float4 goal,
                                  float goal_speed, float goal_falloff) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    __global float* pp = (__global float*)pos;  // NOISE_AT: see noise_field.cl
    const float px = NOISE_AT(pp, i, 0), py = NOISE_AT(pp, i, 1), pz = NOISE_AT(pp, i, 2);
#if defined(NOISE_KIND) && NOISE_KIND != NOISE_WHITE && NOISE_KIND != NOISE_GAUSSIAN
    const uint agent = 0u;  // only the random noises depend on the agent id
#else
    const uint agent = ids[i];
#endif
    float vx, vy, vz;
    NOISE_VELOCITY_S(px, py, pz, t, agent, step, &vx, &vy, &vz);
    // goal.w: goal radius, negative when there is no goal.
    if (goal.w >= 0.0f) {
        const float gx = goal.x - px, gy = goal.y - py, gz = goal.z - pz;
        const float dist = sqrt(gx * gx + gy * gy + gz * gz);
        // The pull grows from 0 on the goal sphere to s0 over goal_falloff
        // metres (0: at once, the paper's V_g); a gradual pull does not
        // pile insects up on the sphere.
        const float ramp = goal_falloff > 0.0f ? fmin(1.0f, (dist - goal.w) / goal_falloff) : 1.0f;
        const float k = (dist > goal.w && dist > 0.0f) ? goal_speed * ramp / dist : 0.0f;
        vx += k * gx; vy += k * gy; vz += k * gz;
    }
    __global float* vp = (__global float*)vel;
    NOISE_AT(vp, i, 0) = vx; NOISE_AT(vp, i, 1) = vy; NOISE_AT(vp, i, 2) = vz; NOISE_AT(vp, i, 3) = 0.0f;
    NOISE_AT(pp, i, 0) = px + vx * dt; NOISE_AT(pp, i, 1) = py + vy * dt; NOISE_AT(pp, i, 2) = pz + vz * dt;
    NOISE_AT(pp, i, 3) = 0.0f;
}

#ifdef NOISE_WIDE
// field_model_advance on SWCL_W consecutive agents per work-item (CPU devices;
// noise_field.cl, explicit-width path): same arithmetic, in the same order.
__kernel void field_model_advance_w(__global float4* pos, __global float4* vel, __global const uint* ids,
                                    uint n, float dt, float t, uint step, NOISE_PARAMS, float4 goal,
                                    float goal_speed, float goal_falloff) {
    const uint base = get_global_id(0) * SWCL_W;
    if (base >= n) return;
    __global float* pp = (__global float*)pos;
    swcl_fw px, py, pz;
    noise_load_xyz_w(pp, base, n, &px, &py, &pz);
    swcl_fw vx, vy, vz;
    NOISE_VELOCITY_W(px, py, pz, t, &vx, &vy, &vz);
    if (goal.w >= 0.0f) {
        const swcl_fw gx = goal.x - px, gy = goal.y - py, gz = goal.z - pz;
        const swcl_fw dist = sqrt(gx * gx + gy * gy + gz * gz);
        const swcl_fw ramp = goal_falloff > 0.0f ? fmin((swcl_fw)(1.0f), (dist - goal.w) / goal_falloff)
                                                 : (swcl_fw)(1.0f);
        const swcl_fw k = select((swcl_fw)(0.0f), goal_speed * ramp / dist, (dist > goal.w) & (dist > 0.0f));
        vx += k * gx; vy += k * gy; vz += k * gz;
    }
    noise_store_w((__global float*)vel, base, n, vx, vy, vz);
    noise_store_w(pp, base, n, px + vx * dt, py + vy * dt, pz + vz * dt);
}
#endif
