// swarmcl — kernels/prefetch.cl
//
// SWCL_PREFETCH(p): a hint that the cache line of the global pointer p will be
// read soon, for loads whose address depends on data (the MDE pass's cell
// starts), which otherwise wait on memory one after another.  On x86 CPU
// devices it is the compiler's prefetch builtin, through an integer cast (CPU
// devices have one flat address space).  PoCL's OpenCL prefetch() built-in
// emits no instruction (perf annotate of the kernel shows none), so it is not
// used.  Other devices, and CPU devices in the GPU profile
// (SWCL_CPU_PROFILE=0, set by the host): nothing, so no x86 builtin reaches a
// GPU compiler.
#ifndef SWCL_PREFETCH_CL
#define SWCL_PREFETCH_CL

#if defined(SWCL_CPU_PROFILE) && SWCL_CPU_PROFILE && defined(__x86_64__) && defined(__has_builtin)
#if __has_builtin(__builtin_prefetch)
#define SWCL_PREFETCH(p) __builtin_prefetch((const void*)(size_t)(p))
// ... of a line that will be written (prefetchw: fetched for ownership).
#define SWCL_PREFETCH_WRITE(p) __builtin_prefetch((const void*)(size_t)(p), 1)
#define SWCL_PREFETCH_ISSUES 1  // for prefetch loops worth running only where it does
#endif
#endif
#ifndef SWCL_PREFETCH
#define SWCL_PREFETCH(p) ((void)0)
#define SWCL_PREFETCH_WRITE(p) ((void)0)
#endif

#endif  // SWCL_PREFETCH_CL
