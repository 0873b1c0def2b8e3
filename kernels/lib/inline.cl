// Inlining for the kernels' helpers (include-only, no kernels).  Helpers are
// `static inline`: plain C99 `inline` gives no linkable definition, and
// NVIDIA's ptxas refused the programs that relied on one being inlined
// (docs/benchmarks.md, "NVIDIA compile").  SWCL_ALWAYS_INLINE forces it;
// -DSWCL_NO_ALWAYS_INLINE drops it, for Oclgrind 21.10, which cannot run the
// llvm.experimental.noalias.scope.decl calls LLVM 14's always-inliner leaves
// even at -cl-opt-disable (docs/reliability.md).
#ifndef SWCL_ALWAYS_INLINE
#ifdef SWCL_NO_ALWAYS_INLINE
#define SWCL_ALWAYS_INLINE
#else
#define SWCL_ALWAYS_INLINE __attribute__((always_inline))
#endif
#endif
#ifndef SWCL_INLINE
#define SWCL_INLINE SWCL_ALWAYS_INLINE static inline
#endif
