// The noise field's kernels: sampling a batch of points (noise_sample, and
// noise_sample_w on CPU devices: lib/noise_field.cl's explicit-width path)
// and baking the procedural field onto a grid (noise_bake).  The field itself
// is lib/noise_field.cl; the host builds this file once per noise
// configuration (host/fields/noise_field.cpp).
#include "lib/noise_field.cl"

// noise_sample (one point per work-item) and, on CPU devices, noise_sample_w
// (SWCL_W points per work-item): one body, wide/noise_sample.inc.cl.
#define SWCL_BW 1
#include "wide/noise_sample.inc.cl"
#undef SWCL_BW
#ifdef NOISE_WIDE
#define SWCL_BW SWCL_W
#include "wide/noise_sample.inc.cl"
#undef SWCL_BW
#endif

// Bakes the procedural field (built without NOISE_KIND_BAKED) onto the grid
// nodes min + (i, j, k) * cell.
__kernel void noise_bake(NOISE_PARAMS, __global float4* out) {
    const uint i = get_global_id(0);
    const int4 noise_bake_dims = NOISE_B_I4(NOISE_SLOT_BAKE_DIMS);
    const uint n = (uint)(noise_bake_dims.x * noise_bake_dims.y * noise_bake_dims.z);
    if (i >= n) return;
    const float4 noise_bake_min = NOISE_B_F4(NOISE_SLOT_BAKE_MIN), noise_bake_cell = NOISE_B_F4(NOISE_SLOT_BAKE_CELL);
    const uint nx = (uint)noise_bake_dims.x, ny = (uint)noise_bake_dims.y;
    const float x = noise_bake_min.x + noise_bake_cell.x * (float)(i % nx);
    const float y = noise_bake_min.y + noise_bake_cell.y * (float)((i / nx) % ny);
    const float z = noise_bake_min.z + noise_bake_cell.z * (float)(i / (nx * ny));
    float vx, vy, vz;
    NOISE_VELOCITY_S(x, y, z, 0.0f, i, 0u, &vx, &vy, &vz);
    __global float* o = (__global float*)out;
    NOISE_AT(o, i, 0) = vx; NOISE_AT(o, i, 1) = vy; NOISE_AT(o, i, 2) = vz; NOISE_AT(o, i, 3) = 0.0f;
}
