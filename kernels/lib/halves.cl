// The halves of a 16-lane vector and the sum of its lanes (include-only, no kernels): v.lo and v.hi,
// except under -DSWCL_OCLGRIND (passed by scripts/oclgrind_check.py, never
// by the library), where they go through private memory.  Oclgrind 21.10's
// uninitialised-value check gets LLVM's shufflevector wrong twice: it
// compares each mask element with llvm::Value::UndefValueVal (a kind of
// value, 11 in LLVM 14) instead of the undefined-element marker -1, so the
// lane a swizzle takes from element 11 of its source reads as uninitialised
// (`m.hi` of an int16 written whole: lane 3), and for an undefined element
// (-1: the widening shuffles of a vector literal built from smaller vectors,
// `(float16)(a, b, c, d)`) it reads a shadow about 4 GiB past its own, junk
// or a crash (docs/reliability.md, "Oclgrind").  The same values either way.
#ifndef SWCL_HALVES_CL
#define SWCL_HALVES_CL
#ifdef SWCL_OCLGRIND
static inline float8 swcl_lo16f(float16 v) {
    float a[16];
    vstore16(v, 0, a);
    return vload8(0, a);
}
static inline float8 swcl_hi16f(float16 v) {
    float a[16];
    vstore16(v, 0, a);
    return vload8(1, a);
}
static inline int8 swcl_lo16i(int16 v) {
    int a[16];
    vstore16(v, 0, a);
    return vload8(0, a);
}
static inline int8 swcl_hi16i(int16 v) {
    int a[16];
    vstore16(v, 0, a);
    return vload8(1, a);
}
#else
#define swcl_lo16f(v) ((v).lo)
#define swcl_hi16f(v) ((v).hi)
#define swcl_lo16i(v) ((v).lo)
#define swcl_hi16i(v) ((v).hi)
#endif

// Sum of a 16-lane vector's lanes in a fixed order (halves, recursively):
// the same bits wherever it is summed.
static inline float swcl_sum16f(float16 v) {
    const float8 a = swcl_lo16f(v) + swcl_hi16f(v);
    const float4 b = a.lo + a.hi;
    const float2 c = b.lo + b.hi;
    return c.x + c.y;
}

// The same for 8 lanes.
static inline float swcl_sum8f(float8 v) {
    const float4 b = v.lo + v.hi;
    const float2 c = b.lo + b.hi;
    return c.x + c.y;
}
#endif
