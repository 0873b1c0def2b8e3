// 2^x in vector lanes for the energy model's exponentials (include-only, no
// kernels).  x is clamped to [-126, 127] and split as k + f, k = rint(x),
// |f| <= 1/2; 2^f = 1 + f P(f), P of degree 4 fitted to the least largest
// relative error on [-1/2, 1/2]: 9.2e-8 (scripts/fit_exp2.py), about one
// float rounding more than PoCL's exp2.  PoCL's exp2 evaluates a polynomial
// of degree 6 and handles the whole float range with two scalings, a
// comparison and a blend each way: 22 instructions a vector against 13 here
// (perf annotate of energy_select, AVX2).  The clamp gives 2^127 where exp2
// overflows to inf and 2^-126 where it goes subnormal.
#ifndef SWCL_EXP2_CL
#define SWCL_EXP2_CL
#include "lib/fma_fast.cl"
#define SWCL_EXP2_C1 0.6931469775972803f
#define SWCL_EXP2_C2 0.24022242230119703f
#define SWCL_EXP2_C3 0.055507339115378605f
#define SWCL_EXP2_C4 0.009671504139301013f
#define SWCL_EXP2_C5 0.0013264626351994807f
// k from the rounding of x + 1.5 2^23 (x within 2^22 of 0: its low
// mantissa bits are rint(x), round to nearest), and the polynomial in fma
// where the device has it (lib/fma_fast.cl): PoCL's convert_int_rte and
// rint are six instructions each on AVX2.  The clamp as comparisons: fmin and
// fmax add an unordered compare and a blend each for NaN (a NaN x gives
// 2^127 here).
#define SWCL_EXP2_DEFINE(NAME, F, I, AS_I, AS_F)                                                     \
    static inline F NAME(F x) {                                                                     \
        F xc = x < -126.0f ? (F)(-126.0f) : x;                                                      \
        xc = xc > 127.0f ? (F)(127.0f) : xc;                                                        \
        const F t = xc + 0x1.8p23f;                                                                 \
        const F f = xc - (t - 0x1.8p23f);                                                           \
        const I k = AS_I(t) - 0x4b400000; /* as_int(0x1.8p23f) */                                   \
        F p = swcl_fma_fast(f, SWCL_EXP2_C5, SWCL_EXP2_C4);                                         \
        p = swcl_fma_fast(f, p, SWCL_EXP2_C3);                                                      \
        p = swcl_fma_fast(f, p, SWCL_EXP2_C2);                                                      \
        p = swcl_fma_fast(f, p, SWCL_EXP2_C1);                                                      \
        p = swcl_fma_fast(f, p, 1.0f);                                                              \
        return p * AS_F((k + 127) << 23);                                                           \
    }
SWCL_EXP2_DEFINE(swcl_exp2_f8, float8, int8, as_int8, as_float8)
SWCL_EXP2_DEFINE(swcl_exp2_f16, float16, int16, as_int16, as_float16)
#endif
