// Width-typed names for a per-width kernel body (docs/architecture.md,
// "Kernel layout"; the model is Box2D v3's contact_solver_wide.inl).  The
// including program defines SWCL_BW — 1, or SWCL_W (8 or 16, from
// -DNOISE_WIDTH; lib/lanes.cl) — and includes the body once per width; the
// body includes this file first.  Expanded at every include (*.inc.cl).
#undef swcl_bf
#undef swcl_bi
#undef swcl_bu
#undef swcl_bcvt_f
#undef swcl_bcvt_i
#undef SWCL_BANY
#undef SWCL_BCOUNT_IF
#undef SWCL_BLANE_IDS
#undef SWCL_BVLOAD
#undef SWCL_BVSTORE
#undef SWCL_KERNEL
#undef SWCL_BFN
#undef SWCL_BLANE
#undef SWCL_BLANE_I
#undef SWCL_BEACH_LANE
#undef SWCL_BLANE_ID
#undef SWCL_BLAST
#if SWCL_BW == 1
// One agent per work-item (GPUs; PoCL vectorises it across work-items).
#define swcl_bf float
#define swcl_bi int
#define swcl_bu uint
#define swcl_bcvt_f convert_float
#define swcl_bcvt_i convert_int
// Masks are comparison results: 1 (true) or 0 here, -1 or 0 in vectors.
#define SWCL_BANY(m) (m)
#define SWCL_BCOUNT_IF(c, m) ((c) += (uint)(m))
#define SWCL_BLANE_IDS 0u
#define SWCL_BVLOAD(p) (*(p))
#define SWCL_BVSTORE(v, p) (*(p) = (v))
#define SWCL_KERNEL(name) name
#define SWCL_BFN(name) name##_s
#define SWCL_BLANE(v, k) (v)
#define SWCL_BLANE_I(k) 0
#define SWCL_BEACH_LANE(E) E(0)
#define SWCL_BLANE_ID(base, k, n) (base)
#define SWCL_BLAST(i, n) (i)
#elif defined(SWCL_W) && SWCL_BW == SWCL_W
// SWCL_W consecutive agents per work-item in floatW lanes (CPU devices).
#define swcl_bf swcl_fw
#define swcl_bi swcl_iw
#define swcl_bu swcl_uw
#define swcl_bcvt_f swcl_cvt_fw
#define swcl_bcvt_i swcl_cvt_iw
#define SWCL_BANY(m) swcl_any_w(m)
#define SWCL_BCOUNT_IF(c, m) ((c) -= swcl_as_uw(m))  /* true is -1 */
#define SWCL_BLANE_IDS ((swcl_uw)(SWCL_LANES(SWCL_LANE_I)))
#define SWCL_BVLOAD(p) swcl_vload_fw(0, (p))
#define SWCL_BVSTORE(v, p) swcl_vstore_fw((v), 0, (p))
#define SWCL_KERNEL(name) name##_w
#define SWCL_BFN(name) name##_w
#define SWCL_BLANE(v, k) SWCL_LANE(v, k)
#define SWCL_BLANE_I(k) SWCL_LANE_I(k)
#define SWCL_BEACH_LANE(E) SWCL_EACH_LANE(E)
// The element of lane k from base on, clamped to n - 1 (the last work-item).
#define SWCL_BLANE_ID(base, k, n) min((base) + (uint)SWCL_LANE_I(k), (n) - 1)
// The lanes' elements i (a vector), clamped to n - 1, the bound a vector too:
// Oclgrind 21.10 runs min(ugentype, uint) (integer min/max/clamp with a
// scalar argument) as if the scalar were a vector, reading past it (garbage
// lanes; docs/reliability.md, "Oclgrind").
#define SWCL_BLAST(i, n) min((i), (swcl_bu)((n) - 1u))
#else
#error "SWCL_BW must be 1 or SWCL_W"
#endif
