// Minimum distance enforcement (curl-noise paper §6, after Treuille et al.
// 2006): every pair closer than d_min is pushed apart, each agent by half the
// overlap along the pair's direction.  Jacobi style — every agent reads the
// positions before the pass and writes a new array — so the result does not
// depend on the order agents are processed in.
#include "lib/min_distance_common.cl"
#include "lib/prefetch.cl"
#include "lib/halves.cl"
#include "lib/lanes.cl"

// Worlds (lib/grid_common.cl): launched over (n, W), n agents a world; world
// w's d_min and seed are d_mins[w], seeds[w], its counters moved[w] (agents
// moved in this pass) and moved[W + w] (summed over passes).
#ifdef SWCL_WORLDS
#define MDE_WORLD_VIEW()                                   \
    const uint world = (uint)get_global_id(1);             \
    const size_t world_base = (size_t)world * n;           \
    pos += world_base;                                     \
    ids += world_base;                                     \
    out += world_base;                                     \
    const float d_min = d_mins[world];                     \
    const ulong seed = seeds[world];                       \
    __global volatile uint* moved_now = moved + world;     \
    __global volatile uint* moved_sum = moved + get_global_size(1) + world;
#else  // one world (lib/grid_common.cl)
#define MDE_WORLD_VIEW()                                   \
    const uint world = 0u;                                 \
    const size_t world_base = 0;                           \
    const float d_min = d_mins[0];                         \
    const ulong seed = seeds[0];                           \
    __global volatile uint* moved_now = moved;             \
    __global volatile uint* moved_sum = moved + 1;
#endif

#define MDE_WORLD_PARAMS GRID_WORLD_PARAMS, __global const float* d_mins, __global const ulong* seeds

__kernel void min_distance_enforce(__global const float4* pos, __global const uint* ids, uint n,
                                   MDE_WORLD_PARAMS, __global float4* out, __global volatile uint* moved) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    MDE_WORLD_VIEW()
    const Grid g = GRID_MAKE_WORLD(n);
    const float4 p = pos[i];
    const float d2_min = d_min * d_min;
    float3 push = (float3)(0.0f);
    bool touched = false;
    int4 lo, hi;
    grid_search_box(&g, p, d_min, &lo, &hi);
    if (hi.y - lo.y <= 1 && hi.z - lo.z <= 1) {
        // At most 2 x 2 rows (always when the cell is at least 2 d_min): their
        // slots in one loop, rows in the order of GRID_FOR_EACH_CANDIDATE, so
        // the sum is the same; one loop exit to mispredict instead of four.
        const int y1 = hi.y, z1 = hi.z;
        const uint2 r0 = grid_row_range(&g, lo.x, hi.x, lo.y, lo.z);
        const uint2 r1 = y1 > lo.y ? grid_row_range(&g, lo.x, hi.x, y1, lo.z) : (uint2)(0u);
        const uint2 r2 = z1 > lo.z ? grid_row_range(&g, lo.x, hi.x, lo.y, z1) : (uint2)(0u);
        const uint2 r3 = y1 > lo.y && z1 > lo.z ? grid_row_range(&g, lo.x, hi.x, y1, z1) : (uint2)(0u);
        const uint c1 = r0.y - r0.x, c2 = c1 + (r1.y - r1.x), c3 = c2 + (r2.y - r2.x), total = c3 + (r3.y - r3.x);
        for (uint t = 0; t < total; ++t) {
            const uint j = t < c1 ? r0.x + t : t < c2 ? r1.x + (t - c1) : t < c3 ? r2.x + (t - c2) : r3.x + (t - c3);
            MDE_CANDIDATE(i, j)
        }
    } else {
        GRID_FOR_EACH_CANDIDATE(&g, p, d_min, j) MDE_CANDIDATE(i, j) GRID_END_FOR
    }
    out[i] = (float4)(p.xyz + push, 0.0f);
    if (touched) {
        atomic_inc(moved_now);
        atomic_inc(moved_sum);
    }
}

#ifdef MDE_WIDTH
// Prefetch distances of min_distance_enforce_w: cells ahead in each row
// stream, lines (16 starts each) per stream per work-item, positions ahead
// of a row's range.  Not sensitive: 128-512 cells and 32-128 slots measured
// alike.
#define MDE_PREFETCH_CELLS 128
#define MDE_PREFETCH_LINES 4
#define MDE_PREFETCH_SLOTS 64
// min_distance_enforce on MDE_WIDTH (8 or 16) consecutive slots per
// work-item (CPU devices).  The scalar kernel's cost is its branches: every
// agent walks 4 rows of 1 to 3 candidates (cell = 2 d_min), and each short
// loop's exit mispredicts.  Here the lanes walk their own boxes in lockstep
// (rows z then y, slots ascending: each lane's visiting order, arithmetic and
// so its sum are the scalar kernel's, bitwise); a lane past its own rows or
// slots is masked.
#if MDE_WIDTH == 8
typedef float8 mde_fw;
typedef int8 mde_iw;
#define mde_any swcl_any8
#define mde_cvt_iw convert_int8
#define mde_as_uw as_uint8
#define mde_vload vload8
#define mde_vstore vstore8
#define MDE_LANE_IDS (mde_iw)(0, 1, 2, 3, 4, 5, 6, 7)
#define MDE_LAST(v) ((v).s7)
#define MDE_LANES(E) E(0), E(1), E(2), E(3), E(4), E(5), E(6), E(7)
#define MDE_EACH_LANE(E) E(0) E(1) E(2) E(3) E(4) E(5) E(6) E(7)
static inline int mde_hmax(int8 v) { const int4 b = max(v.lo, v.hi); const int2 c = max(b.lo, b.hi); return max(c.x, c.y); }
static inline int mde_hsum(int8 v) { const int4 b = v.lo + v.hi; const int2 c = b.lo + b.hi; return c.x + c.y; }
static inline int mde_hmin(int8 v) { const int4 b = min(v.lo, v.hi); const int2 c = min(b.lo, b.hi); return min(c.x, c.y); }
#elif MDE_WIDTH == 16
typedef float16 mde_fw;
typedef int16 mde_iw;
#define mde_any swcl_any16
#define mde_cvt_iw convert_int16
#define mde_as_uw as_uint16
#define mde_vload vload16
#define mde_vstore vstore16
#define MDE_LANE_IDS (mde_iw)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15)
#define MDE_LAST(v) ((v).sf)
#define MDE_LANES(E) E(0), E(1), E(2), E(3), E(4), E(5), E(6), E(7), \
                     E(8), E(9), E(a), E(b), E(c), E(d), E(e), E(f)
#define MDE_EACH_LANE(E) E(0) E(1) E(2) E(3) E(4) E(5) E(6) E(7) \
                         E(8) E(9) E(a) E(b) E(c) E(d) E(e) E(f)
static inline int mde_hmax(int16 v) {
    const int8 a = max(swcl_lo16i(v), swcl_hi16i(v)); const int4 b = max(a.lo, a.hi); const int2 c = max(b.lo, b.hi);
    return max(c.x, c.y);
}
static inline int mde_hmin(int16 v) {
    const int8 a = min(swcl_lo16i(v), swcl_hi16i(v)); const int4 b = min(a.lo, a.hi); const int2 c = min(b.lo, b.hi);
    return min(c.x, c.y);
}
static inline int mde_hsum(int16 v) {
    const int8 a = swcl_lo16i(v) + swcl_hi16i(v); const int4 b = a.lo + a.hi; const int2 c = b.lo + b.hi;
    return c.x + c.y;
}
#else
#error "MDE_WIDTH must be 8 or 16"
#endif

// The lanes of a 32-bit array at the indices idx (every index valid: callers
// send masked lanes to index 0).
#define MDE_GATHER_LANE_(k) a[idx.s##k]
static inline mde_iw mde_gather_i(__global const int* a, mde_iw idx) { return (mde_iw)(MDE_LANES(MDE_GATHER_LANE_)); }
// x, y, z of the positions at slots idx: one float4 load per lane.
#define MDE_LOAD_P_(k) const float4 P##k = pos[idx.s##k];
#define MDE_PX_(k) P##k.x
#define MDE_PY_(k) P##k.y
#define MDE_PZ_(k) P##k.z
static inline void mde_gather_xyz(__global const float4* pos, mde_iw idx, mde_fw* x, mde_fw* y, mde_fw* z) {
    MDE_EACH_LANE(MDE_LOAD_P_)
    *x = (mde_fw)(MDE_LANES(MDE_PX_));
    *y = (mde_fw)(MDE_LANES(MDE_PY_));
    *z = (mde_fw)(MDE_LANES(MDE_PZ_));
}

// grid_axis lane by lane: the same operations, so the same cells.
static inline mde_iw mde_axis(mde_fw x, float origin, float inv_cell, int n) {
    return mde_cvt_iw(clamp((x - origin) * inv_cell, 0.0f, (float)(n - 1)));
}

// Candidate slots j (lanes where in_row) at qx, qy, qz: the scalar
// MDE_CANDIDATE lane by lane.  dist2: d = p - q, d.x*d.x + d.y*d.y + d.z*d.z.
// Lanes out of their row and each lane's own slot get d2 = +inf, so the hit
// test is one compare: on AVX2 a 16-lane mask combined with & is packed to
// bytes and back (perf annotate), a select from one compare is a blend.
#define MDE_CANDIDATE_W(QX, QY, QZ)                                                                   \
    {                                                                                                 \
        const mde_fw dx = px - (QX), dy_ = py - (QY), dz_ = pz - (QZ);                                \
        mde_fw d2 = dx * dx + dy_ * dy_ + dz_ * dz_;                                                  \
        d2 = select((mde_fw)(INFINITY), d2, in_row);                                                  \
        d2 = select(d2, (mde_fw)(INFINITY), j == slot);                                               \
        const mde_iw hit = d2 < d2_min;                                                               \
        if (mde_any(hit)) {                                                                           \
            const mde_fw d = sqrt(d2);                                                                \
            const mde_fw k = 0.5f * (d_min - d);                                                      \
            mde_fw ux = dx / d, uy = dy_ / d, uz = dz_ / d;                                           \
            const mde_iw coincident = hit & (d2 == 0.0f);                                             \
            if (mde_any(coincident)) mde_coincident(coincident, slot, j, ids, seed, &ux, &uy, &uz);   \
            sx = select(sx, sx + k * ux, hit);                                                        \
            sy = select(sy, sy + k * uy, hit);                                                        \
            sz = select(sz, sz + k * uz, hit);                                                        \
            touched |= hit;                                                                           \
        }                                                                                             \
    }

// Rare: the scalar kernel's Philox direction for agents on the same point,
// lane by lane.
static inline void mde_coincident(mde_iw coincident, mde_iw slot, mde_iw j, __global const uint* ids, ulong seed,
                           mde_fw* ux, mde_fw* uy, mde_fw* uz) {
    float ax[MDE_WIDTH], ay[MDE_WIDTH], az[MDE_WIDTH];
    mde_vstore(*ux, 0, ax); mde_vstore(*uy, 0, ay); mde_vstore(*uz, 0, az);
#define MDE_COINCIDENT_(l)                                                                        \
    if (coincident.s##l) {                                                                        \
        const float3 c = coincident_direction(seed, ids[slot.s##l], ids[j.s##l]);                 \
        ax[0x##l] = c.x; ay[0x##l] = c.y; az[0x##l] = c.z;                                        \
    }
    MDE_EACH_LANE(MDE_COINCIDENT_)
#undef MDE_COINCIDENT_
    *ux = mde_vload(0, ax); *uy = mde_vload(0, ay); *uz = mde_vload(0, az);
}

__kernel void min_distance_enforce_w(__global const float4* pos, __global const uint* ids, uint n,
                                     MDE_WORLD_PARAMS, __global float4* out, __global volatile uint* moved) {
    const uint base = get_global_id(0) * MDE_WIDTH;
    if (base >= n) return;
    MDE_WORLD_VIEW()
    const Grid g = GRID_MAKE_WORLD(n);
    const int slot_base = (int)g.slot_base;  // the world's cell ranges count from its first slot
    const mde_iw slot = (int)base + MDE_LANE_IDS;
    const mde_iw live = slot < (int)n;
    mde_fw px, py, pz;
    mde_gather_xyz(pos, select((mde_iw)(0), slot, live), &px, &py, &pz);
    // grid_search_box: the cells of p - r and p + r.
    const mde_iw x0 = mde_axis(px - d_min, g.origin.x, g.inv_cell, g.dims.x);
    const mde_iw x1 = mde_axis(px + d_min, g.origin.x, g.inv_cell, g.dims.x);
    const mde_iw y0 = mde_axis(py - d_min, g.origin.y, g.inv_cell, g.dims.y);
    const mde_iw y1 = mde_axis(py + d_min, g.origin.y, g.inv_cell, g.dims.y);
    const mde_iw z0 = mde_axis(pz - d_min, g.origin.z, g.inv_cell, g.dims.z);
    const mde_iw z1 = mde_axis(pz + d_min, g.origin.z, g.inv_cell, g.dims.z);
    const int ny = mde_hmax(select((mde_iw)(0), y1 - y0, live));
    const int nz = mde_hmax(select((mde_iw)(0), z1 - z0, live));
    const float d2_min = d_min * d_min;
    mde_fw sx = (mde_fw)(0.0f), sy = (mde_fw)(0.0f), sz = (mde_fw)(0.0f);
    mde_iw touched = (mde_iw)(0);
    __global const int* cs = (__global const int*)g.cell_start;
    {
        // The slots are in cell order, so the 4 rows' cell starts are read as
        // 4 forward streams through a start array far larger than the caches
        // (a sparse grid: ~0.3 agents per cell), and each gather of them
        // waited on memory.  Prefetch a few lines of each stream ahead of
        // the last lane (MDE 20.5 -> 15 ms at 1M locusts).
        const int row = g.dims.x, plane = g.dims.x * g.dims.y;
        const int c = MDE_LAST(x0) + row * (MDE_LAST(y0) + g.dims.y * MDE_LAST(z0)) + MDE_PREFETCH_CELLS;
        if (c + row + plane + 16 * MDE_PREFETCH_LINES < plane * g.dims.z) {
            for (int l = 0; l < MDE_PREFETCH_LINES; ++l) {
                SWCL_PREFETCH(cs + c + 16 * l);
                SWCL_PREFETCH(cs + c + row + 16 * l);
                SWCL_PREFETCH(cs + c + plane + 16 * l);
                SWCL_PREFETCH(cs + c + row + plane + 16 * l);
            }
        }
    }
    for (int dz = 0; dz <= nz; ++dz) {
        const mde_iw z = z0 + dz;
        for (int dy = 0; dy <= ny; ++dy) {
            const mde_iw y = y0 + dy;
            const mde_iw row_ok = live & (z <= z1) & (y <= y1);
            // grid_row_range (indices below 2^31: the host checks the cell count)
            const mde_iw row = g.dims.x * (y + g.dims.y * z);
            const mde_iw j0 = mde_gather_i(cs, select((mde_iw)(0), row + x0, row_ok)) - slot_base;
            const mde_iw j1 = mde_gather_i(cs, select((mde_iw)(0), row + x1 + 1, row_ok)) - slot_base;
            const mde_iw len = select((mde_iw)(0), j1 - j0, row_ok);
            const int steps = mde_hmax(len);
            // Lanes whose ranges lie close together in the slot order (the
            // same row, or neighbouring rows of a dense grid): walk the union
            // of the ranges once, each candidate loaded once for all lanes.
            // Otherwise each lane its own range, in lockstep.
            const int lo = mde_hmin(select((mde_iw)(INT_MAX), j0, row_ok));
            const int hi = mde_hmax(select((mde_iw)(0), j1, row_ok));
            if (hi + MDE_PREFETCH_SLOTS < (int)n) SWCL_PREFETCH(pos + hi + MDE_PREFETCH_SLOTS);
            if (hi - lo <= 8 * steps) {
                for (int jj = lo; jj < hi; ++jj) {
                    const float4 qv = pos[jj];
                    const mde_iw j = (mde_iw)(jj);
                    // j0 <= j < j1 on a row_ok lane (len = 0 elsewhere): one unsigned compare
                    const mde_iw in_row = mde_as_uw(j - j0) < mde_as_uw(len);
                    MDE_CANDIDATE_W((mde_fw)(qv.x), (mde_fw)(qv.y), (mde_fw)(qv.z))
                }
            } else {
                for (int t = 0; t < steps; ++t) {
                    const mde_iw j = j0 + t;
                    const mde_iw in_row = (mde_iw)(t) < len;
                    mde_fw qx, qy, qz;
                    mde_gather_xyz(pos, select((mde_iw)(0), j, in_row), &qx, &qy, &qz);
                    MDE_CANDIDATE_W(qx, qy, qz)
                }
            }
        }
    }
    const mde_fw ox = px + sx, oy = py + sy, oz = pz + sz;
#define MDE_STORE_(l) \
    if (base + 0x##l < n) out[base + 0x##l] = (float4)(ox.s##l, oy.s##l, oz.s##l, 0.0f);
    MDE_EACH_LANE(MDE_STORE_)
#undef MDE_STORE_
    const uint count = (uint)mde_hsum(touched & 1);
    if (count) {
        atomic_add(moved_now, count);
        atomic_add(moved_sum, count);
    }
}
#endif
