// swarmcl — tests/noise_test_kernels.cl
// Thin test kernels over kernels/lib/{philox,perlin,curl_noise}.cl: each writes
// what a check on the host compares with tests/reference/noise_reference.hpp.
#include "lib/curl_noise.cl"

__kernel void t_philox(__global const uint4* ctr, __global const uint2* key, __global uint4* out)
{
    size_t i = get_global_id(0);
    out[i] = philox4x32_10(ctr[i], key[i]);
}

/* agent id = global id */
__kernel void t_random(ulong seed, uint step, uint stream,
                       __global uint4* raw, __global float4* uni, __global float4* gauss)
{
    uint i = (uint)get_global_id(0);
    raw[i] = swcl_rand_u4(seed, i, step, stream, 0u);
    uni[i] = swcl_rand_uniform4(seed, i, step, stream);
    gauss[i] = swcl_rand_gauss4(seed, i, step, stream);
}

/* out = (dn/dx, dn/dy, dn/dz, n); seeded with offset o unless use_seed == 0 */
__kernel void t_perlin3(__global const float4* p, uint4 o, int use_seed, __global float4* out)
{
    size_t i = get_global_id(0);
    swcl_vg3 n = use_seed ? swcl_perlin3_seeded(p[i].xyz, o) : swcl_perlin3(p[i].xyz);
    out[i] = (float4)(n.g, n.v);
}

__kernel void t_perlin4(__global const float4* p, uint4 o, int use_seed,
                        __global float* val, __global float4* grad)
{
    size_t i = get_global_id(0);
    swcl_vg4 n = use_seed ? swcl_perlin4_seeded(p[i], o) : swcl_perlin4(p[i]);
    val[i] = n.v; grad[i] = n.g;
}

/* x[i] = (x, y, z, t). mode 0: analytic V, 1: finite-difference V (step h),
 * 2: modulated potential N. out[i].w = 0. */
__kernel void t_curl(__global const float4* x, float scale, float gain, float d0, float time_scale,
                     ulong seed, int timed, __global const float4* prims, uint nprims,
                     int mode, float h, __global float4* out)
{
    size_t i = get_global_id(0);
    swcl_curl_params c = swcl_curl_params_make(scale, gain, d0, time_scale, seed);
    float3 p = x[i].xyz; float t = x[i].w;
    float3 v;
    if (mode == 0)      v = swcl_curl_noise(p, t, timed, c, prims, nprims);
    else if (mode == 1) v = swcl_curl_noise_fd(p, h, t, timed, c, prims, nprims);
    else                v = swcl_curl_noise_potential(p, t, timed, c, prims, nprims);
    out[i] = (float4)(v, 0.0f);
}
