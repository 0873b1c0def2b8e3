// The noise field's kernels: sampling a batch of points (noise_sample, and
// noise_sample_w on CPU devices) and baking the procedural field onto a grid
// (noise_bake).  The field itself is lib/noise_field.cl; the host builds this
// file once per noise configuration (host/fields/noise_field.cpp).
#include "lib/noise_field.cl"

// Samples the field at a batch of points (float4, w ignored); point i is
// agent i for the random noise types.
__kernel void noise_sample(__global const float4* points, uint n, float t, uint step, NOISE_PARAMS,
                           __global float4* out) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    __global const float* p = (__global const float*)points;
    float vx, vy, vz;
    NOISE_VELOCITY_S(NOISE_AT(p, i, 0), NOISE_AT(p, i, 1), NOISE_AT(p, i, 2), t, i, step, &vx, &vy, &vz);
    __global float* o = (__global float*)out;
    NOISE_AT(o, i, 0) = vx; NOISE_AT(o, i, 1) = vy; NOISE_AT(o, i, 2) = vz; NOISE_AT(o, i, 3) = 0.0f;
}

// Bakes the procedural field (built without NOISE_KIND_BAKED) onto the grid
// nodes min + (i, j, k) * cell.
__kernel void noise_bake(NOISE_PARAMS, __global float4* out) {
    const uint i = get_global_id(0);
    const uint n = (uint)(noise_bake_dims.x * noise_bake_dims.y * noise_bake_dims.z);
    if (i >= n) return;
    const uint nx = (uint)noise_bake_dims.x, ny = (uint)noise_bake_dims.y;
    const float x = noise_bake_min.x + noise_bake_cell.x * (float)(i % nx);
    const float y = noise_bake_min.y + noise_bake_cell.y * (float)((i / nx) % ny);
    const float z = noise_bake_min.z + noise_bake_cell.z * (float)(i / (nx * ny));
    float vx, vy, vz;
    NOISE_VELOCITY_S(x, y, z, 0.0f, i, 0u, &vx, &vy, &vz);
    __global float* o = (__global float*)out;
    NOISE_AT(o, i, 0) = vx; NOISE_AT(o, i, 1) = vy; NOISE_AT(o, i, 2) = vz; NOISE_AT(o, i, 3) = 0.0f;
}

#ifdef NOISE_WIDE
// noise_sample on SWCL_W consecutive points per work-item.
__kernel void noise_sample_w(__global const float4* points, uint n, float t, uint step, NOISE_PARAMS,
                             __global float4* out) {
    const uint base = get_global_id(0) * SWCL_W;
    if (base >= n) return;
    __global const float* p = (__global const float*)points;
    swcl_fw x, y, z;
    noise_load_xyz_w(p, base, n, &x, &y, &z);
    swcl_fw vx, vy, vz;
    NOISE_VELOCITY_W(x, y, z, t, &vx, &vy, &vz);
    noise_store_w((__global float*)out, base, n, vx, vy, vz);
}
#endif
