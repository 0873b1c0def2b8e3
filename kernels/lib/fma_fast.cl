// a * b + c as one fused instruction where the device has one (include-only,
// no kernels): FP_FAST_FMAF, which PoCL defines nowhere, or clang's __FMA__
// (x86 with FMA3); else a multiply and an add, as the kernels' other
// arithmetic (they contract nothing by themselves: docs/architecture.md,
// "Floating point").  For sums and polynomials whose results decide
// nothing exactly; PoCL's mad is a multiply and an add everywhere.
#ifndef SWCL_FMA_FAST_CL
#define SWCL_FMA_FAST_CL
#if defined(FP_FAST_FMAF) || defined(__FMA__)
#define swcl_fma_fast(a, b, c) fma((a), (b), (c))
#else
#define swcl_fma_fast(a, b, c) ((a) * (b) + (c))
#endif
#endif
