// swarmcl — kernels/philox.cl
//
// Philox4x32-10 counter-based random numbers (Salmon, Moraes, Dror, Shaw,
// "Parallel random numbers: as easy as 1, 2, 3", SC 2011), OpenCL C 1.2.
//
// Randomness in swarmcl is a pure function of (seed, agent id, step, stream)
// (docs/design.md, "Kernels"), so results do not depend on agent order or device.
// Counter layout used by swcl_rand_u4():
//     ctr = (agent_id, step, stream, sub)      key = (seed & 0xffffffff, seed >> 32)
// `stream` separates independent uses (noise kinds, model terms, ...); `sub`
// is a draw index when one (agent, step, stream) needs more than 4 numbers.
// Known-answer tests (Random123 kat_vectors, philox4x32 10 rounds):
//   ctr=0,0,0,0 key=0,0                         -> 6627e8d5 e169c58d bc57ac4c 9b00dbd8
//   ctr=ffffffff x4 key=ffffffff x2             -> 408f276d 41c83b0e a20bc7c6 6d5451fd
//   ctr=243f6a88 85a308d3 13198a2e 03707344
//   key=a4093822 299f31d0                       -> d16cfe09 94fdcceb 5001e420 24126ea1
// Plain C++ reference: tests/reference/noise_reference.hpp (swcl_ref::philox4x32_10).

#ifndef SWCL_PHILOX_CL
#define SWCL_PHILOX_CL

#define SWCL_PHILOX_M0 0xD2511F53u
#define SWCL_PHILOX_M1 0xCD9E8D57u
#define SWCL_PHILOX_W0 0x9E3779B9u  /* golden ratio */
#define SWCL_PHILOX_W1 0xBB67AE85u  /* sqrt(3) - 1  */

/* Stream ids used inside swarmcl (add new ones at the end, never renumber:
 * changing one changes every seeded result). */
#define SWCL_STREAM_WHITE_NOISE    0u
#define SWCL_STREAM_GAUSSIAN_NOISE 1u
#define SWCL_STREAM_PERLIN_OFFSET  2u  /* per-seed domain offsets, perlin.cl */

/* One Philox round: two 32x32->64 multiplies, xor with the other words and key. */
static inline uint4 swcl_philox_round(uint4 c, uint2 k)
{
    uint hi0 = mul_hi(SWCL_PHILOX_M0, c.x), lo0 = SWCL_PHILOX_M0 * c.x;
    uint hi1 = mul_hi(SWCL_PHILOX_M1, c.z), lo1 = SWCL_PHILOX_M1 * c.z;
    return (uint4)(hi1 ^ c.y ^ k.x, lo1, hi0 ^ c.w ^ k.y, lo0);
}

/* Philox4x32 with 10 rounds; the key is bumped by (W0, W1) between rounds. */
static inline uint4 philox4x32_10(uint4 ctr, uint2 key)
{
    for (int r = 0; r < 9; ++r) {
        ctr = swcl_philox_round(ctr, key);
        key += (uint2)(SWCL_PHILOX_W0, SWCL_PHILOX_W1);
    }
    return swcl_philox_round(ctr, key);
}

static inline uint2 swcl_seed_key(ulong seed)
{
    return (uint2)((uint)(seed & 0xffffffffUL), (uint)(seed >> 32));
}

/* Four independent uints for (seed, agent, step, stream, sub). */
static inline uint4 swcl_rand_u4(ulong seed, uint agent_id, uint step, uint stream, uint sub)
{
    return philox4x32_10((uint4)(agent_id, step, stream, sub), swcl_seed_key(seed));
}

/* uint -> float. The top 24 bits are used so the result is exact in float:
 * [0,1):  k * 2^-24, k = x >> 8 in [0, 2^24)      (0 possible, 1 never)
 * (0,1]:  (k + 1) * 2^-24                          (1 possible, 0 never: safe for log) */
static inline float swcl_u01_co(uint x) { return (float)(x >> 8) * 0x1.0p-24f; }
static inline float swcl_u01_oc(uint x) { return (float)((x >> 8) + 1u) * 0x1.0p-24f; }

static inline float4 swcl_u01_co4(uint4 x)
{
    return (float4)(swcl_u01_co(x.x), swcl_u01_co(x.y), swcl_u01_co(x.z), swcl_u01_co(x.w));
}

/* White noise W (data-driven noise paper §4.2.1): 4 uniforms in [0,1). */
static inline float4 swcl_rand_uniform4(ulong seed, uint agent_id, uint step, uint stream)
{
    return swcl_u01_co4(swcl_rand_u4(seed, agent_id, step, stream, 0u));
}

/* Box–Muller: two N(0,1) from two uints. Data-driven noise paper §4.2.1:
 * G = lambda * sqrt(-2 log W1) * sin(2 pi W2); the cos branch gives the
 * second, independent, normal. W1 in (0,1] so log is finite; W2 in [0,1). */
static inline float2 swcl_box_muller(uint a, uint b)
{
    float r  = sqrt(-2.0f * log(swcl_u01_oc(a)));
    float th = 6.283185307179586f * swcl_u01_co(b);
    return (float2)(r * sin(th), r * cos(th));
}

/* Four N(0,1) for (seed, agent, step, stream); multiply by lambda outside. */
static inline float4 swcl_rand_gauss4(ulong seed, uint agent_id, uint step, uint stream)
{
    uint4 u = swcl_rand_u4(seed, agent_id, step, stream, 0u);
    float2 g0 = swcl_box_muller(u.x, u.y);
    float2 g1 = swcl_box_muller(u.z, u.w);
    return (float4)(g0, g1);
}

#endif /* SWCL_PHILOX_CL */
