// The seven metrics of the data-driven evaluation (noise paper §3.2) from a
// running swarm, one sampled frame at a time (eval/swarm_metrics.hpp).  The
// formulas are host/eval/metrics.cpp's (forward differences of positions
// sampled dt apart), computed in float: differences of positions first,
// divided by dt at the end, so nearby positions subtract exactly.
//
// Every value goes into a values buffer (metric-major), whose blocks of
// METRICS_BLOCK give per-block moments (count, mean, M2 of the finite
// values, two passes in a fixed order) that the host merges in block order,
// and into a fine histogram (eval/metric_accumulator.hpp: the bin is an
// integer function of the float's bits, the host's bin_of): atomic_inc
// where the value is made (GPUs) or plain increments into per-chunk copies
// (CPU devices).  Integer counts are order independent: no float atomics,
// no barriers, results independent of the launch's work-group size.
//
// Worlds (eval/swarm_metrics.hpp): the n values are W runs of per_world
// agents (world w: indices [w per_world, (w + 1) per_world)), each with its
// own histogram (hist + w M_COUNT FB_COUNT, or its own chunk copies), its
// own blocks of moments and its own cells of the point grid (keys
// [w cells, (w + 1) cells)); per_world = n is one world, as before.
//
// Build defines (from the host, one source of truth): FB_SHIFT, FB_LOW_KEY,
// FB_SIDE, FB_COUNT (fine_bins), METRICS_BLOCK, HIST_ATOMIC, and each
// metric's index M_<kernel> with M_COUNT (eval/metric_table.hpp).
#include "lib/grid_common.cl"
#include "lib/halves.cl"

#include "lib/inline.cl"
#include "lib/lanes.cl"
#include "lib/prefetch.cl"

// The metrics' indices, M_SPEED ... M_ETA and M_COUNT: build defines from
// the host's metric table (host/eval/metric_table.hpp), one row per metric.
#if !defined(M_COUNT) || !defined(M_SPEED) || !defined(M_DIST)
#error "metrics.cl needs the metric table's defines (metric_kernel_defines())"
#endif

// fine_bins::bin_of (eval/metric_accumulator.cpp), bit for bit.
SWCL_INLINE uint fine_bin(float x) {
    if (isnan(x)) return FB_COUNT - 1u;
    const uint key = as_uint(fabs(x)) >> FB_SHIFT;
    if (key < FB_LOW_KEY) return FB_SIDE + 1u;
    const uint k = key - FB_LOW_KEY;
    if (k >= FB_SIDE) return x < 0.0f ? 0u : 2u * FB_SIDE + 2u;
    return x < 0.0f ? FB_SIDE - k : FB_SIDE + 2u + k;
}

SWCL_INLINE float dot3(float4 a, float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// ω, α and η in double where the device has it: α is a difference of two
// nearby ω and η of two nearby speeds, so float's relative error (1e-7)
// grows by ω/Δω or v/Δv there; in double the values are the host's to its
// float rounding.
#ifdef cl_khr_fp64
#pragma OPENCL EXTENSION cl_khr_fp64 : enable
typedef double mreal;
typedef double3 mreal3;
#define to_mreal3 convert_double3
#else
typedef float mreal;
typedef float3 mreal3;
#define to_mreal3(v) (v)
#endif

// b - a, exactly where mreal is double.
SWCL_INLINE mreal3 diff3(float4 b, float4 a) { return to_mreal3(b.xyz) - to_mreal3(a.xyz); }
SWCL_INLINE mreal len3(mreal3 a) { return sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }

// The angle between a and b: atan2(|a x b|, a . b) is arccos(â . b̂) of the
// host (§3.2's ω) without arccos's loss of digits at small angles.
SWCL_INLINE mreal angle3(mreal3 a, mreal3 b) {
    const mreal cx = a.y * b.z - a.z * b.y, cy = a.z * b.x - a.x * b.z, cz = a.x * b.y - a.y * b.x;
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), a.x * b.x + a.y * b.y + a.z * b.z);
}

// Moments of block b of every metric in `mask`: block lb = b % per_block of
// world w = b / per_block (per_block: blocks per world) covers vals[m * n + k]
// for k in [w per_world + lb METRICS_BLOCK, ...) up to the world's end, two
// passes (mean, then M2), each 16 values at a time (value k in lane k -
// begin mod 16, the lanes summed by swcl_sum16f) and the last few in
// order: a fixed order, and the block's scalar loops were most of the
// kernel's time; part[m * blocks + b] = (count, mean, M2, 0) (the count as
// a float: exact up to 2^24, and not denormal bits a GPU might flush).
__kernel void metrics_moments(__global const float* vals, uint n, uint per_world, uint per_block, uint mask,
                              uint blocks, __global float4* part) {
    const uint b = get_global_id(0);
    if (b >= blocks) return;
    const uint world0 = (b / per_block) * per_world;
    const uint begin = world0 + (b % per_block) * METRICS_BLOCK;
    const uint end = min(world0 + per_world, begin + METRICS_BLOCK);
    const float16 zero = (float16)(0.0f);
    for (uint m = 0; m < M_COUNT; ++m) {
        if (!((mask >> m) & 1u)) continue;
        __global const float* v = vals + (size_t)m * n;
        float16 s = zero, c = zero;
        uint k = begin;
        for (; k + 16u <= end; k += 16u) {
            const float16 x = vload16(0, v + k);
            const int16 ok = isfinite(x);
            s += select(zero, x, ok);
            c += select(zero, (float16)(1.0f), ok);
        }
        float sum = swcl_sum16f(s), count = swcl_sum16f(c);
        for (; k < end; ++k)
            if (isfinite(v[k])) {
                sum += v[k];
                count += 1.0f;
            }
        const float mean = count > 0.0f ? sum / count : 0.0f;
        float16 q = zero;
        for (k = begin; k + 16u <= end; k += 16u) {
            const float16 x = vload16(0, v + k), d = x - mean;
            q += select(zero, d * d, isfinite(x));
        }
        float m2 = swcl_sum16f(q);
        for (; k < end; ++k)
            if (isfinite(v[k])) {
                const float d = v[k] - mean;
                m2 += d * d;
            }
        part[m * blocks + b] = (float4)(count, mean, m2, 0.0f);
    }
}

// A metric with no value for an agent (e.g. ω at zero speed): a NaN with a
// payload no arithmetic makes (computed NaNs are the default NaN), so a
// value that is NaN is still counted in the NaN bin.
#define M_MISSING 0x7fc0beefu

// HIST_ATOMIC (GPUs): each value counted where it is made, atomic_inc.
// Otherwise (CPU devices) metrics_histogram counts the values buffer into
// per-chunk copies with plain increments: a locked increment waits for its
// cache line, so the random bins' misses did not overlap (a third of the
// per-agent kernel's time).
// hist: the agent's world's histogram.
SWCL_INLINE void count_value(__global volatile uint* hist, uint metric, float x) {
#if HIST_ATOMIC
    atomic_inc(&hist[metric * FB_COUNT + fine_bin(x)]);
#endif
}

// Chunk c of nchunks (per_chunk of them per world) counts the values of its
// world's agents [c' size, ...) (c' = c % per_chunk) of every metric in
// `mask` into its own copy, hist + c * M_COUNT * FB_COUNT.
__kernel void metrics_histogram(__global const float* vals, uint n, uint per_world, uint per_chunk, uint mask,
                                uint nchunks, __global uint* hist) {
    const uint c = get_global_id(0);
    if (c >= nchunks) return;
    const uint size = (per_world + per_chunk - 1u) / per_chunk, world0 = (c / per_chunk) * per_world;
    const uint lc = c % per_chunk;
    const uint begin = world0 + min(lc * size, per_world), end = world0 + min(lc * size + size, per_world);
    __global uint* h = hist + (size_t)c * M_COUNT * FB_COUNT;
    for (uint m = 0; m < M_COUNT; ++m) {
        if (!((mask >> m) & 1u)) continue;
        __global const float* v = vals + (size_t)m * n;
        __global uint* hm = h + m * FB_COUNT;
        for (uint k = begin; k < end; ++k)
            if (as_uint(v[k]) != M_MISSING) hm[fine_bin(v[k])] += 1u;
    }
}

// ring[world0 + id] = the agent's position (slot order -> id order, ids
// counted per world), w = 0.
__kernel void metrics_gather(__global const float4* pos, __global const uint* ids, uint n, uint per_world,
                             __global float4* ring) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    ring[s - s % per_world + ids[s]] = (float4)(pos[s].xyz, 0.0f);
}

// Sample `have` (1, 2 or 3: how many earlier frames there are, at most 3)
// with p0 the frame just sampled and p1, p2, p3 the ones before (only the
// first `have` are read).  Forward differences d1 = p0 - p1 (v of frame
// f-1 times dt), d2 = p1 - p2, d3 = p2 - p3 give:
//   v  of frame f-1: |d1| / dt
//   a, ω of frame f-2: |d1 - d2| / dt², angle(d2, d1) / dt (both speeds > 0;
//       omega[i] keeps it for α at the next sample)
//   α, μ of frame f-3: (ω_{f-2} - ω_{f-3}) / dt, |(d1 - d2) - (d2 - d3)| / dt³
//   η of frame f-1 (its nearest neighbour nn_idx, at nn_dist > 0, found when
//   frame f-1 was sampled): | |v_nei| - |v| | / d, both forward speeds.
__kernel void metrics_sample(__global const float4* p0, __global const float4* p1, __global const float4* p2,
                             __global const float4* p3, uint n, uint per_world, uint have, float dt,
                             __global const uint* nn_idx, __global const float* nn_dist,
                             __global float2* omega, __global volatile uint* hist_all, __global float* vals) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    __global volatile uint* hist = hist_all + (size_t)(i / per_world) * M_COUNT * FB_COUNT;
    uint flags = 0;
    float x[M_COUNT];
    for (uint m = 0; m < M_COUNT; ++m) x[m] = NAN;
    {
        const float4 a0 = p0[i], a1 = p1[i];
        const float4 d1 = a0 - a1;
        const float s1 = dot3(d1, d1);
        const float speed = sqrt(s1) / dt;
        x[M_SPEED] = speed;
        flags |= 1u << M_SPEED;
        const mreal dtr = dt;
        const float dn = nn_dist[i];
        const uint j = nn_idx[i];
        if (dn > 0.0f && j < n) {  // j = ~0: no neighbour found (positions not finite)
            x[M_ETA] = (float)(fabs(len3(diff3(p0[j], p1[j])) / dtr - len3(diff3(a0, a1)) / dtr) / dn);
            flags |= 1u << M_ETA;
        }
        if (have >= 2u) {
            const float4 a2 = p2[i];
            const float4 d2 = a1 - a2, acc1 = d1 - d2;
            x[M_ACCEL] = sqrt(dot3(acc1, acc1)) / dt / dt;
            flags |= 1u << M_ACCEL;
            const mreal3 e1 = diff3(a0, a1), e2 = diff3(a1, a2);
            const bool turn1 = any(e1 != (mreal3)(0)) && any(e2 != (mreal3)(0));
            const mreal w1 = turn1 ? angle3(e2, e1) / dtr : (mreal)0;
            if (turn1) {
                x[M_OMEGA] = (float)w1;
                flags |= 1u << M_OMEGA;
            }
            // ω of the frame before, kept from the last sample (hi + lo: a
            // double to 2^-48) instead of a second atan2; NaN: none.
            const float2 w0s = omega[i];
            const float w1_hi = (float)w1;
            omega[i] = turn1 ? (float2)(w1_hi, (float)(w1 - (mreal)w1_hi)) : (float2)(NAN, 0.0f);
            if (have >= 3u) {
                const float4 a3 = p3[i];
                const float4 d3 = a2 - a3, acc0 = d2 - d3, jerk = acc1 - acc0;
                x[M_JERK] = sqrt(dot3(jerk, jerk)) / dt / dt / dt;
                flags |= 1u << M_JERK;
                if (turn1 && !isnan(w0s.x)) {
                    x[M_ALPHA] = (float)((w1 - ((mreal)w0s.x + (mreal)w0s.y)) / dtr);
                    flags |= 1u << M_ALPHA;
                }
            }
        }
        for (uint m = 0; m < M_COUNT; ++m)
            if ((flags >> m) & 1u) count_value(hist, m, x[m]);
    }
    // Missing values as M_MISSING (the moments skip every NaN); d is the
    // nearest kernel's.
    for (uint m = 0; m < M_COUNT; ++m)
        if (m != M_DIST) vals[(size_t)m * n + i] = (flags >> m) & 1u ? x[m] : as_float(M_MISSING);
}

#if defined(SWCL_W)
// metrics_sample on SWCL_W consecutive agents per work-item (CPU devices:
// the scalar kernel's call of atan2 kept PoCL from vectorising it across
// work-items, and it was a third of a sampled frame at 100k agents).  Every
// lane does the scalar kernel's operations in its order, the double ones in
// double lanes, so the values are the scalar kernel's bitwise
// (tests/test_swarm_metrics.cpp).  Launch ceil(n / SWCL_W); lanes past n
// repeat agent n - 1 and write nothing.
#if M_COUNT != 7
#error "metrics_sample_w writes the six metrics besides d by name: a new metric needs its lanes here"
#endif
#ifdef cl_khr_fp64
#if SWCL_W == 8
typedef double8 ms_rw;
typedef long8 ms_rm;
#define ms_cvt_rw convert_double8
#define ms_cvt_fw convert_float8
#define ms_cvt_rm_iw convert_int8
#else
typedef double16 ms_rw;
typedef long16 ms_rm;
#define ms_cvt_rw convert_double16
#define ms_cvt_fw convert_float16
#define ms_cvt_rm_iw convert_int16
#endif
#else
typedef swcl_fw ms_rw;
typedef swcl_iw ms_rm;
#define ms_cvt_rw(v) (v)
#define ms_cvt_fw(v) (v)
#define ms_cvt_rm_iw(v) (v)
#endif

// The x, y, z of W float4 (element idx(k) of `a` for lane k) as lanes.
#define MS_LOAD_W(a, idx, X, Y, Z)                                  \
    {                                                               \
        float px_[SWCL_W], py_[SWCL_W], pz_[SWCL_W];                \
        for (uint l = 0; l < SWCL_W; ++l) {                         \
            const float4 q_ = (a)[idx(l)];                          \
            px_[l] = q_.x;                                          \
            py_[l] = q_.y;                                          \
            pz_[l] = q_.z;                                          \
        }                                                           \
        X = swcl_vload_fw(0, px_);                                  \
        Y = swcl_vload_fw(0, py_);                                  \
        Z = swcl_vload_fw(0, pz_);                                  \
    }
// len3 of (bx - ax, by - ay, bz - az) in mreal lanes (diff3's exact difference).
SWCL_INLINE ms_rw ms_len3_w(swcl_fw bx, swcl_fw by, swcl_fw bz, swcl_fw ax, swcl_fw ay, swcl_fw az) {
    const ms_rw x = ms_cvt_rw(bx) - ms_cvt_rw(ax), y = ms_cvt_rw(by) - ms_cvt_rw(ay), z = ms_cvt_rw(bz) - ms_cvt_rw(az);
    return sqrt(x * x + y * y + z * z);
}

__kernel void metrics_sample_w(__global const float4* p0, __global const float4* p1, __global const float4* p2,
                               __global const float4* p3, uint n, uint per_world, uint have, float dt,
                               __global const uint* nn_idx, __global const float* nn_dist,
                               __global float2* omega, __global volatile uint* hist_all, __global float* vals) {
    const uint base = get_global_id(0) * SWCL_W;
    if (base >= n) return;
    const uint lanes = min((uint)SWCL_W, n - base);
    const mreal dtr = dt;
#define MS_SELF_(l) min(base + (l), n - 1u)
    swcl_fw a0x, a0y, a0z, a1x, a1y, a1z;
    MS_LOAD_W(p0, MS_SELF_, a0x, a0y, a0z)
    MS_LOAD_W(p1, MS_SELF_, a1x, a1y, a1z)
    const swcl_fw d1x = a0x - a1x, d1y = a0y - a1y, d1z = a0z - a1z;
    const swcl_fw speed = sqrt(d1x * d1x + d1y * d1y + d1z * d1z) / dt;
    // η: the neighbour's forward speed against the agent's (scalar: j < n
    // and d > 0; other lanes read agent n - 1 and are not kept).
    float dn_[SWCL_W];
    uint j_[SWCL_W];
    for (uint l = 0; l < SWCL_W; ++l) {
        dn_[l] = nn_dist[MS_SELF_(l)];
        j_[l] = nn_idx[MS_SELF_(l)];
    }
#ifdef SWCL_PREFETCH_ISSUES
    // The next work-item's neighbours, asked for now: they are agents
    // anywhere in the frame (frames are in agent order, not cell order), and
    // the gathers below waited on memory lane after lane (perf: half of the
    // kernel's samples on those loads; bench/results/metrics_prefetch/ab.json).
    for (uint l = 0; l < SWCL_W; ++l) {
        const uint k = base + SWCL_W + l;
        const uint j = k < n ? nn_idx[k] : n;
        if (j < n) {
            SWCL_PREFETCH(p0 + j);
            SWCL_PREFETCH(p1 + j);
        }
    }
#endif
    const swcl_fw dn = swcl_vload_fw(0, dn_);
    const swcl_uw jn = swcl_vload_uw(0, j_);
    const swcl_iw has_eta = (dn > 0.0f) & (jn < (swcl_uw)(n));
#define MS_NEI_(l) (j_[l] < n ? j_[l] : n - 1u)
    swcl_fw b0x, b0y, b0z, b1x, b1y, b1z;
    MS_LOAD_W(p0, MS_NEI_, b0x, b0y, b0z)
    MS_LOAD_W(p1, MS_NEI_, b1x, b1y, b1z)
#undef MS_NEI_
    const swcl_fw eta = ms_cvt_fw(fabs(ms_len3_w(b0x, b0y, b0z, b1x, b1y, b1z) / dtr -
                                       ms_len3_w(a0x, a0y, a0z, a1x, a1y, a1z) / dtr) / ms_cvt_rw(dn));
    swcl_fw accel = (swcl_fw)(0.0f), w1f = (swcl_fw)(0.0f), jerk = (swcl_fw)(0.0f), alpha = (swcl_fw)(0.0f);
    swcl_iw turn = (swcl_iw)(0), has_alpha = (swcl_iw)(0);
    if (have >= 2u) {
        swcl_fw a2x, a2y, a2z;
        MS_LOAD_W(p2, MS_SELF_, a2x, a2y, a2z)
        const swcl_fw d2x = a1x - a2x, d2y = a1y - a2y, d2z = a1z - a2z;
        const swcl_fw c1x = d1x - d2x, c1y = d1y - d2y, c1z = d1z - d2z;
        accel = sqrt(c1x * c1x + c1y * c1y + c1z * c1z) / dt / dt;
        // angle3(e2, e1), e1 = diff3(a0, a1), e2 = diff3(a1, a2)
        const ms_rw e1x = ms_cvt_rw(a0x) - ms_cvt_rw(a1x), e1y = ms_cvt_rw(a0y) - ms_cvt_rw(a1y),
                    e1z = ms_cvt_rw(a0z) - ms_cvt_rw(a1z);
        const ms_rw e2x = ms_cvt_rw(a1x) - ms_cvt_rw(a2x), e2y = ms_cvt_rw(a1y) - ms_cvt_rw(a2y),
                    e2z = ms_cvt_rw(a1z) - ms_cvt_rw(a2z);
        const ms_rm turn_r = ((e1x != (ms_rw)(0)) | (e1y != (ms_rw)(0)) | (e1z != (ms_rw)(0))) &
                             ((e2x != (ms_rw)(0)) | (e2y != (ms_rw)(0)) | (e2z != (ms_rw)(0)));
        turn = ms_cvt_rm_iw(turn_r);
        const ms_rw cx = e2y * e1z - e2z * e1y, cy = e2z * e1x - e2x * e1z, cz = e2x * e1y - e2y * e1x;
        const ms_rw w1 = select((ms_rw)(0), atan2(sqrt(cx * cx + cy * cy + cz * cz), e2x * e1x + e2y * e1y + e2z * e1z) / dtr,
                                turn_r);
        w1f = ms_cvt_fw(w1);
        const ms_rw w1lo = w1 - ms_cvt_rw(w1f);
        // ω of the frame before (hi + lo), then this one's in its place.
        float w0h[SWCL_W], w0l[SWCL_W], wlo[SWCL_W], whi[SWCL_W];
        for (uint l = 0; l < SWCL_W; ++l) {
            const float2 w = omega[MS_SELF_(l)];
            w0h[l] = w.x;
            w0l[l] = w.y;
        }
        swcl_vstore_fw(w1f, 0, whi);
        swcl_vstore_fw(ms_cvt_fw(w1lo), 0, wlo);
        int tn[SWCL_W];
        swcl_vstore_iw(turn, 0, tn);
        for (uint l = 0; l < lanes; ++l)
            omega[base + l] = tn[l] ? (float2)(whi[l], wlo[l]) : (float2)(NAN, 0.0f);
        if (have >= 3u) {
            swcl_fw a3x, a3y, a3z;
            MS_LOAD_W(p3, MS_SELF_, a3x, a3y, a3z)
            const swcl_fw d3x = a2x - a3x, d3y = a2y - a3y, d3z = a2z - a3z;
            const swcl_fw c0x = d2x - d3x, c0y = d2y - d3y, c0z = d2z - d3z;
            const swcl_fw jx = c1x - c0x, jy = c1y - c0y, jz = c1z - c0z;
            jerk = sqrt(jx * jx + jy * jy + jz * jz) / dt / dt / dt;
            const swcl_fw w0x = swcl_vload_fw(0, w0h), w0y = swcl_vload_fw(0, w0l);
            has_alpha = turn & ~isnan(w0x);
            alpha = ms_cvt_fw((w1 - (ms_cvt_rw(w0x) + ms_cvt_rw(w0y))) / dtr);
        }
    }
#undef MS_SELF_
    // Each metric's lanes to its values (M_MISSING where the scalar kernel
    // has none) and, on GPUs, to the lane's world's histogram.
    const swcl_fw missing = (swcl_fw)(as_float(M_MISSING));
    const swcl_iw yes = (swcl_iw)(-1);
    const swcl_iw two = have >= 2u ? yes : (swcl_iw)(0), three = have >= 3u ? yes : (swcl_iw)(0);
    const swcl_fw val[6] = {speed, eta, accel, w1f, jerk, alpha};
    const swcl_iw has[6] = {yes, has_eta, two, two & turn, three, three & has_alpha};
    const uint metric[6] = {M_SPEED, M_ETA, M_ACCEL, M_OMEGA, M_JERK, M_ALPHA};
    for (uint q = 0; q < 6u; ++q) {
        const swcl_fw v = select(missing, val[q], has[q]);
        __global float* out = vals + (size_t)metric[q] * n + base;
        if (lanes == SWCL_W) {
            swcl_vstore_fw(v, 0, out);
        } else {
            float vl[SWCL_W];
            swcl_vstore_fw(v, 0, vl);
            for (uint l = 0; l < lanes; ++l) out[l] = vl[l];
        }
#if HIST_ATOMIC
        float vl[SWCL_W];
        int hl[SWCL_W];
        swcl_vstore_fw(v, 0, vl);
        swcl_vstore_iw(has[q], 0, hl);
        for (uint l = 0; l < lanes; ++l)
            if (hl[l]) count_value(hist_all + (size_t)((base + l) / per_world) * M_COUNT * FB_COUNT, metric[q], vl[l]);
#endif
    }
}
#undef MS_LOAD_W
#endif

// sorted[k] = the point at sorted position k of the point grid, its index
// in w (as uint bits): the nearest-neighbour search then reads candidates
// in a row's range contiguously, and neighbouring work-items search
// neighbouring cells.
__kernel void metrics_sort_points(__global const float4* pts, __global const uint* slots, uint n,
                                  __global float4* sorted) {
    const uint k = get_global_id(0);
    if (k >= n) return;
    const uint j = slots[k];
    sorted[k] = (float4)(pts[j].xyz, as_float(j));
}

// The candidates at sorted positions [k0, k1) (but k itself).  Ties go to
// the lowest index.
SWCL_INLINE void metrics_visit(__global const float4* sp, uint self, float4 p, uint k0, uint k1, float* best_d2,
                               uint* best) {
    for (uint k = k0; k < k1; ++k) {
        const float4 q = sp[k];
        const float d2 = dist2(p, q);
        const uint j = as_uint(q.w);
        if (k != self && (d2 < *best_d2 || (d2 == *best_d2 && j < *best))) {
            *best_d2 = d2;
            *best = j;
        }
    }
}

// The nearest other point of p (sorted position self) into (best_d2, best):
// boxes of cells around p's cell growing one cell per side from k0, each
// visiting the cells not in the previous box (first [plo, phi]: cells an
// earlier search has seen; an empty box is lo > hi), until the best
// distance is below the distance to anything outside the box or the box is
// the whole grid.  A cell seen twice changes nothing (the least (d2, index)
// is the same).
SWCL_INLINE void metrics_search(const Grid* g, __global const float4* sp, uint self, float4 p, int k0, int4 plo,
                                int4 phi, float* best_d2, uint* best) {
    const int4 c = grid_cell_of(g, p);
    const int4 last = g->dims - (int4)(1, 1, 1, 1);
    for (int k = k0;; ++k) {
        const int4 lo = max(c - (int4)(k, k, k, 0), (int4)(0, 0, 0, 0));
        const int4 hi = min(c + (int4)(k, k, k, 0), last);
        GRID_FOR_EACH_NEW_RANGE(g, lo, hi, plo, phi, rg) {
            metrics_visit(sp, self, p, rg.x, rg.y, best_d2, best);
        }
        GRID_END_NEW_RANGE
        if (all(lo.xyz == (int3)(0)) && all(hi.xyz == last.xyz)) break;
        const float bound = grid_outside_bound(g, p, lo, hi);
        if (bound > 0.0f && *best_d2 <= bound * bound) break;
        plo = lo;
        phi = hi;
    }
}

// d of the frame just sampled (§3.2, the shortest distance): the nearest
// other point of every point over the point grid (spatial/point_grid.hpp,
// built on these points; sp: metrics_sort_points), one work-item per
// sorted position: boxes of cells growing one cell per side, each visiting
// only the cells not seen before, until the best distance is below the
// distance to anything outside the box or the box is the whole grid.
// nn_idx, nn_dist (index order) are kept for η at the next sample.
// Worlds: the grid's groups are the worlds (PointGrid::build_groups), and
// sorted positions are world by world, so position self's world is
// self / per_world and its cells start at cell_start + world cells.
__kernel void metrics_nearest(__global const float4* sp, uint n, uint per_world, __global const float4* geo,
                              __global const uint* cell_start, __global uint* nn_idx, __global float* nn_dist,
                              __global volatile uint* hist_all, __global float* vals) {
    const uint self = get_global_id(0);
    if (self >= n) return;
    {
        const uint world = self / per_world;
        __global volatile uint* hist = hist_all + (size_t)world * M_COUNT * FB_COUNT;
        const Grid g = grid_from_geometry(geo, cell_start + (size_t)world * as_uint(geo[1].w));
        const float4 p = sp[self];
        const uint i = as_uint(p.w);
        float best_d2 = INFINITY;
        uint best = 0xffffffffu;
        metrics_search(&g, sp, self, p, 0, (int4)(1, 1, 1, 0), (int4)(0, 0, 0, 0), &best_d2, &best);
        const float d = sqrt(best_d2);
        nn_idx[i] = best;
        nn_dist[i] = d;
        count_value(hist, M_DIST, d);
        // Index order, as every other metric: the blocks of moments then do
        // not depend on the grid (a world and its swarm alone build different
        // cells, and give the same moments).
        vals[(size_t)M_DIST * n + i] = d;
    }
}

#if defined(SWCL_W)
// The boxes the lanes grow together (sizes 0 and 1: the union of their cells
// and one cell more a side) before the lanes still unsettled go on alone.
#ifndef MN_SHARED_BOXES
#define MN_SHARED_BOXES 2
#endif
// 1: boxes a row of cells each (below; SwarmMetrics sets it where a row of
// cells is expected to hold at least as many points as lanes).
#ifndef MN_ROWS_APART
#define MN_ROWS_APART 0
#endif
// metrics_nearest on SWCL_W consecutive sorted positions per work-item (CPU
// devices; PoCL does not vectorise the scalar kernel across work-items, and
// its loop was a third of a sample's time): the lanes' points are
// neighbours in the grid's order, so the lanes of one row of cells grow one
// box together, the union of their cells grown one cell per side, and every
// candidate of it is loaded once and tested against those lanes.  The box
// stops when every such lane's best distance is below its distance to
// anything outside it, or after MN_SHARED_BOXES boxes: a third box would be
// 25 rows for the one or two lanes (of 16) whose neighbour lies past a
// cell; those search on alone (metrics_search).
// The nearest point is the least (d2, index) over the whole world, found
// exactly by either search with dist2's arithmetic, so every lane gets the
// scalar kernel's answer bitwise (tests/test_swarm_metrics.cpp).  A 2-D range:
// ceil(per_world / SWCL_W) work-items for each world (get_global_id(1));
// lanes past the world's last point repeat it and write nothing.
__kernel void metrics_nearest_w(__global const float4* sp, uint n, uint per_world, __global const float4* geo,
                                __global const uint* cell_start, __global uint* nn_idx, __global float* nn_dist,
                                __global volatile uint* hist_all, __global float* vals) {
    const uint t = get_global_id(0) * SWCL_W;
    if (t >= per_world) return;
    const uint world = get_global_id(1), first = world * per_world, last = first + per_world - 1u;
    __global volatile uint* hist = hist_all + (size_t)world * M_COUNT * FB_COUNT;
    const Grid g = grid_from_geometry(geo, cell_start + (size_t)world * as_uint(geo[1].w));
    int4 cell[SWCL_W];
    int4 ulo = g.dims, uhi = (int4)(0);
    for (uint l = 0; l < SWCL_W; ++l) {
        cell[l] = grid_cell_of(&g, sp[min(first + t + l, last)]);
        ulo = min(ulo, cell[l]);
        uhi = max(uhi, cell[l]);
    }
    const swcl_uw lane = (swcl_uw)(SWCL_LANES(SWCL_LANE_I));
    const swcl_uw self = min((swcl_uw)(first + t) + lane, (swcl_uw)(last));
    const int4 top = g.dims - (int4)(1, 1, 1, 1);
    // The least (d2, index) so far in two halves, even and odd candidates of
    // each row, merged after every box: each half's update waits on its own
    // last one only (the loop was bound by that chain), and the least of
    // the two is the least of all.  The lane's own position gets d2 = NaN,
    // which is never less nor equal.
    swcl_fw best_d2 = (swcl_fw)(INFINITY), odd_d2 = (swcl_fw)(INFINITY);
    swcl_uw best = (swcl_uw)(0xffffffffu), odd = (swcl_uw)(0xffffffffu);
    // A candidate as far as the lane's best so far sets the lane's tie: the
    // strict test keeps the first of equals, not the lowest index, so such a
    // lane searches again alone (rare: equal float distances of distinct
    // points).  Without one, the least d2 was met once and is the answer.
    swcl_iw tie = (swcl_iw)(0);
    // Candidate k against the segment's lanes (the others' coordinates are
    // NaN: never less nor equal) into (bd2, bj), as metrics_visit lane by
    // lane (d = p - q, dist2's order).
#define MN_CANDIDATE_W(k, bd2, bj, SELF)                                                            \
    {                                                                                              \
        const float4 q = sp[k];                                                                    \
        const swcl_fw dx = qx - q.x, dy = qy - q.y, dz = qz - q.z;                                 \
        const swcl_fw e2 = dx * dx + dy * dy + dz * dz;                                            \
        const swcl_fw d2 = (SELF) ? select(e2, (swcl_fw)(NAN), self == (swcl_uw)(k)) : e2;         \
        const swcl_iw better = d2 < (bd2);                                                         \
        tie |= d2 == (bd2);                                                                        \
        (bd2) = select((bd2), d2, better);                                                         \
        (bj) = select((bj), (swcl_uw)(as_uint(q.w)), better);                                      \
    }
#define MN_VISIT_SELF_W(k0, k1, SELF)                                                               \
    {                                                                                              \
        uint k = (k0);                                                                             \
        for (; k + 1u < (k1); k += 2u) {                                                           \
            MN_CANDIDATE_W(k, best_d2, best, SELF)                                                 \
            MN_CANDIDATE_W(k + 1u, odd_d2, odd, SELF)                                              \
        }                                                                                          \
        if (k < (k1)) MN_CANDIDATE_W(k, best_d2, best, SELF)                                       \
    }
#if MN_ROWS_APART
    // Only ranges holding one of the lanes' own positions test for it (long
    // rows: 6 % of the kernel at 100k agents; in a fit's small worlds the
    // branch a range cost more than it saved).
    const uint own_lo = first + t, own_hi = min(first + t + SWCL_W, last + 1u);
#define MN_VISIT_W(k0, k1)                                                                          \
    if ((k1) <= own_lo || (k0) >= own_hi) MN_VISIT_SELF_W(k0, k1, false)                           \
    else MN_VISIT_SELF_W(k0, k1, true)
#else
#define MN_VISIT_W(k0, k1) MN_VISIT_SELF_W(k0, k1, true)
#endif
    float bd2[SWCL_W], sd2[SWCL_W];  // final; a segment's vector
    uint bj[SWCL_W], sj[SWCL_W];
    int ties[SWCL_W];  // a lane's bit is final after its segment (NaN is never equal)
    // With MN_ROWS_APART, the lanes in segments of one row of cells each (the
    // points are in cell order, so a segment's cells run along x): where a
    // row holds more points than there are lanes, 16 consecutive points often
    // end one row and start the next, and one box over both would be whole
    // rows wide.  Where rows hold a few points (a fit's worlds), the lanes
    // span several rows and one box over all of them is the smaller.
    for (uint s0 = 0, s1; s0 < SWCL_W; s0 = s1) {
        for (s1 = s0 + 1u; s1 < SWCL_W && (!MN_ROWS_APART || all(cell[s1].yz == cell[s0].yz)); ++s1) {
        }
        const int4 clo = MN_ROWS_APART ? cell[s0] : ulo, chi = MN_ROWS_APART ? cell[s1 - 1u] : uhi;
        // The lanes' coordinates read lane by lane for each segment (kept
        // over segments they took registers the candidate loop needs; a
        // vector load of 16 floats right after their 16 scalar stores
        // waited on them, perf annotate: a seventh of the kernel).
        const swcl_iw in = (lane >= (swcl_uw)(s0)) & (lane < (swcl_uw)(s1));
#define MN_P_(k) sp[min(first + t + SWCL_LANE_I(k), last)]
#define MN_PX_(k) MN_P_(k).x
#define MN_PY_(k) MN_P_(k).y
#define MN_PZ_(k) MN_P_(k).z
        const swcl_fw qx = select((swcl_fw)(NAN), (swcl_fw)(SWCL_LANES(MN_PX_)), in),
                      qy = select((swcl_fw)(NAN), (swcl_fw)(SWCL_LANES(MN_PY_)), in),
                      qz = select((swcl_fw)(NAN), (swcl_fw)(SWCL_LANES(MN_PZ_)), in);
#undef MN_PX_
#undef MN_PY_
#undef MN_PZ_
#undef MN_P_
        int4 plo = (int4)(1, 1, 1, 0), phi = (int4)(0, 0, 0, 0);  // empty "previous" box
        int r = 0;
        int4 lo, hi;
        bool tail = false;
        for (;; ++r) {
            lo = max(clo - (int4)(r, r, r, 0), (int4)(0, 0, 0, 0));
            hi = min(chi + (int4)(r, r, r, 0), top);
            GRID_FOR_EACH_NEW_RANGE(&g, lo, hi, plo, phi, rg) {
                MN_VISIT_W(rg.x, rg.y)
            }
            GRID_END_NEW_RANGE
            {
                const swcl_iw better = (odd_d2 < best_d2) | ((odd_d2 == best_d2) & (odd < best));
                best_d2 = select(best_d2, odd_d2, better);
                best = select(best, odd, better);
            }
            if (all(lo.xyz == (int3)(0)) && all(hi.xyz == top.xyz)) break;
            swcl_vstore_fw(best_d2, 0, sd2);
            bool done = true;
            for (uint l = s0; l < s1 && done; ++l) {
                const float bound = grid_outside_bound(&g, sp[min(first + t + l, last)], lo, hi);
                done = bound > 0.0f && sd2[l] <= bound * bound;
            }
            if (done) break;
            if (r + 1 == MN_SHARED_BOXES) {
                tail = true;
                break;
            }
            plo = lo;
            phi = hi;
        }
        // The segment's lanes are final but for those the shared boxes did
        // not settle: they go on alone, their own boxes growing from the
        // next size and skipping the shared box's cells.
        swcl_vstore_fw(best_d2, 0, sd2);
        swcl_vstore_uw(best, 0, sj);
        swcl_vstore_iw(tie, 0, ties);
        for (uint l = s0; l < s1; ++l) {
            bd2[l] = sd2[l];
            bj[l] = sj[l];
        }
        for (uint l = s0; tail && l < s1 && t + l < per_world; ++l) {
            if (ties[l]) continue;  // searched again below
            const float4 p = sp[first + t + l];
            const float bound = grid_outside_bound(&g, p, lo, hi);
            if (bound > 0.0f && bd2[l] <= bound * bound) continue;
            metrics_search(&g, sp, first + t + l, p, r + 1, lo, hi, &bd2[l], &bj[l]);
        }
    }
#undef MN_VISIT_W
#undef MN_VISIT_SELF_W
#undef MN_CANDIDATE_W
    for (uint l = 0; l < SWCL_W && t + l < per_world; ++l) {
        const float4 p = sp[first + t + l];
        if (ties[l]) {
            bd2[l] = INFINITY;
            bj[l] = 0xffffffffu;
            metrics_search(&g, sp, first + t + l, p, 0, (int4)(1, 1, 1, 0), (int4)(0, 0, 0, 0), &bd2[l], &bj[l]);
        }
        const uint i = as_uint(p.w);
        const float d = sqrt(bd2[l]);
        nn_idx[i] = bj[l];
        nn_dist[i] = d;
        count_value(hist, M_DIST, d);
        vals[(size_t)M_DIST * n + i] = d;
    }
}
#endif
