// A noise field as the swarm models use it: the four noise functions of the
// data-driven noise paper (§4.2.1) — curl, Perlin vector, white, Gaussian —
// evaluated procedurally, or a curl/Perlin field baked onto a grid and read
// back by trilinear interpolation (the curl-noise paper precomputes its field,
// §5.3).  The host packs the parameters (host/fields/noise_field.cpp).
#ifndef SWCL_NOISE_FIELD_CL
#define SWCL_NOISE_FIELD_CL
#include "curl_noise.cl"

#define NOISE_CURL 0
#define NOISE_PERLIN 1
#define NOISE_WHITE 2
#define NOISE_GAUSSIAN 3

// Kernel arguments of a noise field, in this order (NoiseField::set_args):
//   type, flags (bit 0 time-varying, bit 1 finite differences, bit 2 baked),
//   shape = (scale, gain, d0, 1/time_scale), fd step, seed, the three Perlin
//   channel offsets, boundary primitives, the baked grid and its placement.
#define NOISE_PARAMS int noise_type, int noise_flags, float4 noise_shape, float noise_fd_step, \
    ulong noise_seed, uint4 noise_off0, uint4 noise_off1, uint4 noise_off2, \
    __global const float4* noise_prims, uint noise_nprims, \
    __global const float4* noise_baked, float4 noise_bake_min, float4 noise_bake_cell, int4 noise_bake_dims

#define NOISE_FLAG_TIMED 1
#define NOISE_FLAG_FD 2
#define NOISE_FLAG_BAKED 4

typedef struct {
    int type, flags;
    swcl_curl_params curl;
    float fd_step;
    ulong seed;
    __global const float4* prims;
    uint nprims;
    __global const float4* baked;
    float4 bake_min, bake_inv_cell;
    int4 bake_dims;
} NoiseField;

#define NOISE_MAKE() noise_make(noise_type, noise_flags, noise_shape, noise_fd_step, noise_seed, \
    noise_off0, noise_off1, noise_off2, noise_prims, noise_nprims, noise_baked, noise_bake_min, \
    noise_bake_cell, noise_bake_dims)

inline NoiseField noise_make(int type, int flags, float4 shape, float fd_step, ulong seed, uint4 off0,
                             uint4 off1, uint4 off2, __global const float4* prims, uint nprims,
                             __global const float4* baked, float4 bake_min, float4 bake_cell,
                             int4 bake_dims) {
    NoiseField f;
    f.type = type;
    f.flags = flags;
    f.curl.scale = shape.x;
    f.curl.inv_scale = 1.0f / shape.x;
    f.curl.gain = shape.y;
    f.curl.d0 = shape.z;
    f.curl.inv_time_scale = shape.w;
    f.curl.off[0] = off0;
    f.curl.off[1] = off1;
    f.curl.off[2] = off2;
    f.fd_step = fd_step;
    f.seed = seed;
    f.prims = prims;
    f.nprims = nprims;
    f.baked = baked;
    f.bake_min = bake_min;
    f.bake_inv_cell = (float4)(1.0f) / bake_cell;
    f.bake_dims = bake_dims;
    return f;
}

// Perlin vector noise P(x) = gain (P1, P2, P3)(x / scale) (noise paper
// §4.2.1), used as a velocity as given: boundaries (Eq. 2) shape the curl
// potential only.
inline float3 noise_perlin_vector(const NoiseField* f, float3 x, float t) {
    float3 psi;
    swcl_mat3 J;
    swcl_noise_potential(x, t, f->flags & NOISE_FLAG_TIMED, f->curl, &psi, &J);
    return psi;
}

// Trilinear read of the baked grid, clamped to its border outside.
inline float3 noise_baked_sample(const NoiseField* f, float3 x) {
    const float3 u = clamp((x - f->bake_min.xyz) * f->bake_inv_cell.xyz, (float3)(0.0f),
                           convert_float3(f->bake_dims.xyz - (int3)(1)));
    const int3 i0 = min(convert_int3(floor(u)), f->bake_dims.xyz - (int3)(2));
    const float3 w = u - convert_float3(i0);
    const int sx = 1, sy = f->bake_dims.x, sz = f->bake_dims.x * f->bake_dims.y;
    __global const float4* c = f->baked + (i0.x + sy * i0.y + sz * i0.z);
    const float4 x00 = mix(c[0], c[sx], w.x);
    const float4 x10 = mix(c[sy], c[sy + sx], w.x);
    const float4 x01 = mix(c[sz], c[sz + sx], w.x);
    const float4 x11 = mix(c[sz + sy], c[sz + sy + sx], w.x);
    return mix(mix(x00, x10, w.y), mix(x01, x11, w.y), w.z).xyz;
}

// The noise velocity (m/s) at x and time t for agent `agent` at step `step`.
// Curl and Perlin depend on (x, t); white and Gaussian on (seed, agent, step)
// only (Philox, so the same on every device and in any agent order).
inline float3 noise_velocity(const NoiseField* f, float3 x, float t, uint agent, uint step) {
    if (f->flags & NOISE_FLAG_BAKED) return noise_baked_sample(f, x);
    switch (f->type) {
        case NOISE_PERLIN: return noise_perlin_vector(f, x, t);
        case NOISE_WHITE: {
            // Uniform in [-gain, gain] per axis: zero mean, variance gain^2 / 3.
            const float4 w = swcl_rand_uniform4(f->seed, agent, step, SWCL_STREAM_WHITE_NOISE);
            return f->curl.gain * (2.0f * w.xyz - (float3)(1.0f));
        }
        case NOISE_GAUSSIAN:
            // lambda sqrt(-2 log W1) sin(2 pi W2) with lambda = gain (§4.2.1).
            return f->curl.gain * swcl_rand_gauss4(f->seed, agent, step, SWCL_STREAM_GAUSSIAN_NOISE).xyz;
        default: {
            const int timed = f->flags & NOISE_FLAG_TIMED;
            if (f->flags & NOISE_FLAG_FD)
                return swcl_curl_noise_fd(x, f->fd_step, t, timed, f->curl, f->prims, f->nprims);
            return swcl_curl_noise(x, t, timed, f->curl, f->prims, f->nprims);
        }
    }
}

// Samples the field at a batch of points; point i is agent i for the random
// noise types.
__kernel void noise_sample(__global const float4* points, uint n, float t, uint step, NOISE_PARAMS,
                           __global float4* out) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const NoiseField f = NOISE_MAKE();
    out[i] = (float4)(noise_velocity(&f, points[i].xyz, t, i, step), 0.0f);
}

// Bakes the procedural field (flags without BAKED) onto the grid nodes
// min + (i, j, k) * cell.
__kernel void noise_bake(NOISE_PARAMS, __global float4* out) {
    const uint i = get_global_id(0);
    const uint n = (uint)(noise_bake_dims.x * noise_bake_dims.y * noise_bake_dims.z);
    if (i >= n) return;
    const NoiseField f = NOISE_MAKE();
    const uint nx = (uint)noise_bake_dims.x, ny = (uint)noise_bake_dims.y;
    const float3 x = noise_bake_min.xyz +
                     noise_bake_cell.xyz * (float3)((float)(i % nx), (float)((i / nx) % ny), (float)(i / (nx * ny)));
    out[i] = (float4)(noise_velocity(&f, x, 0.0f, i, 0u), 0.0f);
}
#endif
