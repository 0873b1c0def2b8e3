// noise_sample (SWCL_BW = 1) and noise_sample_w (SWCL_BW = SWCL_W
// consecutive points per work-item, CPU devices; launch ceil(n / SWCL_W)):
// samples the field at a batch of points (float4, w ignored); point i is
// agent i for the random noise types (width 1 only).  Included by
// noise_field.cl once per width.
#include "wide/width.inc.cl"

__kernel void SWCL_KERNEL(noise_sample)(__global const float4* points, uint n, float t, uint step, NOISE_PARAMS,
                                        __global float4* out) {
    const uint base = get_global_id(0) * SWCL_BW;
    if (base >= n) return;
    __global const float* p = (__global const float*)points;
    swcl_bf x, y, z;
    SWCL_BFN(noise_load_xyz)(p, base, n, &x, &y, &z);
    swcl_bf vx, vy, vz;
    NOISE_VELOCITY_B(x, y, z, t, base, step, &vx, &vy, &vz);
    SWCL_BFN(noise_store)((__global float*)out, base, n, vx, vy, vz);
}
