// field_model_advance (SWCL_BW = 1: one agent per work-item) and
// field_model_advance_w (SWCL_BW = SWCL_W consecutive agents per work-item,
// CPU devices; launch ceil(n / SWCL_W)): one body, so the same arithmetic in
// the same order at every width.  Included by field_model.cl once per width.
#include "wide/width.inc.cl"

__kernel void SWCL_KERNEL(field_model_advance)(__global float4* pos, __global float4* vel, __global const uint* ids,
                                               uint n, float dt, float t, uint step, NOISE_PARAMS,
                                               __global const float* params) {
    const uint base = get_global_id(0) * SWCL_BW;
    if (base >= n) return;
#ifdef SWCL_WORLDS
    // World get_global_id(1) of a swarm of worlds, n agents each
    // (lib/grid_common.cl): its agents, its parameter and noise blocks and
    // its noise boundaries (its walls at its own domain).
    const size_t world = get_global_id(1), world_base = world * n;
    pos += world_base;
    vel += world_base;
    ids += world_base;
    params += world * FIELD_FLOATS;
    noise_block += world * NOISE_BLOCK_FLOATS;
    noise_prims += world * 2u * NOISE_B_UINT(NOISE_SLOT_NPRIMS);
#endif
    // The model's parameter block (models/field_params.cpp lays it out; the
    // host defines FIELD_<KEY> as each parameter's slot).  goal.w: the goal
    // radius, negative when there is no goal.
    const float4 goal = (float4)(params[FIELD_GOAL_CENTER], params[FIELD_GOAL_CENTER + 1],
                                 params[FIELD_GOAL_CENTER + 2],
                                 params[FIELD_HAS_GOAL] != 0.0f ? params[FIELD_GOAL_RADIUS] : -1.0f);
    const float goal_speed = params[FIELD_GOAL_SPEED], goal_falloff = params[FIELD_GOAL_FALLOFF];
    __global float* pp = (__global float*)pos;  // NOISE_AT: see lib/noise_field.cl
    swcl_bf px, py, pz;
    SWCL_BFN(noise_load_xyz)(pp, base, n, &px, &py, &pz);
#if defined(NOISE_KIND) && NOISE_KIND != NOISE_WHITE && NOISE_KIND != NOISE_GAUSSIAN
    const uint agent = 0u;  // only the random noises depend on the agent id
#else
    const uint agent = ids[base];  // width 1 only: the random noises have no wide path
#endif
    swcl_bf vx, vy, vz;
    NOISE_VELOCITY_B(px, py, pz, t, agent, step, &vx, &vy, &vz);
    if (goal.w >= 0.0f) {
        const swcl_bf gx = goal.x - px, gy = goal.y - py, gz = goal.z - pz;
        const swcl_bf dist = sqrt(gx * gx + gy * gy + gz * gz);
        // The pull grows from 0 on the goal sphere to s0 over goal_falloff
        // metres (0: at once, the paper's V_g); a gradual pull does not
        // pile insects up on the sphere.
        const swcl_bf ramp = goal_falloff > 0.0f ? fmin((swcl_bf)(1.0f), (dist - goal.w) / goal_falloff)
                                                 : (swcl_bf)(1.0f);
        const swcl_bf k = select((swcl_bf)(0.0f), goal_speed * ramp / dist, (dist > goal.w) & (dist > 0.0f));
        vx += k * gx; vy += k * gy; vz += k * gz;
    }
    // max_speed > 0: a faster agent is slowed to it (0: no limit, the paper's).
    const float max_speed = params[FIELD_MAX_SPEED];
    if (max_speed > 0.0f) {
        const swcl_bf speed = sqrt(vx * vx + vy * vy + vz * vz);
        const swcl_bf k = select((swcl_bf)(1.0f), max_speed / speed, speed > max_speed);
        vx *= k; vy *= k; vz *= k;
    }
    SWCL_BFN(noise_store)((__global float*)vel, base, n, vx, vy, vz);
    SWCL_BFN(noise_store)(pp, base, n, px + vx * dt, py + vy * dt, pz + vz * dt);
}
