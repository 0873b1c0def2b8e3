// The curl-noise paper's governing field (Eq. 9, §6): each agent moves by
//   V = curl N (boundary-aware curl noise, Eq. 1-3; boundaries include the
//       obstacle meshes through their signed distance grid)
//     + s0 * (-grad C / |grad C|) (the global field, Eq. 8, sampled trilinearly)
// then p += V dt; minimum distance enforcement runs after (min_distance.cl).
// Built per noise configuration like noise_field.cl, plus -DPATH_MESH=1 when
// obstacle meshes shape the curl noise (the curl noise is then assembled
// here from curl_noise.cl's pieces, the mesh last).
#include "lib/noise_field.cl"

#ifndef PATH_MESH
#define PATH_MESH 0
#endif
// -DPATH_BAKED=1: the mesh-aware curl noise was baked onto a grid of nodes
// (path_noise_bake) and is read back trilinearly (noise_baked_sample_s).
#ifndef PATH_BAKED
#define PATH_BAKED 0
#endif

// Trilinear read of a cell-centred float4 grid (origin_h: min corner, cell
// edge), clamped to its border.
static inline float4 path_trilinear(__global const float4* grid, int4 dims, float4 origin_h, float3 p) {
    const float3 u = clamp((p - origin_h.xyz) / origin_h.w - (float3)(0.5f), (float3)(0.0f),
                           convert_float3(dims.xyz - (int3)(1)));
    const int3 i0 = min(convert_int3(u), dims.xyz - (int3)(2));
    const float3 w = u - convert_float3(i0);
    const int sy = dims.x, sz = dims.x * dims.y;
    __global const float4* c = grid + (i0.x + sy * i0.y + sz * i0.z);
    const float4 x00 = mix(c[0], c[1], w.x), x10 = mix(c[sy], c[sy + 1], w.x);
    const float4 x01 = mix(c[sz], c[sz + 1], w.x), x11 = mix(c[sz + sy], c[sz + sy + 1], w.x);
    return mix(mix(x00, x10, w.y), mix(x01, x11, w.y), w.z);
}

#if PATH_MESH
// The mesh distance as a boundary of Eq. 2 (curl_noise.cl's plug-in): d, its
// gradient and Hessian from the tricubic B-spline of the cell-centred signed
// distance grid, a C^2 interpolant (so curl N stays continuous and exactly
// divergence-free; the B-spline smooths edges by about one cell).
static inline void path_bspline(float t, float* w, float* dw, float* ddw) {
    const float s = 1.0f - t, t2 = t * t, t3 = t2 * t;
    w[0] = s * s * s / 6.0f;
    w[1] = (3.0f * t3 - 6.0f * t2 + 4.0f) / 6.0f;
    w[2] = (-3.0f * t3 + 3.0f * t2 + 3.0f * t + 1.0f) / 6.0f;
    w[3] = t3 / 6.0f;
    dw[0] = -0.5f * s * s;
    dw[1] = 1.5f * t2 - 2.0f * t;
    dw[2] = -1.5f * t2 + t + 0.5f;
    dw[3] = 0.5f * t2;
    ddw[0] = s; ddw[1] = 3.0f * t - 2.0f; ddw[2] = 1.0f - 3.0f * t; ddw[3] = t;
}

static inline swcl_dist path_mesh_dist(__global const float* phi, int4 dims, float4 origin_h, float3 p) {
    const float3 u = (p - origin_h.xyz) / origin_h.w - (float3)(0.5f);
    const float3 f = floor(u);
    const int3 i0 = convert_int3(f);
    float wx[4], dwx[4], ddwx[4], wy[4], dwy[4], ddwy[4], wz[4], dwz[4], ddwz[4];
    path_bspline(u.x - f.x, wx, dwx, ddwx);
    path_bspline(u.y - f.y, wy, dwy, ddwy);
    path_bspline(u.z - f.z, wz, dwz, ddwz);
    float d = 0, gx = 0, gy = 0, gz = 0, hxx = 0, hyy = 0, hzz = 0, hxy = 0, hxz = 0, hyz = 0;
    for (int c = 0; c < 4; ++c) {
        const int z = clamp(i0.z - 1 + c, 0, dims.z - 1);
        for (int b = 0; b < 4; ++b) {
            const int y = clamp(i0.y - 1 + b, 0, dims.y - 1);
            __global const float* row = phi + (size_t)dims.x * (y + (size_t)dims.y * z);
            float r = 0, rx = 0, rxx = 0;
            for (int a = 0; a < 4; ++a) {
                const float v = row[clamp(i0.x - 1 + a, 0, dims.x - 1)];
                r += wx[a] * v; rx += dwx[a] * v; rxx += ddwx[a] * v;
            }
            d += wy[b] * wz[c] * r;
            gx += wy[b] * wz[c] * rx;
            gy += dwy[b] * wz[c] * r;
            gz += wy[b] * dwz[c] * r;
            hxx += wy[b] * wz[c] * rxx;
            hyy += ddwy[b] * wz[c] * r;
            hzz += wy[b] * ddwz[c] * r;
            hxy += dwy[b] * wz[c] * rx;
            hxz += wy[b] * dwz[c] * rx;
            hyz += dwy[b] * dwz[c] * r;
        }
    }
    const float ih = 1.0f / origin_h.w;
    swcl_dist s;
    s.d = d;
    s.g = (float3)(gx, gy, gz) * ih;
    s.hd = (float3)(hxx, hyy, hzz) * (ih * ih);
    s.ho = (float3)(hyz, hxz, hxy) * (ih * ih);
    return s;
}

// V_l at (x, y, z): curl noise (NOISE_KIND == NOISE_CURL, analytic
// derivatives) with every analytic boundary, then the mesh (Eq. 2 once more).
static inline void path_noise_mesh(NOISE_PARAMS, __global const float* phi, int4 dims, float4 origin_h, float x, float y,
                            float z, float t, float* vx, float* vy, float* vz) {
    const float scale = NOISE_B(NOISE_SCALE), gain = NOISE_B(NOISE_GAIN), d0 = NOISE_B(NOISE_BOUNDARY_DISTANCE);
    swcl_pj N;
    swcl_noise_potential_s(x, y, z, t, NOISE_TIMED, 1.0f / scale, gain, NOISE_B(NOISE_SLOT_INV_TIME_SCALE),
                           NOISE_B_OFF(0), NOISE_B_OFF(1), NOISE_B_OFF(2), &N);
    swcl_modulate_prims_s(&N, x, y, z, d0, noise_prims, 0u, NOISE_B_UINT(NOISE_SLOT_NPRIMS));
    // The B-spline reaches 2 cells: farther than d0 + 2 sqrt(3) cells from
    // the mesh, Eq. 2 is the identity; skip the 64 taps.
    const float3 p = (float3)(x, y, z);
    const float3 u = clamp((p - origin_h.xyz) / origin_h.w, (float3)(0.0f), convert_float3(dims.xyz - (int3)(1)));
    const int3 c = convert_int3(u);
    if (phi[c.x + dims.x * (c.y + dims.y * c.z)] < d0 + 3.5f * origin_h.w) {
        float3 psi;
        swcl_mat3 J;
        swcl_pj_get(&N, &psi, &J);
        swcl_modulate(path_mesh_dist(phi, dims, origin_h, p), d0, &psi, &J);
        swcl_pj_set(&N, psi, J);
    }
    swcl_pj_curl(&N, scale, vx, vy, vz);
}

// Bakes path_noise_mesh onto the nodes vl_min + (i, j, k) * vl_cell (static noise).
__kernel void path_noise_bake(NOISE_PARAMS, __global const float* phi, int4 dims, float4 origin_h,
                              float4 vl_min, float4 vl_cell, int4 vl_dims, __global float4* out) {
    const uint i = get_global_id(0);
    const uint n = (uint)(vl_dims.x * vl_dims.y * vl_dims.z);
    if (i >= n) return;
    const uint nx = (uint)vl_dims.x, ny = (uint)vl_dims.y;
    float vx, vy, vz;
    path_noise_mesh(NOISE_ARGS, phi, dims, origin_h, vl_min.x + vl_cell.x * (float)(i % nx),
                    vl_min.y + vl_cell.y * (float)((i / nx) % ny), vl_min.z + vl_cell.z * (float)(i / (nx * ny)),
                    0.0f, &vx, &vy, &vz);
    out[i] = (float4)(vx, vy, vz, 0.0f);
}

// Rebakes the nodes box_lo + [0, box_dims) only, in place (a chasing target
// moved: Eq. 2 is the identity beyond d0 of the ball, so the other nodes keep
// their values).  The same node arithmetic as path_noise_bake: bitwise a full bake.
__kernel void path_noise_rebake_box(NOISE_PARAMS, __global const float* phi, int4 dims, float4 origin_h,
                                    float4 vl_min, float4 vl_cell, int4 vl_dims, int4 box_lo, int4 box_dims,
                                    __global float4* out) {
    const uint j = get_global_id(0);
    const uint n = (uint)(box_dims.x * box_dims.y * box_dims.z);
    if (j >= n) return;
    const uint bx = (uint)box_dims.x, by = (uint)box_dims.y;
    const uint ix = (uint)box_lo.x + j % bx, iy = (uint)box_lo.y + (j / bx) % by, iz = (uint)box_lo.z + j / (bx * by);
    const uint nx = (uint)vl_dims.x, ny = (uint)vl_dims.y;
    const uint i = ix + nx * (iy + ny * iz);
    float vx, vy, vz;
    path_noise_mesh(NOISE_ARGS, phi, dims, origin_h, vl_min.x + vl_cell.x * (float)(i % nx),
                    vl_min.y + vl_cell.y * (float)((i / nx) % ny), vl_min.z + vl_cell.z * (float)(i / (nx * ny)),
                    0.0f, &vx, &vy, &vz);
    out[i] = (float4)(vx, vy, vz, 0.0f);
}
#endif

// Positive phototaxis (curl-noise paper §7: "probabilistically added a small
// magnitude of speed towards the lamp holder for each insect"): with
// probability lamp_pull.x (a Philox uniform per agent and step) the insect
// gets lamp_pull.y m/s towards the lamp centre lamp.xyz, turned by the angle
// (cos, sin) = lamp_pull.zw about the vertical axis, counter-clockwise seen
// from +z (our light-compass offset); the radial part fades by Eq. 3's ramp within lamp_keep of the
// bulb (radius lamp.w).  Host reference: tests/test_path_field.cpp.
#define SWCL_STREAM_PHOTOTAXIS 24u
SWCL_INLINE float3 path_lamp_pull(float4 lamp, float4 lamp_pull, float lamp_keep, ulong seed, uint agent, uint step,
                                  float3 p) {
    const float u = swcl_u01_co(swcl_rand_u4(seed, agent, step, SWCL_STREAM_PHOTOTAXIS, 0u).x);
    if (!(u < lamp_pull.x)) return (float3)(0.0f);
    const float3 r = lamp.xyz - p;
    const float dist = length(r);
    if (!(dist > 0.0f)) return (float3)(0.0f);
    const float3 radial = r / dist;
    const float hl = sqrt(r.x * r.x + r.y * r.y);
    const float3 tangent = hl > 0.0f ? (float3)(r.y / hl, -r.x / hl, 0.0f) : (float3)(0.0f);  // z x (p - lamp)
    const float fade = swcl_ramp(fmax(dist - lamp.w, 0.0f) / lamp_keep);
    return lamp_pull.y * (lamp_pull.z * fade * radial + lamp_pull.w * tangent);
}

// Agent i's xyz and its velocity and position stores, at the bodies' widths:
// float4 loads and stores at width 1, lib/noise_field.cl's lane loads and
// stores at SWCL_W.
SWCL_INLINE void path_load_xyz_s(__global const float4* p, uint i, uint n, float* x, float* y, float* z) {
    const float4 v = p[i];
    *x = v.x; *y = v.y; *z = v.z;
}
SWCL_INLINE void path_store_s(__global float4* o, uint i, uint n, float a, float b, float c) {
    o[i] = (float4)(a, b, c, 0.0f);
}

// path_model_advance: every configuration; path_model_advance_w: SWCL_W
// agents per work-item, CPU devices with a baked local field or a noise
// the module's wide path covers (NOISE_WIDE: NoiseField::width() > 1;
// not the mesh-aware procedural noise).  One body,
// wide/path_model_advance.inc.cl.
#define SWCL_BW 1
#include "wide/path_model_advance.inc.cl"
#undef SWCL_BW

#if (PATH_BAKED || !PATH_MESH) && defined(NOISE_WIDE)
SWCL_INLINE void path_load_xyz_w(__global const float4* p, uint base, uint n, swcl_fw* x, swcl_fw* y, swcl_fw* z) {
    noise_load_xyz_w((__global const float*)p, base, n, x, y, z);
}
SWCL_INLINE void path_store_w(__global float4* o, uint base, uint n, swcl_fw a, swcl_fw b, swcl_fw c) {
    noise_store_w((__global float*)o, base, n, a, b, c);
}
#define SWCL_BW SWCL_W
#include "wide/path_model_advance.inc.cl"
#undef SWCL_BW
#endif
