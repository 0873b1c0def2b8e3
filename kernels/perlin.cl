// swarmcl — kernels/perlin.cl
//
// Ken Perlin's improved noise (Perlin 2002, "Improving Noise", SIGGRAPH; the
// noise the curl-noise paper §4 builds P1, P2, P3 from) in float, with its
// ANALYTIC gradient, plus a 4D variant (time as 4th coordinate) and a seed
// scheme for independent potentials. OpenCL C 1.2; no double on the device.
//
//  * permutation: Perlin's 256-entry reference table; indices are masked with
//    & 255, which equals his doubled p[512] table.
//  * fade: f(t) = 6t^5 - 15t^4 + 10t^3,  f'(t) = 30 t^2 (t - 1)^2.
//  * 3D gradients: Perlin's grad(hash, x, y, z) with hash & 15 (12 edge
//    directions of the cube, 4 of them repeated), as vectors.
//  * 4D gradients (swarmcl's choice; Perlin 2002 is 3D only): the 32 vectors
//    with one zero and three +-1 components (tesseract edge midpoints, as in
//    Gustavson's 4D noise). With h = hash & 31: the zero axis is h >> 3, the
//    other three axes in ascending order take the sign of bits 0, 1, 2 of h
//    (bit set -> -1). 4D hash: perm[perm[perm[perm[X]+Y]+Z]+W].
//  * value and gradient are computed together by nested linear
//    interpolation on (value, gradient) pairs: lerp(t(x), a, b) has gradient
//    ga + t (gb - ga) + (b - a) t'(x) e_axis.
//
// Seeds (swarmcl's choice; the papers only say "three Perlin noise functions
// with different random seeds", curl-noise paper §4): a seed and a channel
// give a Philox draw o = philox(ctr=(channel, 0, SWCL_STREAM_PERLIN_OFFSET, 0),
// key=seed). Each 32-bit word translates the domain along one axis by
//     (o >> 24)                 whole lattice cells (0..255; the noise is
//                               256-periodic, so this covers every shift), and
//     (o & 0xffffff) * 2^-24    a fraction of a cell.
// The integer part is added to the integer lattice index (not to the float
// coordinate), so precision is that of the unseeded noise. Shifted copies are
// decorrelated beyond ~1 cell; 2^32 distinct shifts per axis.
// Reference values: noise(3.14, 42, 7) = 0.13691995878400012 (unseeded,
// double); 0 at every integer lattice point (unseeded).
// Plain C++ reference: tests/reference/noise_reference.hpp.

#ifndef SWCL_PERLIN_CL
#define SWCL_PERLIN_CL

#include "philox.cl"

__constant uchar swcl_perm[256] = {
    151,160,137,91,90,15,131,13,201,95,96,53,194,233,7,225,140,36,103,30,69,142,
    8,99,37,240,21,10,23,190,6,148,247,120,234,75,0,26,197,62,94,252,219,203,117,
    35,11,32,57,177,33,88,237,149,56,87,174,20,125,136,171,168,68,175,74,165,71,
    134,139,48,27,166,77,146,158,231,83,111,229,122,60,211,133,230,220,105,92,41,
    55,46,245,40,244,102,143,54,65,25,63,161,1,216,80,73,209,76,132,187,208,89,
    18,169,200,196,135,130,116,188,159,86,164,100,109,198,173,186,3,64,52,217,226,
    250,124,123,5,202,38,147,118,126,255,82,85,212,207,206,59,227,47,16,58,17,182,
    189,28,42,223,183,170,213,119,248,152,2,44,154,163,70,221,153,101,155,167,43,
    172,9,129,22,39,253,19,98,108,110,79,113,224,232,178,185,112,104,218,246,97,
    228,251,34,242,193,238,210,144,12,191,179,162,241,81,51,145,235,249,14,239,
    107,49,192,214,31,181,199,106,157,184,84,204,176,115,121,50,45,127,4,150,254,
    138,236,205,93,222,114,67,29,24,72,243,141,128,195,78,66,215,61,156,180 };

/* Value and gradient of a 3D / 4D noise function. */
typedef struct { float v; float3 g; } swcl_vg3;
typedef struct { float v; float4 g; } swcl_vg4;

inline int swcl_perm_at(int i) { return (int)swcl_perm[i & 255]; }

inline int swcl_hash3(int X, int Y, int Z)
{
    return swcl_perm_at(swcl_perm_at(swcl_perm_at(X) + Y) + Z);
}
inline int swcl_hash4(int X, int Y, int Z, int W)
{
    return swcl_perm_at(swcl_perm_at(swcl_perm_at(swcl_perm_at(X) + Y) + Z) + W);
}

inline float swcl_fade(float t)  { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
inline float swcl_dfade(float t) { return 30.0f * t * t * (t * (t - 2.0f) + 1.0f); }

/* Perlin 2002 grad(hash, x, y, z) written as the gradient vector g, so that
 * grad(hash, x, y, z) = dot(g, (x, y, z)). */
inline float3 swcl_grad3_vec(int h)
{
    h &= 15;
    float3 u = (h < 8) ? (float3)(1.0f, 0.0f, 0.0f) : (float3)(0.0f, 1.0f, 0.0f);
    float3 v = (h < 4) ? (float3)(0.0f, 1.0f, 0.0f)
             : ((h == 12 || h == 14) ? (float3)(1.0f, 0.0f, 0.0f) : (float3)(0.0f, 0.0f, 1.0f));
    return ((h & 1) ? -u : u) + ((h & 2) ? -v : v);
}

/* 4D gradient: zero axis h>>3, signs from bits 0..2 (see header). */
inline float4 swcl_grad4_vec(int h)
{
    h &= 31;
    float s0 = (h & 1) ? -1.0f : 1.0f, s1 = (h & 2) ? -1.0f : 1.0f, s2 = (h & 4) ? -1.0f : 1.0f;
    switch (h >> 3) {
    case 0:  return (float4)(0.0f, s0, s1, s2);
    case 1:  return (float4)(s0, 0.0f, s1, s2);
    case 2:  return (float4)(s0, s1, 0.0f, s2);
    default: return (float4)(s0, s1, s2, 0.0f);
    }
}

/* lerp on (value, gradient) pairs along one axis; t = fade(f_axis), dt = fade'(f_axis). */
inline swcl_vg3 swcl_dlerp3(float t, float dt, int axis, swcl_vg3 a, swcl_vg3 b)
{
    swcl_vg3 r;
    r.v = a.v + t * (b.v - a.v);
    r.g = a.g + t * (b.g - a.g);
    float e = dt * (b.v - a.v);
    if (axis == 0) r.g.x += e; else if (axis == 1) r.g.y += e; else r.g.z += e;
    return r;
}
inline swcl_vg4 swcl_dlerp4(float t, float dt, int axis, swcl_vg4 a, swcl_vg4 b)
{
    swcl_vg4 r;
    r.v = a.v + t * (b.v - a.v);
    r.g = a.g + t * (b.g - a.g);
    float e = dt * (b.v - a.v);
    if (axis == 0) r.g.x += e; else if (axis == 1) r.g.y += e;
    else if (axis == 2) r.g.z += e; else r.g.w += e;
    return r;
}

/* Corner term: value dot(g, f - c), gradient g (the linear part). */
inline swcl_vg3 swcl_corner3(int X, int Y, int Z, int cx, int cy, int cz, float3 f)
{
    swcl_vg3 r;
    r.g = swcl_grad3_vec(swcl_hash3(X + cx, Y + cy, Z + cz));
    r.v = dot(r.g, f - (float3)((float)cx, (float)cy, (float)cz));
    return r;
}
inline swcl_vg4 swcl_corner4(int4 L, int cx, int cy, int cz, int cw, float4 f)
{
    swcl_vg4 r;
    r.g = swcl_grad4_vec(swcl_hash4(L.x + cx, L.y + cy, L.z + cz, L.w + cw));
    r.v = dot(r.g, f - (float4)((float)cx, (float)cy, (float)cz, (float)cw));
    return r;
}

/* Improved noise and its gradient at p, lattice shifted by ioff whole cells. */
inline swcl_vg3 swcl_perlin3_shifted(float3 p, int3 ioff)
{
    float3 fl = floor(p);
    float3 f = p - fl;                      /* exact in float */
    int X = (int)fl.x + ioff.x, Y = (int)fl.y + ioff.y, Z = (int)fl.z + ioff.z;
    float3 u = (float3)(swcl_fade(f.x), swcl_fade(f.y), swcl_fade(f.z));
    float3 du = (float3)(swcl_dfade(f.x), swcl_dfade(f.y), swcl_dfade(f.z));
    swcl_vg3 x00 = swcl_dlerp3(u.x, du.x, 0, swcl_corner3(X, Y, Z, 0, 0, 0, f), swcl_corner3(X, Y, Z, 1, 0, 0, f));
    swcl_vg3 x10 = swcl_dlerp3(u.x, du.x, 0, swcl_corner3(X, Y, Z, 0, 1, 0, f), swcl_corner3(X, Y, Z, 1, 1, 0, f));
    swcl_vg3 x01 = swcl_dlerp3(u.x, du.x, 0, swcl_corner3(X, Y, Z, 0, 0, 1, f), swcl_corner3(X, Y, Z, 1, 0, 1, f));
    swcl_vg3 x11 = swcl_dlerp3(u.x, du.x, 0, swcl_corner3(X, Y, Z, 0, 1, 1, f), swcl_corner3(X, Y, Z, 1, 1, 1, f));
    swcl_vg3 y0 = swcl_dlerp3(u.y, du.y, 1, x00, x10);
    swcl_vg3 y1 = swcl_dlerp3(u.y, du.y, 1, x01, x11);
    return swcl_dlerp3(u.z, du.z, 2, y0, y1);
}

inline swcl_vg4 swcl_perlin4_shifted(float4 p, int4 ioff)
{
    float4 fl = floor(p);
    float4 f = p - fl;
    int4 L = convert_int4(fl) + ioff;
    float4 u = (float4)(swcl_fade(f.x), swcl_fade(f.y), swcl_fade(f.z), swcl_fade(f.w));
    float4 du = (float4)(swcl_dfade(f.x), swcl_dfade(f.y), swcl_dfade(f.z), swcl_dfade(f.w));
    swcl_vg4 zw[4];                          /* index (cz + 2 cw) after the x and y lerps */
    for (int c = 0; c < 4; ++c) {
        int cz = c & 1, cw = c >> 1;
        swcl_vg4 x0 = swcl_dlerp4(u.x, du.x, 0, swcl_corner4(L, 0, 0, cz, cw, f), swcl_corner4(L, 1, 0, cz, cw, f));
        swcl_vg4 x1 = swcl_dlerp4(u.x, du.x, 0, swcl_corner4(L, 0, 1, cz, cw, f), swcl_corner4(L, 1, 1, cz, cw, f));
        zw[c] = swcl_dlerp4(u.y, du.y, 1, x0, x1);
    }
    swcl_vg4 w0 = swcl_dlerp4(u.z, du.z, 2, zw[0], zw[1]);
    swcl_vg4 w1 = swcl_dlerp4(u.z, du.z, 2, zw[2], zw[3]);
    return swcl_dlerp4(u.w, du.w, 3, w0, w1);
}

/* Unseeded noise (Perlin's reference function) with gradient. */
inline swcl_vg3 swcl_perlin3(float3 p) { return swcl_perlin3_shifted(p, (int3)(0)); }
inline swcl_vg4 swcl_perlin4(float4 p) { return swcl_perlin4_shifted(p, (int4)(0)); }

/* Per-seed, per-channel domain offset (see header): a raw Philox draw. */
inline uint4 swcl_perlin_offset(ulong seed, uint channel)
{
    return swcl_rand_u4(seed, channel, 0u, SWCL_STREAM_PERLIN_OFFSET, 0u);
}
inline int4 swcl_offset_cells(uint4 o) { return convert_int4(o >> 24); }
inline float4 swcl_offset_frac(uint4 o) { return convert_float4(o & 0xffffffu) * 0x1.0p-24f; }

/* Seeded noise: value and gradient (d/dp) of noise_seed(p) = noise(p + offset). */
inline swcl_vg3 swcl_perlin3_seeded(float3 p, uint4 o)
{
    return swcl_perlin3_shifted(p + swcl_offset_frac(o).xyz, swcl_offset_cells(o).xyz);
}
inline swcl_vg4 swcl_perlin4_seeded(float4 p, uint4 o)
{
    return swcl_perlin4_shifted(p + swcl_offset_frac(o), swcl_offset_cells(o));
}

#endif /* SWCL_PERLIN_CL */
