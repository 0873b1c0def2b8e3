// Neighbour queries over the grid, one work-item per agent slot (cell order,
// so neighbouring work-items read the same cells).  Results are written in
// agent-id order through ids[].  Launched over (n, W) for W worlds of n
// agents (lib/grid_common.cl): each world's queries see its own agents only,
// ids and results are the world's (ids from 0), results at world w n + id.
#include "lib/grid_common.cl"
#include "lib/lanes.cl"

#ifdef SWCL_WORLDS
#define NB_WORLD_VIEW()                                       \
    const size_t world_base = (size_t)get_global_id(1) * n;   \
    pos += world_base;                                        \
    ids += world_base;                                        \
    const Grid g = GRID_MAKE_WORLD(n);
#else  // one world (lib/grid_common.cl)
#define NB_WORLD_VIEW()                                       \
    const size_t world_base = 0;                              \
    const Grid g = GRID_MAKE();
#endif

#define NO_AGENT 0xFFFFFFFFu

__kernel void neighbor_count(__global const float4* pos, __global const uint* ids, uint n,
                             GRID_WORLD_PARAMS, float radius, __global uint* out_counts) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    NB_WORLD_VIEW()
    out_counts += world_base;
    const float4 p = pos[i];
    const float r2 = radius * radius;
    uint count = 0;
    GRID_FOR_EACH_CANDIDATE(&g, p, radius, j) {
        count += (j != i && dist2(p, pos[j]) <= r2) ? 1u : 0u;
    } GRID_END_FOR
    out_counts[ids[i]] = count;
}

#if defined(SWCL_W)
// neighbor_count for SWCL_W consecutive slots a work-item (CPU devices,
// launch ceil(n / SWCL_W) a world; PoCL runs the scalar kernel one agent at
// a time).  The lanes' slots are neighbours in cell order, so their search
// boxes overlap: the union of the boxes is walked cell by cell, each cell's
// candidates loaded once and tested against the lanes whose own box holds
// the cell (so each lane counts exactly the candidates the scalar kernel
// visits, with dist2's arithmetic: the same counts).  Lanes past n repeat
// slot n - 1 and write nothing.
__kernel void neighbor_count_w(__global const float4* pos, __global const uint* ids, uint n,
                               GRID_WORLD_PARAMS, float radius, __global uint* out_counts) {
    const uint base = get_global_id(0) * SWCL_W;
    if (base >= n) return;
    NB_WORLD_VIEW()
    out_counts += world_base;
    const float r2 = radius * radius;
    float lx[SWCL_W], ly[SWCL_W], lz[SWCL_W];
    int blo[3][SWCL_W], bhi[3][SWCL_W];
    int4 lo = g.dims, hi = (int4)(0);
    for (uint l = 0; l < SWCL_W; ++l) {
        const float4 p = pos[min(base + l, n - 1u)];
        lx[l] = p.x;
        ly[l] = p.y;
        lz[l] = p.z;
        int4 a, b;
        grid_search_box(&g, p, radius, &a, &b);  // the scalar kernel's box
        blo[0][l] = a.x, blo[1][l] = a.y, blo[2][l] = a.z;
        bhi[0][l] = b.x, bhi[1][l] = b.y, bhi[2][l] = b.z;
        lo = min(lo, a);
        hi = max(hi, b);
    }
    const swcl_fw px = swcl_vload_fw(0, lx), py = swcl_vload_fw(0, ly), pz = swcl_vload_fw(0, lz);
    const swcl_iw lox = swcl_vload_iw(0, blo[0]), loy = swcl_vload_iw(0, blo[1]), loz = swcl_vload_iw(0, blo[2]);
    const swcl_iw hix = swcl_vload_iw(0, bhi[0]), hiy = swcl_vload_iw(0, bhi[1]), hiz = swcl_vload_iw(0, bhi[2]);
    const swcl_uw self = min((swcl_uw)(base) + (swcl_uw)(SWCL_LANES(SWCL_LANE_I)), (swcl_uw)(n - 1u));
    swcl_uw count = (swcl_uw)(0u);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y) {
            const swcl_iw in_row = (loy <= y) & (y <= hiy) & (loz <= z) & (z <= hiz);
            if (!swcl_any_w(in_row)) continue;
            const uint row = (uint)g.dims.x * ((uint)y + (uint)g.dims.y * (uint)z);
            for (int x = lo.x; x <= hi.x; ++x) {
                const swcl_iw in_box = in_row & (lox <= x) & (x <= hix);
                const uint j0 = g.cell_start[row + (uint)x] - g.slot_base, j1 = g.cell_start[row + (uint)x + 1u] - g.slot_base;
                if (j0 == j1 || !swcl_any_w(in_box)) continue;
                for (uint j = j0; j < j1; ++j) {
                    const float4 q = pos[j];
                    const swcl_fw dx = px - q.x, dy = py - q.y, dz = pz - q.z;
                    const swcl_iw hit = in_box & (self != (swcl_uw)(j)) & (dx * dx + dy * dy + dz * dz <= r2);
                    count -= swcl_as_uw(hit);  // true is -1
                }
            }
        }
    uint c[SWCL_W];
    swcl_vstore_uw(count, 0, c);
    for (uint l = 0; l < SWCL_W && base + l < n; ++l) out_counts[ids[base + l]] = c[l];
}
#endif

// (d2, id) lexicographic order: deterministic ties.
static inline bool closer(float d2a, uint ida, float d2b, uint idb) {
    return d2a < d2b || (d2a == d2b && ida < idb);
}

static inline void visit_nearest(__global const float4* pos, __global const uint* ids, uint i, float4 p,
                          uint j0, uint j1, float* best_d2, uint* best_id) {
    for (uint j = j0; j < j1; ++j) {
        if (j == i) continue;
        const float d2 = dist2(p, pos[j]);
        const uint id = ids[j];
        if (closer(d2, id, *best_d2, *best_id)) { *best_d2 = d2; *best_id = id; }
    }
}

// Nearest other agent: boxes of cells growing one cell per side around the
// agent's cell, each time visiting only the cells not seen before, until the
// best distance found is below the distance to anything outside the box, or
// the box is the whole grid.
__kernel void nearest_neighbor(__global const float4* pos, __global const uint* ids, uint n,
                               GRID_WORLD_PARAMS, __global float* out_dist, __global uint* out_ids) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    NB_WORLD_VIEW()
    out_dist += world_base;
    out_ids += world_base;
    const float4 p = pos[i];
    const int4 c = grid_cell_of(&g, p);
    const int4 last = g.dims - (int4)(1, 1, 1, 1);
    float best_d2 = INFINITY;
    uint best_id = NO_AGENT;
    int4 plo = (int4)(1, 1, 1, 0), phi = (int4)(0, 0, 0, 0);  // empty "previous" box
    for (int k = 0;; ++k) {
        const int4 lo = max(c - (int4)(k, k, k, 0), (int4)(0, 0, 0, 0));
        const int4 hi = min(c + (int4)(k, k, k, 0), last);
        GRID_FOR_EACH_NEW_RANGE(&g, lo, hi, plo, phi, rg) {
            visit_nearest(pos, ids, i, p, rg.x, rg.y, &best_d2, &best_id);
        }
        GRID_END_NEW_RANGE
        const bool whole = lo.x == 0 && lo.y == 0 && lo.z == 0 && hi.x == last.x && hi.y == last.y &&
                           hi.z == last.z;
        if (whole) break;
        const float bound = grid_outside_bound(&g, p, lo, hi);
        if (bound > 0.0f && best_d2 <= bound * bound) break;
        plo = lo;
        phi = hi;
    }
    const uint id = ids[i];
    out_dist[id] = best_id == NO_AGENT ? INFINITY : sqrt(best_d2);
    out_ids[id] = best_id;
}

// Up to cap neighbours within radius, nearest first.  The list is kept sorted
// in the caller's output slice while scanning (insertion), holding slots; at
// the end slots become ids.
__kernel void neighbor_lists(__global const float4* pos, __global const uint* ids, uint n,
                             GRID_WORLD_PARAMS, float radius, uint cap, __global uint* out_list,
                             __global uint* out_counts) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    NB_WORLD_VIEW()
    out_counts += world_base;
    out_list += world_base * cap;
    const float4 p = pos[i];
    const float r2 = radius * radius;
    const uint self = ids[i];
    __global uint* list = out_list + (size_t)self * cap;
    uint count = 0, kept = 0;
    GRID_FOR_EACH_CANDIDATE(&g, p, radius, j) {
        if (j == i) continue;
        const float d2 = dist2(p, pos[j]);
        if (d2 > r2) continue;
        ++count;
        const uint id = ids[j];
        // Position in the sorted list; entries past `cap` fall off the end.
        uint at = kept;
        while (at > 0) {
            const uint other = list[at - 1];
            if (!closer(d2, id, dist2(p, pos[other]), ids[other])) break;
            --at;
        }
        if (at >= cap) continue;
        const uint last = kept < cap ? kept : cap - 1u;
        for (uint m = last; m > at; --m) list[m] = list[m - 1];
        list[at] = j;
        if (kept < cap) ++kept;
    } GRID_END_FOR
    for (uint m = 0; m < kept; ++m) list[m] = ids[list[m]];
    for (uint m = kept; m < cap; ++m) list[m] = NO_AGENT;
    out_counts[self] = count;
}
