// The explicit width of the CPU kernels (docs/noise.md): with -DNOISE_WIDTH=8
// or 16 (NoiseField::width()), SWCL_W and its lane types (swcl_fw, swcl_iw,
// swcl_uw: floatW, intW, uintW) and lane macros, for the _w helpers of
// lib/perlin.cl, lib/curl_noise.cl, lib/noise_field.cl and the per-width
// bodies (kernels/wide/).  Without it (or with 1) none of these is defined;
// the any() helpers for 8 and 16 lanes (below) always are.
#ifndef SWCL_LANES_CL
#define SWCL_LANES_CL
// (Outside every #if: kernel_sources.cpp expands a file where it is first
// included, and only there.)
#include "lib/halves.cl"
#if defined(NOISE_WIDTH) && NOISE_WIDTH > 1
#define SWCL_W NOISE_WIDTH
#if SWCL_W == 8
typedef float8 swcl_fw;
typedef int8 swcl_iw;
typedef uint8 swcl_uw;
#define swcl_cvt_fw convert_float8
#define swcl_cvt_iw convert_int8
#define swcl_as_uw as_uint8
#define swcl_vload_fw vload8
#define swcl_vstore_fw vstore8
#define swcl_vload_uw vload8
#define swcl_vstore_uw vstore8
#define swcl_vload_iw vload8
#define swcl_vstore_iw vstore8
#define SWCL_LANES(E) E(0), E(1), E(2), E(3), E(4), E(5), E(6), E(7)
#define SWCL_EACH_LANE(E) E(0) E(1) E(2) E(3) E(4) E(5) E(6) E(7)
#elif SWCL_W == 16
typedef float16 swcl_fw;
typedef int16 swcl_iw;
typedef uint16 swcl_uw;
#define swcl_cvt_fw convert_float16
#define swcl_cvt_iw convert_int16
#define swcl_as_uw as_uint16
#define swcl_vload_fw vload16
#define swcl_vstore_fw vstore16
#define swcl_vload_uw vload16
#define swcl_vstore_uw vstore16
#define swcl_vload_iw vload16
#define swcl_vstore_iw vstore16
#define SWCL_LANES(E) E(0), E(1), E(2), E(3), E(4), E(5), E(6), E(7), \
                      E(8), E(9), E(a), E(b), E(c), E(d), E(e), E(f)
#define SWCL_EACH_LANE(E) E(0) E(1) E(2) E(3) E(4) E(5) E(6) E(7) \
                          E(8) E(9) E(a) E(b) E(c) E(d) E(e) E(f)
#else
#error "NOISE_WIDTH must be 1, 8 or 16"
#endif
/* SWCL_LANES(E): E(k) for every lane, comma separated (a vector literal);
 * SWCL_EACH_LANE(E): the same, juxtaposed (statements). k is a hex digit
 * token; lane k of a vector and its index as an int: */
#define SWCL_LANE(v, k) ((v).s##k)
#define SWCL_LANE_I(k) (0x##k)
#if SWCL_W == 8
#define swcl_any_w swcl_any8
#else
#define swcl_any_w swcl_any16
#endif
#endif
// any(m) without OpenCL's any(): PoCL 3.1 lowers any() on int8 and int16 to
// a test and a branch per lane (a chain of `js`, perf annotate of
// policy_observe_w).  On x86 the lanes' sign bits into one mask and a test
// of it: vmovmskps for 8 lanes (AVX), a compare with 0 into a mask register
// for 16 (AVX-512, _mm512_cmplt_epi32_mask); elsewhere (and under Oclgrind,
// which has neither) by halving ORs, the 16-lane one 7 instructions more
// than the mask (a dozen any() per candidate in policy_observe_w: its pass
// 196 -> 156 ms at 100k agents, docs/benchmarks.md).  The same answer.
#if defined(__x86_64__) && defined(__has_builtin)
#if defined(__AVX__) && __has_builtin(__builtin_ia32_movmskps256)
#define SWCL_ANY8_MASK
#endif
#if defined(__AVX512F__) && __has_builtin(__builtin_ia32_cmpd512_mask)
#define SWCL_ANY16_MASK
#endif
#endif
#ifdef SWCL_ANY8_MASK
static inline int swcl_any8(int8 m) { return __builtin_ia32_movmskps256(as_float8(m)) != 0; }
#else
static inline int swcl_any8(int8 m) {
    const int4 b = m.lo | m.hi;
    const int2 c = b.lo | b.hi;
    return (c.x | c.y) < 0;
}
#endif
#ifdef SWCL_ANY16_MASK
static inline int swcl_any16(int16 m) { return __builtin_ia32_cmpd512_mask(m, (int16)(0), 1, (ushort)0xffff) != 0; }
#else
static inline int swcl_any16(int16 m) { return swcl_any8(swcl_lo16i(m) | swcl_hi16i(m)); }
#endif
#endif
