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

#include "lib/philox.cl"
#include "lib/lanes.cl"

/* Everything on the hot path is always inlined and written in plain scalar
 * floats and ints (no float3, no struct returns, no switch, no private
 * arrays): PoCL's CPU device vectorises a kernel across work-items only when
 * every instruction of its body has a scalar type, and that is also the shape
 * GPUs like. The struct / float3 functions further down are thin wrappers
 * over the scalar cores (*_s), kept for tests and the generic boundary path. */
#include "lib/inline.cl"

/* int, not uchar: a gather of 32-bit words, no zero extension. */
__constant int swcl_perm[256] = {
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

SWCL_INLINE int swcl_perm_at(int i) { return swcl_perm[i & 255]; }

/* Pairs (perm[i], perm[i + 1]) in one word, perm[i] | perm[(i + 1) & 255] << 8:
 * the hash of a lattice cell always needs both neighbours along the next
 * axis, so one gather serves two lookups (7 gathers instead of 14 in 3D, 15
 * instead of 30 in 4D; the same hashes bit for bit).  Made from swcl_perm
 * (above) by a one-line loop; the noise tests check the results against the
 * C++ reference. */
__constant int swcl_perm2[256] = {
    41111,35232,23433,23131,3930,33551,3459,51469,24521,24671,13664,49717,
    59842,2025,57607,36065,9356,26404,7783,17694,36421,2190,25352,9571,
    61477,5616,2581,5898,48663,1726,37894,63380,30967,60024,19434,75,
    6656,50458,16069,24126,64606,56316,52187,30155,9077,2851,8203,14624,
    45369,8625,22561,60760,38381,14485,22328,44631,5294,32020,34941,43912,
    43179,17576,44868,19119,42314,18341,34375,35718,12427,6960,42523,19878,
    37453,40594,59294,21479,28499,58735,31461,15482,54076,34259,59013,56550,
    27100,23657,10588,14121,11831,62766,10485,62504,26356,36710,13967,16694,
    6465,16153,41279,417,55297,20696,18768,53577,19665,33868,48004,53435,
    22992,4697,43282,51369,50376,34756,33415,29826,48244,40892,22175,42070,
    25764,28004,50797,44486,47789,954,16387,13376,55604,58073,64226,31994,
    31612,1403,51717,9930,37670,30355,32374,65406,21247,21842,54357,53204,
    52943,15310,58171,12259,4143,14864,4410,46609,48566,7357,10780,57130,
    47071,43703,54698,30677,63607,39160,664,11266,39468,41882,18083,56646,
    39389,26009,39781,42907,11175,44075,2476,33033,5761,10006,64807,5117,
    25107,27746,28268,20334,29007,57457,59616,45800,47538,28857,26736,55912,
    63194,25078,58465,64484,8955,61986,49650,61121,53998,37074,3216,48908,
    46015,41651,61858,20977,13137,37171,60305,63979,3833,61198,27631,12651,
    49201,54976,8150,46367,51125,27335,40298,47261,21688,52308,45260,29616,
    31091,12921,11570,32557,1151,38404,65174,35582,60554,52716,24013,56925,
    29406,17266,7491,6173,18456,62280,36339,32909,50048,20163,16974,55106,
    15831,39997,46236,38836 };
SWCL_INLINE int swcl_perm2_at(int i) { return swcl_perm2[i & 255]; }
/* The two halves of a pair: perm[i], perm[i + 1]. */
#define SWCL_LO(p) ((p) & 255)
#define SWCL_HI(p) ((p) >> 8)

/* The corner hashes of lattice cell (X, Y, Z) from pair lookups (type T,
 * lookup PAIR: scalar or lanes): the pairs hAA, hBA, hAB, hBB hold
 * perm[perm[perm[X + cx] + Y + cy] + Z + cz] for cz = 0 (LO) and 1 (HI). */
#define SWCL_HASH3_PAIRS(T, PAIR)                                                   \
    const T pX = PAIR(X);                                                           \
    const T A = SWCL_LO(pX) + Y, B = SWCL_HI(pX) + Y;                               \
    const T pA = PAIR(A), pB = PAIR(B);                                             \
    const T AA = SWCL_LO(pA) + Z, AB = SWCL_HI(pA) + Z;                             \
    const T BA = SWCL_LO(pB) + Z, BB = SWCL_HI(pB) + Z;                             \
    const T hAA = PAIR(AA), hBA = PAIR(BA), hAB = PAIR(AB), hBB = PAIR(BB);
/* 4D: Zij = perm[perm[X + cx] + Y + cy] + Z (i = cx, j = cy); the pair Zij_cz
 * at perm[Zij + cz] + W holds the corner hashes for cw = 0 (LO) and 1 (HI). */
#define SWCL_HASH4_PAIRS(T, PAIR)                                                   \
    const T pX = PAIR(X);                                                           \
    const T P0 = SWCL_LO(pX) + Y, P1 = SWCL_HI(pX) + Y;                             \
    const T p0 = PAIR(P0), p1 = PAIR(P1);                                           \
    const T Z00 = SWCL_LO(p0) + Z, Z10 = SWCL_LO(p1) + Z;                           \
    const T Z01 = SWCL_HI(p0) + Z, Z11 = SWCL_HI(p1) + Z;                           \
    const T q00 = PAIR(Z00), q10 = PAIR(Z10), q01 = PAIR(Z01), q11 = PAIR(Z11);     \
    const T Z00_0 = PAIR(SWCL_LO(q00) + W), Z00_1 = PAIR(SWCL_HI(q00) + W);         \
    const T Z10_0 = PAIR(SWCL_LO(q10) + W), Z10_1 = PAIR(SWCL_HI(q10) + W);         \
    const T Z01_0 = PAIR(SWCL_LO(q01) + W), Z01_1 = PAIR(SWCL_HI(q01) + W);         \
    const T Z11_0 = PAIR(SWCL_LO(q11) + W), Z11_1 = PAIR(SWCL_HI(q11) + W);

SWCL_INLINE int swcl_hash3(int X, int Y, int Z)
{
    return swcl_perm_at(swcl_perm_at(swcl_perm_at(X) + Y) + Z);
}
SWCL_INLINE int swcl_hash4(int X, int Y, int Z, int W)
{
    return swcl_perm_at(swcl_perm_at(swcl_perm_at(swcl_perm_at(X) + Y) + Z) + W);
}

SWCL_INLINE float swcl_fade(float t)  { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
SWCL_INLINE float swcl_dfade(float t) { return 30.0f * t * t * (t * (t - 2.0f) + 1.0f); }

/* floor(x) as an int, branch free (the builtin floor carries inf/NaN
 * branches on PoCL). Exact for |x| < 2^31, the range of the int lattice
 * indices anyway. */
SWCL_INLINE int swcl_floor_i(float x)
{
    const int i = (int)x;                 /* truncation toward 0 */
    return ((float)i > x) ? i - 1 : i;
}

/* Perlin 2002 grad(hash, x, y, z) as a vector g, grad = dot(g, (x, y, z)):
 * u = h < 8 ? x : y, v = h < 4 ? y : (h == 12 || h == 14 ? x : z), signs from
 * bits 0 and 1 (set -> -1). u and v are different axes. */
SWCL_INLINE void swcl_grad3_s(int h, float* gx, float* gy, float* gz)
{
    h &= 15;
    const float su = (h & 1) ? -1.0f : 1.0f, sv = (h & 2) ? -1.0f : 1.0f;
    const int vx = (h == 12) | (h == 14);
    *gx = (h < 8) ? su : (vx ? sv : 0.0f);
    *gy = (h < 8) ? ((h < 4) ? sv : 0.0f) : su;
    *gz = (h >= 4 && !vx) ? sv : 0.0f;
}

/* 4D gradient: zero axis h >> 3, the other three in ascending order take the
 * sign of bits 0, 1, 2 (set -> -1). */
SWCL_INLINE void swcl_grad4_s(int h, float* gx, float* gy, float* gz, float* gw)
{
    h &= 31;
    const int z = h >> 3;
    const float s0 = (h & 1) ? -1.0f : 1.0f, s1 = (h & 2) ? -1.0f : 1.0f, s2 = (h & 4) ? -1.0f : 1.0f;
    *gx = (z == 0) ? 0.0f : s0;
    *gy = (z == 0) ? s0 : ((z == 1) ? 0.0f : s1);
    *gz = (z <= 1) ? s1 : ((z == 2) ? 0.0f : s2);
    *gw = (z == 3) ? 0.0f : s2;
}

/* A corner of the 3D lattice: gradient g and value dot(g, d), d = f - corner. */
#define SWCL_CORNER3(h, dx, dy, dz, C)                                        \
    float C##x, C##y, C##z;                                                   \
    swcl_grad3_s((h), &C##x, &C##y, &C##z);                                   \
    const float C##v = C##x * (dx) + C##y * (dy) + C##z * (dz);

/* lerp of (value, gradient) along axis AX: R = A + t (B - A), gradient
 * gA + t (gB - gA) + dt (B - A) e_AX. */
#define SWCL_DLERP3(t, dt, AX, A, B, R)                                       \
    const float R##v = A##v + (t) * (B##v - A##v);                            \
    const float R##x = A##x + (t) * (B##x - A##x) + ((AX) == 0 ? (dt) * (B##v - A##v) : 0.0f); \
    const float R##y = A##y + (t) * (B##y - A##y) + ((AX) == 1 ? (dt) * (B##v - A##v) : 0.0f); \
    const float R##z = A##z + (t) * (B##z - A##z) + ((AX) == 2 ? (dt) * (B##v - A##v) : 0.0f);

/* The 8 corners (gradient . offset) and the x, y, z lerps of value and
 * gradient after SWCL_HASH3_PAIRS, for the scalar core (SWCL_CORNER3,
 * SWCL_DLERP3) and the lanes (the _W macros); result in rv, rx, ry, rz. */
#define SWCL_NOISE3_BODY(CORNER, DLERP) \
    CORNER(SWCL_LO(hAA), x,  y,  z,  c000) \
    CORNER(SWCL_LO(hBA), x1, y,  z,  c100) \
    CORNER(SWCL_LO(hAB), x,  y1, z,  c010) \
    CORNER(SWCL_LO(hBB), x1, y1, z,  c110) \
    CORNER(SWCL_HI(hAA), x,  y,  z1, c001) \
    CORNER(SWCL_HI(hBA), x1, y,  z1, c101) \
    CORNER(SWCL_HI(hAB), x,  y1, z1, c011) \
    CORNER(SWCL_HI(hBB), x1, y1, z1, c111) \
    DLERP(u, du, 0, c000, c100, a00) \
    DLERP(u, du, 0, c010, c110, a10) \
    DLERP(u, du, 0, c001, c101, a01) \
    DLERP(u, du, 0, c011, c111, a11) \
    DLERP(v, dv, 1, a00, a10, b0) \
    DLERP(v, dv, 1, a01, a11, b1) \
    DLERP(w, dw, 2, b0, b1, r)

/* 4D: the 16 corners after SWCL_HASH4_PAIRS (SWCL_H4, below), then the x, y,
 * z and w lerps as the reference's nested lerps; result in rv, rx .. rw. */
#define SWCL_NOISE4_BODY(CORNER, DLERP) \
    CORNER(SWCL_H4(Z00, 0, 0), x,  y,  z,  w,  c0000) \
    CORNER(SWCL_H4(Z10, 0, 0), x1, y,  z,  w,  c1000) \
    CORNER(SWCL_H4(Z01, 0, 0), x,  y1, z,  w,  c0100) \
    CORNER(SWCL_H4(Z11, 0, 0), x1, y1, z,  w,  c1100) \
    CORNER(SWCL_H4(Z00, 1, 0), x,  y,  z1, w,  c0010) \
    CORNER(SWCL_H4(Z10, 1, 0), x1, y,  z1, w,  c1010) \
    CORNER(SWCL_H4(Z01, 1, 0), x,  y1, z1, w,  c0110) \
    CORNER(SWCL_H4(Z11, 1, 0), x1, y1, z1, w,  c1110) \
    CORNER(SWCL_H4(Z00, 0, 1), x,  y,  z,  w1, c0001) \
    CORNER(SWCL_H4(Z10, 0, 1), x1, y,  z,  w1, c1001) \
    CORNER(SWCL_H4(Z01, 0, 1), x,  y1, z,  w1, c0101) \
    CORNER(SWCL_H4(Z11, 0, 1), x1, y1, z,  w1, c1101) \
    CORNER(SWCL_H4(Z00, 1, 1), x,  y,  z1, w1, c0011) \
    CORNER(SWCL_H4(Z10, 1, 1), x1, y,  z1, w1, c1011) \
    CORNER(SWCL_H4(Z01, 1, 1), x,  y1, z1, w1, c0111) \
    CORNER(SWCL_H4(Z11, 1, 1), x1, y1, z1, w1, c1111) \
    DLERP(u, du, 0, c0000, c1000, a000) DLERP(u, du, 0, c0100, c1100, a100) \
    DLERP(u, du, 0, c0010, c1010, a010) DLERP(u, du, 0, c0110, c1110, a110) \
    DLERP(u, du, 0, c0001, c1001, a001) DLERP(u, du, 0, c0101, c1101, a101) \
    DLERP(u, du, 0, c0011, c1011, a011) DLERP(u, du, 0, c0111, c1111, a111) \
    DLERP(v, dv, 1, a000, a100, b00) DLERP(v, dv, 1, a010, a110, b10) \
    DLERP(v, dv, 1, a001, a101, b01) DLERP(v, dv, 1, a011, a111, b11) \
    DLERP(s, ds, 2, b00, b10, e0) DLERP(s, ds, 2, b01, b11, e1) \
    DLERP(q, dq, 3, e0, e1, r)

/* Improved noise and its gradient at p, lattice shifted by (ox, oy, oz) whole
 * cells (scalar core). */
SWCL_INLINE void swcl_perlin3_s(float px, float py, float pz, int ox, int oy, int oz,
                                float* val, float* gx, float* gy, float* gz)
{
    const int ix = swcl_floor_i(px), iy = swcl_floor_i(py), iz = swcl_floor_i(pz);
    const float x = px - (float)ix, y = py - (float)iy, z = pz - (float)iz;   /* exact */
    const int X = ix + ox, Y = iy + oy, Z = iz + oz;
    const float u = swcl_fade(x), v = swcl_fade(y), w = swcl_fade(z);
    const float du = swcl_dfade(x), dv = swcl_dfade(y), dw = swcl_dfade(z);
    const float x1 = x - 1.0f, y1 = y - 1.0f, z1 = z - 1.0f;
    SWCL_HASH3_PAIRS(int, swcl_perm2_at)
    SWCL_NOISE3_BODY(SWCL_CORNER3, SWCL_DLERP3)
    *val = rv; *gx = rx; *gy = ry; *gz = rz;
}

/* 4D: lattice corners and lerps on (value, 4-gradient). */
#define SWCL_CORNER4(h, dx, dy, dz, dw, C)                                    \
    float C##x, C##y, C##z, C##w;                                             \
    swcl_grad4_s((h), &C##x, &C##y, &C##z, &C##w);                            \
    const float C##v = C##x * (dx) + C##y * (dy) + C##z * (dz) + C##w * (dw);
#define SWCL_DLERP4(t, dt, AX, A, B, R)                                       \
    const float R##v = A##v + (t) * (B##v - A##v);                            \
    const float R##x = A##x + (t) * (B##x - A##x) + ((AX) == 0 ? (dt) * (B##v - A##v) : 0.0f); \
    const float R##y = A##y + (t) * (B##y - A##y) + ((AX) == 1 ? (dt) * (B##v - A##v) : 0.0f); \
    const float R##z = A##z + (t) * (B##z - A##z) + ((AX) == 2 ? (dt) * (B##v - A##v) : 0.0f); \
    const float R##w = A##w + (t) * (B##w - A##w) + ((AX) == 3 ? (dt) * (B##v - A##v) : 0.0f);

/* hash of corner (cx, cy, cz, cw) = perm[perm[Zij + cz] + W + cw], with
 * Zij = perm[perm[X+cx]+Y+cy]+Z: Zij_cz is the pair at perm[Zij + cz] + W. */
#define SWCL_H4(ZW, cz, cw) (cw ? SWCL_HI(ZW##_##cz) : SWCL_LO(ZW##_##cz))

SWCL_INLINE void swcl_perlin4_s(float px, float py, float pz, float pw, int ox, int oy, int oz, int ow,
                                float* val, float* gx, float* gy, float* gz, float* gw)
{
    const int ix = swcl_floor_i(px), iy = swcl_floor_i(py), iz = swcl_floor_i(pz), iw = swcl_floor_i(pw);
    const float x = px - (float)ix, y = py - (float)iy, z = pz - (float)iz, w = pw - (float)iw;
    const int X = ix + ox, Y = iy + oy, Z = iz + oz, W = iw + ow;
    const float u = swcl_fade(x), v = swcl_fade(y), s = swcl_fade(z), q = swcl_fade(w);
    const float du = swcl_dfade(x), dv = swcl_dfade(y), ds = swcl_dfade(z), dq = swcl_dfade(w);
    const float x1 = x - 1.0f, y1 = y - 1.0f, z1 = z - 1.0f, w1 = w - 1.0f;
    /* hash4 = perm[perm[perm[perm[X]+Y]+Z]+W] */
    SWCL_HASH4_PAIRS(int, swcl_perm2_at)
    SWCL_NOISE4_BODY(SWCL_CORNER4, SWCL_DLERP4)
    *val = rv; *gx = rx; *gy = ry; *gz = rz; *gw = rw;
}

/* Seeded channel (see header): fraction of the Philox offset added to the
 * coordinate, whole cells to the lattice index. */
SWCL_INLINE float swcl_off_frac(uint o) { return (float)(o & 0xffffffu) * 0x1.0p-24f; }
SWCL_INLINE int swcl_off_cells(uint o) { return (int)(o >> 24); }

SWCL_INLINE void swcl_perlin3_seeded_s(float px, float py, float pz, uint4 o,
                                       float* val, float* gx, float* gy, float* gz)
{
    swcl_perlin3_s(px + swcl_off_frac(o.x), py + swcl_off_frac(o.y), pz + swcl_off_frac(o.z),
                   swcl_off_cells(o.x), swcl_off_cells(o.y), swcl_off_cells(o.z), val, gx, gy, gz);
}
SWCL_INLINE void swcl_perlin4_seeded_s(float px, float py, float pz, float pw, uint4 o,
                                       float* val, float* gx, float* gy, float* gz, float* gw)
{
    swcl_perlin4_s(px + swcl_off_frac(o.x), py + swcl_off_frac(o.y), pz + swcl_off_frac(o.z),
                   pw + swcl_off_frac(o.w), swcl_off_cells(o.x), swcl_off_cells(o.y),
                   swcl_off_cells(o.z), swcl_off_cells(o.w), val, gx, gy, gz, gw);
}

/* ---- struct / vector wrappers (tests, generic paths) ---- */

SWCL_INLINE swcl_vg3 swcl_perlin3_shifted(float3 p, int3 ioff)
{
    swcl_vg3 r; float gx, gy, gz;
    swcl_perlin3_s(p.x, p.y, p.z, ioff.x, ioff.y, ioff.z, &r.v, &gx, &gy, &gz);
    r.g = (float3)(gx, gy, gz);
    return r;
}
SWCL_INLINE swcl_vg4 swcl_perlin4_shifted(float4 p, int4 ioff)
{
    swcl_vg4 r; float gx, gy, gz, gw;
    swcl_perlin4_s(p.x, p.y, p.z, p.w, ioff.x, ioff.y, ioff.z, ioff.w, &r.v, &gx, &gy, &gz, &gw);
    r.g = (float4)(gx, gy, gz, gw);
    return r;
}

/* Unseeded noise (Perlin's reference function) with gradient. */
SWCL_INLINE swcl_vg3 swcl_perlin3(float3 p) { return swcl_perlin3_shifted(p, (int3)(0)); }
SWCL_INLINE swcl_vg4 swcl_perlin4(float4 p) { return swcl_perlin4_shifted(p, (int4)(0)); }

/* Per-seed, per-channel domain offset (see header): a raw Philox draw. */
static inline uint4 swcl_perlin_offset(ulong seed, uint channel)
{
    return swcl_rand_u4(seed, channel, 0u, SWCL_STREAM_PERLIN_OFFSET, 0u);
}
static inline int4 swcl_offset_cells(uint4 o) { return convert_int4(o >> 24); }
static inline float4 swcl_offset_frac(uint4 o) { return convert_float4(o & 0xffffffu) * 0x1.0p-24f; }

/* Seeded noise: value and gradient (d/dp) of noise_seed(p) = noise(p + offset). */
SWCL_INLINE swcl_vg3 swcl_perlin3_seeded(float3 p, uint4 o)
{
    swcl_vg3 r; float gx, gy, gz;
    swcl_perlin3_seeded_s(p.x, p.y, p.z, o, &r.v, &gx, &gy, &gz);
    r.g = (float3)(gx, gy, gz);
    return r;
}
SWCL_INLINE swcl_vg4 swcl_perlin4_seeded(float4 p, uint4 o)
{
    swcl_vg4 r; float gx, gy, gz, gw;
    swcl_perlin4_seeded_s(p.x, p.y, p.z, p.w, o, &r.v, &gx, &gy, &gz, &gw);
    r.g = (float4)(gx, gy, gz, gw);
    return r;
}

/* ---- explicit-width variants (CPU devices) ----
 *
 * Built when NOISE_WIDTH (8 or 16) is defined: the same arithmetic as the
 * scalar cores above, in the same order, on SWCL_W consecutive points at once
 * (floatW lanes), so every lane gives the scalar result up to the compiler's
 * own contraction choices. PoCL does not vectorise the scalar cores across
 * work-items (docs/noise.md), so on CPUs one work-item runs SWCL_W points.
 * Permutation lookups are gathers (swcl_perm_w). Lane types and macros:
 * lib/lanes.cl. */
#if defined(SWCL_W)

/* The permutation lookup of W lanes. On x86 CPUs with AVX-512 and W = 16 one
 * hardware gather (vpgatherdd); LLVM does not form it from W scalar loads,
 * and those cost an extract, a load and an insert per lane. (The AVX2 gather
 * for W = 8 measured slower than the scalar loads on a Xeon, so W = 8 keeps
 * them.)
 * The __constant table is addressed through an integer cast: CPU devices have
 * one flat address space. -DSWCL_NO_HW_GATHER keeps the scalar loads. */
#define SWCL_PERM_LANE_(k) swcl_perm[SWCL_LANE(swcl_pi_, k)]
#ifdef __has_builtin
#define SWCL_HAS_BUILTIN(x) __has_builtin(x)
#else
#define SWCL_HAS_BUILTIN(x) 0
#endif
#if defined(SWCL_NO_HW_GATHER)
#define SWCL_HW_GATHER 0
SWCL_INLINE swcl_iw swcl_perm_w(swcl_iw i)
{
    const swcl_iw swcl_pi_ = i & 255;
    return (swcl_iw)(SWCL_LANES(SWCL_PERM_LANE_));
}
#elif SWCL_W == 16 && defined(__AVX512F__) && defined(__x86_64__) && SWCL_HAS_BUILTIN(__builtin_ia32_gathersiv16si)
#define SWCL_HW_GATHER 1
SWCL_INLINE swcl_iw swcl_perm_w(swcl_iw i)
{
    const swcl_iw swcl_pi_ = i & 255;
    return __builtin_ia32_gathersiv16si((int16)(0), (const void*)(size_t)swcl_perm, swcl_pi_, (ushort)0xffff, 4);
}
#else
#define SWCL_HW_GATHER 0
SWCL_INLINE swcl_iw swcl_perm_w(swcl_iw i)
{
    const swcl_iw swcl_pi_ = i & 255;
    return (swcl_iw)(SWCL_LANES(SWCL_PERM_LANE_));
}
#endif

#define SWCL_PERM2_LANE_(k) swcl_perm2[SWCL_LANE(swcl_pi_, k)]
#if SWCL_HW_GATHER
SWCL_INLINE swcl_iw swcl_perm2_w(swcl_iw i)
{
    const swcl_iw swcl_pi_ = i & 255;
    return __builtin_ia32_gathersiv16si((int16)(0), (const void*)(size_t)swcl_perm2, swcl_pi_, (ushort)0xffff, 4);
}
#else
SWCL_INLINE swcl_iw swcl_perm2_w(swcl_iw i)
{
    const swcl_iw swcl_pi_ = i & 255;
    return (swcl_iw)(SWCL_LANES(SWCL_PERM2_LANE_));
}
#endif
SWCL_INLINE swcl_fw swcl_fade_w(swcl_fw t)  { return t * t * t * (t * (t * 6.0f - 15.0f) + 10.0f); }
SWCL_INLINE swcl_fw swcl_dfade_w(swcl_fw t) { return 30.0f * t * t * (t * (t - 2.0f) + 1.0f); }
SWCL_INLINE swcl_iw swcl_floor_iw(swcl_fw x)
{
    const swcl_iw i = swcl_cvt_iw(x);            /* truncation toward 0 */
    return i + (swcl_cvt_fw(i) > x);              /* true is -1 */
}

SWCL_INLINE void swcl_grad3_w(swcl_iw h, swcl_fw* gx, swcl_fw* gy, swcl_fw* gz)
{
    h &= 15;
    const swcl_fw one = (swcl_fw)(1.0f), mone = (swcl_fw)(-1.0f), zero = (swcl_fw)(0.0f);
    const swcl_fw su = select(one, mone, (h & 1) != 0), sv = select(one, mone, (h & 2) != 0);
    const swcl_iw vx = (h == 12) | (h == 14);
    const swcl_iw lt8 = h < 8;
    *gx = select(select(zero, sv, vx), su, lt8);
    *gy = select(su, select(zero, sv, h < 4), lt8);
    *gz = select(zero, sv, (h >= 4) & ~vx);
}

SWCL_INLINE void swcl_grad4_w(swcl_iw h, swcl_fw* gx, swcl_fw* gy, swcl_fw* gz, swcl_fw* gw)
{
    h &= 31;
    const swcl_iw z = h >> 3;
    const swcl_fw one = (swcl_fw)(1.0f), mone = (swcl_fw)(-1.0f), zero = (swcl_fw)(0.0f);
    const swcl_fw s0 = select(one, mone, (h & 1) != 0), s1 = select(one, mone, (h & 2) != 0),
                  s2 = select(one, mone, (h & 4) != 0);
    *gx = select(s0, zero, z == 0);
    *gy = select(select(s1, zero, z == 1), s0, z == 0);
    *gz = select(select(s2, zero, z == 2), s1, z <= 1);
    *gw = select(s2, zero, z == 3);
}

#define SWCL_CORNER3_W(h, dx, dy, dz, C)                                      \
    swcl_fw C##x, C##y, C##z;                                                 \
    swcl_grad3_w((h), &C##x, &C##y, &C##z);                                   \
    const swcl_fw C##v = C##x * (dx) + C##y * (dy) + C##z * (dz);
#define SWCL_DLERP3_W(t, dt, AX, A, B, R)                                     \
    const swcl_fw R##v = A##v + (t) * (B##v - A##v);                          \
    const swcl_fw R##x = A##x + (t) * (B##x - A##x) + ((AX) == 0 ? (dt) * (B##v - A##v) : (swcl_fw)(0.0f)); \
    const swcl_fw R##y = A##y + (t) * (B##y - A##y) + ((AX) == 1 ? (dt) * (B##v - A##v) : (swcl_fw)(0.0f)); \
    const swcl_fw R##z = A##z + (t) * (B##z - A##z) + ((AX) == 2 ? (dt) * (B##v - A##v) : (swcl_fw)(0.0f));

SWCL_INLINE void swcl_perlin3_w(swcl_fw px, swcl_fw py, swcl_fw pz, int ox, int oy, int oz,
                                swcl_fw* val, swcl_fw* gx, swcl_fw* gy, swcl_fw* gz)
{
    const swcl_iw ix = swcl_floor_iw(px), iy = swcl_floor_iw(py), iz = swcl_floor_iw(pz);
    const swcl_fw x = px - swcl_cvt_fw(ix), y = py - swcl_cvt_fw(iy), z = pz - swcl_cvt_fw(iz);
    const swcl_iw X = ix + ox, Y = iy + oy, Z = iz + oz;
    const swcl_fw u = swcl_fade_w(x), v = swcl_fade_w(y), w = swcl_fade_w(z);
    const swcl_fw du = swcl_dfade_w(x), dv = swcl_dfade_w(y), dw = swcl_dfade_w(z);
    const swcl_fw x1 = x - 1.0f, y1 = y - 1.0f, z1 = z - 1.0f;
    SWCL_HASH3_PAIRS(swcl_iw, swcl_perm2_w)
    SWCL_NOISE3_BODY(SWCL_CORNER3_W, SWCL_DLERP3_W)
    *val = rv; *gx = rx; *gy = ry; *gz = rz;
}

#define SWCL_CORNER4_W(h, dx, dy, dz, dw, C)                                  \
    swcl_fw C##x, C##y, C##z, C##w;                                           \
    swcl_grad4_w((h), &C##x, &C##y, &C##z, &C##w);                            \
    const swcl_fw C##v = C##x * (dx) + C##y * (dy) + C##z * (dz) + C##w * (dw);
#define SWCL_DLERP4_W(t, dt, AX, A, B, R)                                     \
    const swcl_fw R##v = A##v + (t) * (B##v - A##v);                          \
    const swcl_fw R##x = A##x + (t) * (B##x - A##x) + ((AX) == 0 ? (dt) * (B##v - A##v) : (swcl_fw)(0.0f)); \
    const swcl_fw R##y = A##y + (t) * (B##y - A##y) + ((AX) == 1 ? (dt) * (B##v - A##v) : (swcl_fw)(0.0f)); \
    const swcl_fw R##z = A##z + (t) * (B##z - A##z) + ((AX) == 2 ? (dt) * (B##v - A##v) : (swcl_fw)(0.0f)); \
    const swcl_fw R##w = A##w + (t) * (B##w - A##w) + ((AX) == 3 ? (dt) * (B##v - A##v) : (swcl_fw)(0.0f));

SWCL_INLINE void swcl_perlin4_w(swcl_fw px, swcl_fw py, swcl_fw pz, swcl_fw pw, int ox, int oy, int oz, int ow,
                                swcl_fw* val, swcl_fw* gx, swcl_fw* gy, swcl_fw* gz, swcl_fw* gw)
{
    const swcl_iw ix = swcl_floor_iw(px), iy = swcl_floor_iw(py), iz = swcl_floor_iw(pz), iw = swcl_floor_iw(pw);
    const swcl_fw x = px - swcl_cvt_fw(ix), y = py - swcl_cvt_fw(iy), z = pz - swcl_cvt_fw(iz),
                  w = pw - swcl_cvt_fw(iw);
    const swcl_iw X = ix + ox, Y = iy + oy, Z = iz + oz, W = iw + ow;
    const swcl_fw u = swcl_fade_w(x), v = swcl_fade_w(y), s = swcl_fade_w(z), q = swcl_fade_w(w);
    const swcl_fw du = swcl_dfade_w(x), dv = swcl_dfade_w(y), ds = swcl_dfade_w(z), dq = swcl_dfade_w(w);
    const swcl_fw x1 = x - 1.0f, y1 = y - 1.0f, z1 = z - 1.0f, w1 = w - 1.0f;
    SWCL_HASH4_PAIRS(swcl_iw, swcl_perm2_w)
    SWCL_NOISE4_BODY(SWCL_CORNER4_W, SWCL_DLERP4_W)
    *val = rv; *gx = rx; *gy = ry; *gz = rz; *gw = rw;
}

SWCL_INLINE void swcl_perlin3_seeded_w(swcl_fw px, swcl_fw py, swcl_fw pz, uint4 o,
                                       swcl_fw* val, swcl_fw* gx, swcl_fw* gy, swcl_fw* gz)
{
    swcl_perlin3_w(px + swcl_off_frac(o.x), py + swcl_off_frac(o.y), pz + swcl_off_frac(o.z),
                   swcl_off_cells(o.x), swcl_off_cells(o.y), swcl_off_cells(o.z), val, gx, gy, gz);
}
SWCL_INLINE void swcl_perlin4_seeded_w(swcl_fw px, swcl_fw py, swcl_fw pz, swcl_fw pw, uint4 o,
                                       swcl_fw* val, swcl_fw* gx, swcl_fw* gy, swcl_fw* gz, swcl_fw* gw)
{
    swcl_perlin4_w(px + swcl_off_frac(o.x), py + swcl_off_frac(o.y), pz + swcl_off_frac(o.z),
                   pw + swcl_off_frac(o.w), swcl_off_cells(o.x), swcl_off_cells(o.y),
                   swcl_off_cells(o.z), swcl_off_cells(o.w), val, gx, gy, gz, gw);
}
#endif /* SWCL_W */

#endif /* SWCL_PERLIN_CL */
