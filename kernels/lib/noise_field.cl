// A noise field as the swarm models use it: the four noise functions of the
// data-driven noise paper (§4.2.1) — curl, Perlin vector, white, Gaussian —
// evaluated procedurally, or a curl/Perlin field baked onto a grid and read
// back by trilinear interpolation (the curl-noise paper precomputes its field,
// §5.3).  The host packs the parameters (host/fields/noise_field.cpp).
// Functions only: the models include it, noise_field.cl holds the noise
// kernels.
#ifndef SWCL_NOISE_FIELD_CL
#define SWCL_NOISE_FIELD_CL
#include "lib/curl_noise.cl"

#define NOISE_CURL 0
#define NOISE_PERLIN 1
#define NOISE_WHITE 2
#define NOISE_GAUSSIAN 3

// Kernel arguments of a noise field (NoiseField::set_args): its parameter
// block, the boundary primitives and the baked grid.  The block holds the
// noise table's device rows at the slots NOISE_<KEY> (fields/noise_params.cpp;
// NoiseField::defines passes them: NOISE_TYPE, NOISE_SCALE, NOISE_GAIN,
// NOISE_BOUNDARY_DISTANCE, NOISE_FD_STEP), then, from NOISE_FLOATS on, what
// the host derives from them (NoiseField::write_block, same order):
//   flags (bit 0 time-varying, bit 1 finite differences, bit 2 baked),
//   1/time_scale (0: static), the seed (low, high 32 bits), the three Perlin
//   channel offsets (uint4 each), the number of primitives, and the baked
//   grid's min corner, node spacing (float4 each) and nodes per axis (int4).
// Integers are bit-cast into the float slots.
#define NOISE_PARAMS __global const float *noise_block, __global const float4 *noise_prims, \
    __global const float4 *noise_baked
#define NOISE_ARGS noise_block, noise_prims, noise_baked
#define NOISE_SLOT_FLAGS (NOISE_FLOATS + 0)
#define NOISE_SLOT_INV_TIME_SCALE (NOISE_FLOATS + 1)
#define NOISE_SLOT_SEED (NOISE_FLOATS + 2)
#define NOISE_SLOT_OFFSETS (NOISE_FLOATS + 4)
#define NOISE_SLOT_NPRIMS (NOISE_FLOATS + 16)
#define NOISE_SLOT_BAKE_MIN (NOISE_FLOATS + 17)
#define NOISE_SLOT_BAKE_CELL (NOISE_FLOATS + 21)
#define NOISE_SLOT_BAKE_DIMS (NOISE_FLOATS + 25)
#define NOISE_BLOCK_FLOATS (NOISE_FLOATS + 29)

// Reads of the block.
#define NOISE_B(slot) noise_block[slot]
#define NOISE_B_UINT(slot) as_uint(noise_block[slot])
#define NOISE_B_F4(slot) vload4(0, noise_block + (slot))
#define NOISE_B_U4(slot) as_uint4(vload4(0, noise_block + (slot)))
#define NOISE_B_I4(slot) as_int4(vload4(0, noise_block + (slot)))
#define NOISE_B_SEED() ((ulong)NOISE_B_UINT(NOISE_SLOT_SEED) | ((ulong)NOISE_B_UINT(NOISE_SLOT_SEED + 1) << 32))
#define NOISE_B_OFF(k) NOISE_B_U4(NOISE_SLOT_OFFSETS + 4 * (k))

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

#define NOISE_MAKE() noise_make(NOISE_ARGS)

SWCL_INLINE NoiseField noise_make(NOISE_PARAMS) {
    NoiseField f;
    f.type = as_int(NOISE_B(NOISE_TYPE));
    f.flags = as_int(NOISE_B(NOISE_SLOT_FLAGS));
    f.curl.scale = NOISE_B(NOISE_SCALE);
    f.curl.inv_scale = 1.0f / f.curl.scale;
    f.curl.gain = NOISE_B(NOISE_GAIN);
    f.curl.d0 = NOISE_B(NOISE_BOUNDARY_DISTANCE);
    f.curl.inv_time_scale = NOISE_B(NOISE_SLOT_INV_TIME_SCALE);
    f.curl.off[0] = NOISE_B_OFF(0);
    f.curl.off[1] = NOISE_B_OFF(1);
    f.curl.off[2] = NOISE_B_OFF(2);
    f.fd_step = NOISE_B(NOISE_FD_STEP);
    f.seed = NOISE_B_SEED();
    f.prims = noise_prims;
    f.nprims = NOISE_B_UINT(NOISE_SLOT_NPRIMS);
    f.baked = noise_baked;
    f.bake_min = NOISE_B_F4(NOISE_SLOT_BAKE_MIN);
    f.bake_inv_cell = (float4)(1.0f) / NOISE_B_F4(NOISE_SLOT_BAKE_CELL);
    f.bake_dims = NOISE_B_I4(NOISE_SLOT_BAKE_DIMS);
    return f;
}

// Perlin vector noise P(x) = gain (P1, P2, P3)(x / scale) (noise paper
// §4.2.1), used as a velocity as given: boundaries (Eq. 2) shape the curl
// potential only.
SWCL_INLINE float3 noise_perlin_vector(const NoiseField* f, float3 x, float t) {
    float3 psi;
    swcl_mat3 J;
    swcl_noise_potential(x, t, f->flags & NOISE_FLAG_TIMED, f->curl, &psi, &J);
    return psi;
}

// Trilinear read of the baked grid, clamped to its border outside.
SWCL_INLINE float3 noise_baked_sample(const NoiseField* f, float3 x) {
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
SWCL_INLINE float3 noise_velocity(const NoiseField* f, float3 x, float t, uint agent, uint step) {
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

// ---- specialised scalar path ------------------------------------------------
//
// The host builds this file once per noise configuration with
//   -DNOISE_KIND=k      NOISE_CURL, NOISE_PERLIN, NOISE_WHITE, NOISE_GAUSSIAN,
//                       or NOISE_KIND_BAKED (a baked grid, trilinear)
//   -DNOISE_TIMED=0|1   4D (time-varying) Perlin
//   -DNOISE_FD=0|1      finite-difference curl (a check; generic path)
//   -DNOISE_WALLS=0|1   prims[0] is the domain box interior (6 walls)
//   -DNOISE_OBSTACLES=0|1  further primitives follow (a loop over them)
// so the hot path has no runtime switch on the type or flags and, for the
// common cases (no boundary or domain walls only), no loop either: then
// everything is straight-line scalar code that PoCL vectorises across
// work-items. Without NOISE_KIND the runtime switch above is used (the
// kernel arguments are the same either way).
#define NOISE_KIND_BAKED 4
#ifndef NOISE_TIMED
#define NOISE_TIMED 0
#endif
#ifndef NOISE_FD
#define NOISE_FD 0
#endif
#ifndef NOISE_WALLS
#define NOISE_WALLS 0
#endif
#ifndef NOISE_OBSTACLES
#define NOISE_OBSTACLES 0
#endif

// Trilinear read of the baked grid (float4 nodes), clamped to its border
// outside: scalar, branch free.
SWCL_INLINE void noise_baked_sample_s(__global const float4* baked, float4 bmin, float4 bcell, int4 dims,
                                      float x, float y, float z, float* vx, float* vy, float* vz) {
    const float fx = (float)(dims.x - 1), fy = (float)(dims.y - 1), fz = (float)(dims.z - 1);
    float ux = (x - bmin.x) * (1.0f / bcell.x), uy = (y - bmin.y) * (1.0f / bcell.y),
          uz = (z - bmin.z) * (1.0f / bcell.z);
    ux = ux > 0.0f ? (ux < fx ? ux : fx) : 0.0f;   // NaN-free inputs (checked on the host)
    uy = uy > 0.0f ? (uy < fy ? uy : fy) : 0.0f;
    uz = uz > 0.0f ? (uz < fz ? uz : fz) : 0.0f;
    int ix = (int)ux, iy = (int)uy, iz = (int)uz;   // u >= 0: truncation is floor
    ix = ix < dims.x - 2 ? ix : dims.x - 2;
    iy = iy < dims.y - 2 ? iy : dims.y - 2;
    iz = iz < dims.z - 2 ? iz : dims.z - 2;
    const float wx = ux - (float)ix, wy = uy - (float)iy, wz = uz - (float)iz;
    const int sy = 4 * dims.x, sz = 4 * dims.x * dims.y;
    __global const float* c = (__global const float*)baked + 4 * (ix + dims.x * (iy + dims.y * iz));
#define NOISE_TRI(k)                                                                   \
    {                                                                                  \
        const float x00 = c[k] + (c[4 + k] - c[k]) * wx;                               \
        const float x10 = c[sy + k] + (c[sy + 4 + k] - c[sy + k]) * wx;                \
        const float x01 = c[sz + k] + (c[sz + 4 + k] - c[sz + k]) * wx;                \
        const float x11 = c[sz + sy + k] + (c[sz + sy + 4 + k] - c[sz + sy + k]) * wx; \
        const float y0 = x00 + (x10 - x00) * wy, y1 = x01 + (x11 - x01) * wy;          \
        r##k = y0 + (y1 - y0) * wz;                                                    \
    }
    float r0, r1, r2;
    NOISE_TRI(0) NOISE_TRI(1) NOISE_TRI(2)
#undef NOISE_TRI
    *vx = r0; *vy = r1; *vz = r2;
}

#if defined(NOISE_KIND) && (NOISE_KIND == NOISE_KIND_BAKED || \
    ((NOISE_KIND == NOISE_CURL || NOISE_KIND == NOISE_PERLIN) && !NOISE_FD))
#define NOISE_SCALAR 1
#else
#define NOISE_SCALAR 0
#endif

// The noise velocity at (x, y, z), time t, agent `agent`, step `step`, into
// (*vx, *vy, *vz); same value as noise_velocity().
#define NOISE_VELOCITY_S(x, y, z, t, agent, step, vx, vy, vz) \
    noise_velocity_s(NOISE_ARGS, x, y, z, t, agent, step, vx, vy, vz)

SWCL_INLINE void noise_velocity_s(NOISE_PARAMS, float x, float y, float z, float t, uint agent, uint step,
                                  float* vx, float* vy, float* vz) {
#if NOISE_SCALAR && NOISE_KIND == NOISE_KIND_BAKED
    noise_baked_sample_s(noise_baked, NOISE_B_F4(NOISE_SLOT_BAKE_MIN), NOISE_B_F4(NOISE_SLOT_BAKE_CELL),
                         NOISE_B_I4(NOISE_SLOT_BAKE_DIMS), x, y, z, vx, vy, vz);
#elif NOISE_SCALAR
    const float scale = NOISE_B(NOISE_SCALE), gain = NOISE_B(NOISE_GAIN), d0 = NOISE_B(NOISE_BOUNDARY_DISTANCE);
    swcl_pj N;
    swcl_noise_potential_s(x, y, z, t, NOISE_TIMED, 1.0f / scale, gain, NOISE_B(NOISE_SLOT_INV_TIME_SCALE),
                           NOISE_B_OFF(0), NOISE_B_OFF(1), NOISE_B_OFF(2), &N);
#if NOISE_KIND == NOISE_PERLIN
    // Perlin vector noise: psi itself, no boundaries (noise_perlin_vector).
    *vx = N.p0; *vy = N.p1; *vz = N.p2;
#else
#if NOISE_WALLS
    {
        __global const float* w = (__global const float*)noise_prims;
        swcl_modulate_box_interior_s(&N, x, y, z, w[0], w[1], w[2], w[4], w[5], w[6], 1.0f / d0);
    }
#endif
#if NOISE_OBSTACLES
    swcl_modulate_prims_s(&N, x, y, z, d0, noise_prims, NOISE_WALLS ? 1u : 0u, NOISE_B_UINT(NOISE_SLOT_NPRIMS));
#endif
    swcl_pj_curl(&N, scale, vx, vy, vz);
#endif
#else
    const NoiseField f = NOISE_MAKE();
    const float3 v = noise_velocity(&f, (float3)(x, y, z), t, agent, step);
    *vx = v.x; *vy = v.y; *vz = v.z;
#endif
}

// Component c of float4 element i of a buffer seen as floats.
#define NOISE_AT(p, i, c) (p)[4 * (size_t)(i) + (c)]

// ---- width-typed helpers for the per-width bodies (kernels/wide/) ----------
//
// A body written once for any width (docs/architecture.md, "Kernel layout")
// calls SWCL_BFN(noise_load_xyz), SWCL_BFN(noise_store) and NOISE_VELOCITY_B:
// at width 1 the scalar helpers here, at SWCL_W the _w ones below.

// The xyz of float4 element i of p (seen as floats).
SWCL_INLINE void noise_load_xyz_s(__global const float* p, uint i, uint n, float* x, float* y, float* z) {
    *x = NOISE_AT(p, i, 0); *y = NOISE_AT(p, i, 1); *z = NOISE_AT(p, i, 2);
}
// Stores (a, b, c, 0) to float4 element i of o.
SWCL_INLINE void noise_store_s(__global float* o, uint i, uint n, float a, float b, float c) {
    NOISE_AT(o, i, 0) = a; NOISE_AT(o, i, 1) = b; NOISE_AT(o, i, 2) = c; NOISE_AT(o, i, 3) = 0.0f;
}
// The noise velocity at the body's width: noise_velocity_s or _w (which
// ignores agent and step: the random noises have no wide path).
#define NOISE_VELOCITY_B(x, y, z, t, agent, step, vx, vy, vz)                                                    \
    SWCL_BFN(noise_velocity)(NOISE_ARGS, x, y, z, t, agent, step, vx, vy, vz)

// ---- explicit-width path (CPU devices) --------------------------------------
//
// With -DNOISE_WIDTH=8|16 (NoiseField::width(): CPU devices, or
// $SWARMCL_NOISE_WIDTH) and a configuration of the specialised path without
// obstacles, noise_sample_w (and field_model_advance_w) run SWCL_W
// consecutive points per work-item in floatW lanes: the scalar path's
// arithmetic, in the same order (perlin.cl, curl_noise.cl). Launch
// ceil(n / SWCL_W) work-items; the last one clamps its loads to point n - 1
// and stores only the lanes below n.
#if defined(SWCL_W) && NOISE_SCALAR && !NOISE_OBSTACLES
#define NOISE_WIDE 1

// Trilinear blend of the 8 nodes from c (strides sy, sz in nodes).
SWCL_INLINE float4 noise_tri4(__global const float4* c, int sy, int sz, float wx, float wy, float wz) {
    const float4 x00 = c[0] + (c[1] - c[0]) * wx;
    const float4 x10 = c[sy] + (c[sy + 1] - c[sy]) * wx;
    const float4 x01 = c[sz] + (c[sz + 1] - c[sz]) * wx;
    const float4 x11 = c[sz + sy] + (c[sz + sy + 1] - c[sz + sy]) * wx;
    const float4 y0 = x00 + (x10 - x00) * wy, y1 = x01 + (x11 - x01) * wy;
    return y0 + (y1 - y0) * wz;
}

// noise_baked_sample_s on SWCL_W points.
SWCL_INLINE void noise_baked_sample_w(__global const float4* baked, float4 bmin, float4 bcell, int4 dims,
                                      swcl_fw x, swcl_fw y, swcl_fw z, swcl_fw* vx, swcl_fw* vy, swcl_fw* vz) {
    const swcl_fw zero = (swcl_fw)(0.0f);
    const float fx = (float)(dims.x - 1), fy = (float)(dims.y - 1), fz = (float)(dims.z - 1);
    swcl_fw ux = (x - bmin.x) * (1.0f / bcell.x), uy = (y - bmin.y) * (1.0f / bcell.y),
            uz = (z - bmin.z) * (1.0f / bcell.z);
    ux = select(zero, select((swcl_fw)(fx), ux, ux < fx), ux > 0.0f);
    uy = select(zero, select((swcl_fw)(fy), uy, uy < fy), uy > 0.0f);
    uz = select(zero, select((swcl_fw)(fz), uz, uz < fz), uz > 0.0f);
    const swcl_iw ix = min(swcl_cvt_iw(ux), (swcl_iw)(dims.x - 2)), iy = min(swcl_cvt_iw(uy), (swcl_iw)(dims.y - 2)),
                  iz = min(swcl_cvt_iw(uz), (swcl_iw)(dims.z - 2));
    const swcl_fw wx = ux - swcl_cvt_fw(ix), wy = uy - swcl_cvt_fw(iy), wz = uz - swcl_cvt_fw(iz);
    // Per lane: the 8 corner nodes as float4 loads, interpolated as float4
    // (each component as noise_baked_sample_s computes it), then transposed.
    const int sy = dims.x, sz = dims.x * dims.y;
    const swcl_iw b = ix + dims.x * (iy + dims.y * iz);
#define NOISE_TRI_LANE_(k)                                                                               \
    const float4 r_##k = noise_tri4(baked + SWCL_LANE(b, k), sy, sz, SWCL_LANE(wx, k), SWCL_LANE(wy, k), \
                                    SWCL_LANE(wz, k));
    SWCL_EACH_LANE(NOISE_TRI_LANE_)
#undef NOISE_TRI_LANE_
#define NOISE_RX_(k) r_##k.x
#define NOISE_RY_(k) r_##k.y
#define NOISE_RZ_(k) r_##k.z
    *vx = (swcl_fw)(SWCL_LANES(NOISE_RX_));
    *vy = (swcl_fw)(SWCL_LANES(NOISE_RY_));
    *vz = (swcl_fw)(SWCL_LANES(NOISE_RZ_));
#undef NOISE_RX_
#undef NOISE_RY_
#undef NOISE_RZ_
}

// noise_velocity_s on SWCL_W points (curl, Perlin vector or baked).
SWCL_INLINE void noise_velocity_w(NOISE_PARAMS, swcl_fw x, swcl_fw y, swcl_fw z, float t, uint agent, uint step,
                                  swcl_fw* vx, swcl_fw* vy, swcl_fw* vz) {
#if NOISE_KIND == NOISE_KIND_BAKED
    noise_baked_sample_w(noise_baked, NOISE_B_F4(NOISE_SLOT_BAKE_MIN), NOISE_B_F4(NOISE_SLOT_BAKE_CELL),
                         NOISE_B_I4(NOISE_SLOT_BAKE_DIMS), x, y, z, vx, vy, vz);
#else
    const float scale = NOISE_B(NOISE_SCALE), gain = NOISE_B(NOISE_GAIN), d0 = NOISE_B(NOISE_BOUNDARY_DISTANCE);
    swcl_pjw N;
    swcl_noise_potential_w(x, y, z, t, NOISE_TIMED, 1.0f / scale, gain, NOISE_B(NOISE_SLOT_INV_TIME_SCALE),
                           NOISE_B_OFF(0), NOISE_B_OFF(1), NOISE_B_OFF(2), &N);
#if NOISE_KIND == NOISE_PERLIN
    *vx = N.p0; *vy = N.p1; *vz = N.p2;
#else
#if NOISE_WALLS
    {
        __global const float* w = (__global const float*)noise_prims;
        swcl_modulate_box_interior_w(&N, x, y, z, w[0], w[1], w[2], w[4], w[5], w[6], 1.0f / d0);
    }
#endif
    swcl_pjw_curl(&N, scale, vx, vy, vz);
#endif
#endif
}

#define NOISE_VELOCITY_W(x, y, z, t, vx, vy, vz) \
    noise_velocity_w(NOISE_ARGS, x, y, z, t, 0u, 0u, vx, vy, vz)

// The xyz of the SWCL_W points (float4 elements of p, seen as floats) from
// `base` on: whole float16 loads and shuffles, or, in the last work-item,
// single loads with indices clamped to n - 1.
#define NOISE_LOAD_LANE_(k) p[4 * (size_t)min(base + (uint)SWCL_LANE_I(k), n - 1) + c]
SWCL_INLINE swcl_fw noise_load_tail_w(__global const float* p, uint base, uint n, int c) {
    return (swcl_fw)(SWCL_LANES(NOISE_LOAD_LANE_));
}
#undef NOISE_LOAD_LANE_
// Under -DSWCL_OCLGRIND (the Oclgrind check only) always the single loads:
// Oclgrind 21.10 crashed in the vector literals' shuffles (lib/halves.cl).
SWCL_INLINE void noise_load_xyz_w(__global const float* p, uint base, uint n, swcl_fw* x, swcl_fw* y, swcl_fw* z) {
#ifdef SWCL_OCLGRIND
    if (false) {
#else
    if (base + SWCL_W <= n) {
#endif
        __global const float* q = p + 4 * (size_t)base;
        const float16 a0 = vload16(0, q), a1 = vload16(1, q);
#if SWCL_W == 16
        const float16 a2 = vload16(2, q), a3 = vload16(3, q);
        *x = (float16)(a0.s048c, a1.s048c, a2.s048c, a3.s048c);
        *y = (float16)(a0.s159d, a1.s159d, a2.s159d, a3.s159d);
        *z = (float16)(a0.s26ae, a1.s26ae, a2.s26ae, a3.s26ae);
#else
        *x = (float8)(a0.s048c, a1.s048c);
        *y = (float8)(a0.s159d, a1.s159d);
        *z = (float8)(a0.s26ae, a1.s26ae);
#endif
    } else {
        *x = noise_load_tail_w(p, base, n, 0);
        *y = noise_load_tail_w(p, base, n, 1);
        *z = noise_load_tail_w(p, base, n, 2);
    }
}

// Stores (a.k, b.k, c.k, 0) to float4 element base + k of o, for the lanes
// below n: whole float16 stores except in the last work-item.
#define NOISE_STORE_LANE_(k)                                                              \
    if (base + (uint)SWCL_LANE_I(k) < n)                                                  \
        vstore4((float4)(SWCL_LANE(a, k), SWCL_LANE(b, k), SWCL_LANE(c, k), 0.0f),        \
                base + (uint)SWCL_LANE_I(k), o);
#define NOISE_STORE4_(j, k0, k1, k2, k3)                                                  \
    vstore16((float16)(a.s##k0, b.s##k0, c.s##k0, 0.0f, a.s##k1, b.s##k1, c.s##k1, 0.0f,  \
                       a.s##k2, b.s##k2, c.s##k2, 0.0f, a.s##k3, b.s##k3, c.s##k3, 0.0f), \
             j, q);
SWCL_INLINE void noise_store_w(__global float* o, uint base, uint n, swcl_fw a, swcl_fw b, swcl_fw c) {
    if (base + SWCL_W <= n) {
        __global float* q = o + 4 * (size_t)base;
        NOISE_STORE4_(0, 0, 1, 2, 3)
        NOISE_STORE4_(1, 4, 5, 6, 7)
#if SWCL_W == 16
        NOISE_STORE4_(2, 8, 9, a, b)
        NOISE_STORE4_(3, c, d, e, f)
#endif
    } else {
        SWCL_EACH_LANE(NOISE_STORE_LANE_)
    }
}
#undef NOISE_STORE_LANE_
#undef NOISE_STORE4_

#endif
#endif
