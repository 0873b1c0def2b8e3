// path_model_advance (SWCL_BW = 1: one agent per work-item, any local field)
// and path_model_advance_w (SWCL_BW = SWCL_W consecutive agents per
// work-item, CPU devices, baked local field; launch ceil(n / SWCL_W)): one
// body, so the same arithmetic in the same order at every width.  Included
// by path_model.cl once per width.
#include "wide/width.inc.cl"

__kernel void SWCL_KERNEL(path_model_advance)(__global float4* pos, __global float4* vel, __global const uint* ids,
                                              uint n, float dt, float t, uint step, NOISE_PARAMS,
                                              __global const float4* dirs, int4 dims, float4 origin_h,
                                              __global const uint* group_end, uint ngroups,
                                              __global const float* params, __global const float* phi,
                                              __global const float4* world_extra, uint dirs_stride,
                                              __global const float4* vl, float4 vl_min, float4 vl_cell,
                                              int4 vl_dims) {
    const uint base = get_global_id(0) * SWCL_BW;
    if (base >= n) return;
#ifdef SWCL_WORLDS
    // World get_global_id(1) of a swarm of worlds, n agents each: its
    // agents, its parameter and noise blocks and noise boundaries, its row of world_extra and its
    // direction fields (dirs_stride 0: one set for every world, same goals).
    const size_t world = get_global_id(1), world_base = world * n;
    pos += world_base;
    vel += world_base;
    ids += world_base;
    params += world * PATH_FLOATS;
    noise_block += world * NOISE_BLOCK_FLOATS;
    noise_prims += world * 2u * NOISE_B_UINT(NOISE_SLOT_NPRIMS);  // its boundaries' rounding follows its noise.scale
    world_extra += world;
    dirs += world * dirs_stride;
#endif
    // The model's parameter block (models/path_params.cpp lays it out; the
    // host defines PATH_<KEY> as each parameter's slot): s0 and the lamp
    // (lamp.w: its radius, 0 when it is off).  world_extra: what the host
    // computes from the parameters (x: 1 / (A goal_falloff), 0 without the
    // ramp; y, z: cos, sin of the lamp's angle).
    const float4 extra = world_extra[0];
    const float inv_falloff_cost = extra.x;
    const float2 lamp_turn = (float2)(extra.y, extra.z);
    const float s0 = params[PATH_SPEED];
    const float4 lamp = (float4)(params[PATH_LAMP_CENTER], params[PATH_LAMP_CENTER + 1], params[PATH_LAMP_CENTER + 2],
                                 params[PATH_LAMP_ENABLED] != 0.0f ? params[PATH_LAMP_RADIUS] : 0.0f);
    const float4 lamp_pull = (float4)(params[PATH_LAMP_PROBABILITY], params[PATH_LAMP_SPEED], lamp_turn.x, lamp_turn.y);
    const float lamp_keep = params[PATH_LAMP_KEEP_OUT];
    // The lamp's draws are keyed by the noise seed (the noise block's).
    const ulong noise_seed = NOISE_B_SEED();
    swcl_bf px, py, pz;
    SWCL_BFN(path_load_xyz)(pos, base, n, &px, &py, &pz);
    swcl_bf vx, vy, vz;
#if PATH_BAKED
    SWCL_BFN(noise_baked_sample)(vl, vl_min, vl_cell, vl_dims, px, py, pz, &vx, &vy, &vz);
#elif PATH_MESH  // width 1 only
    path_noise_mesh(NOISE_ARGS, phi, dims, origin_h, px, py, pz, t, &vx, &vy, &vz);
#else  // the agent id matters to the random noises only (width 1)
    NOISE_VELOCITY_B(px, py, pz, t, ids[base], step, &vx, &vy, &vz);
#endif
    const size_t cells = (size_t)dims.x * dims.y * dims.z;
    // Per lane: the agent's group (groups own consecutive id ranges,
    // group_end), the global field there, and the optional goal ramp (host:
    // goal_falloff; d.w is the cost C, 0 in the goal).
#define PATH_VG_LANE_(k)                                                                                     \
    {                                                                                                        \
        const uint agent = ids[SWCL_BLANE_ID(base, k, n)];                                                   \
        uint g = 0;                                                                                          \
        while (g + 1 < ngroups && agent >= group_end[g]) ++g;                                                \
        const float4 d = path_trilinear(dirs + g * cells, dims, origin_h,                                    \
                                        (float3)(SWCL_BLANE(px, k), SWCL_BLANE(py, k), SWCL_BLANE(pz, k)));  \
        const float kk = inv_falloff_cost > 0.0f ? s0 * fmin(1.0f, d.w * inv_falloff_cost) : s0;            \
        SWCL_BLANE(vx, k) += kk * d.x;                                                                       \
        SWCL_BLANE(vy, k) += kk * d.y;                                                                       \
        SWCL_BLANE(vz, k) += kk * d.z;                                                                       \
        if (lamp.w > 0.0f) {                                                                                 \
            const float3 pl = path_lamp_pull(lamp, lamp_pull, lamp_keep, noise_seed, agent, step,                 \
                                             (float3)(SWCL_BLANE(px, k), SWCL_BLANE(py, k), SWCL_BLANE(pz, k))); \
            SWCL_BLANE(vx, k) += pl.x;                                                                       \
            SWCL_BLANE(vy, k) += pl.y;                                                                       \
            SWCL_BLANE(vz, k) += pl.z;                                                                       \
        }                                                                                                    \
    }
    SWCL_BEACH_LANE(PATH_VG_LANE_)
#undef PATH_VG_LANE_
    SWCL_BFN(path_store)(vel, base, n, vx, vy, vz);
    SWCL_BFN(path_store)(pos, base, n, px + vx * dt, py + vy * dt, pz + vz * dt);
}
