// A uniform grid over any points at any cell size (spatial/point_grid.hpp):
// the geometry from the points' bounding box (or given by the host), a cell
// key per slot, the slots sorted by cell with grid.cl's stable radix sort
// (so by slot within a cell), and each cell's range of sorted slots.  The
// points are not moved.  Everything is deterministic: min/max are exact, the
// sort is stable and each cell's range is written by exactly one work-item.
//
// Geometry (geo[0], geo[1]): grid_common.cl grid_from_geometry.
#include "lib/grid_common.cl"

// Chunk b's bounding box: part[2 b], part[2 b + 1] (empty: +inf, -inf).
// Groups (each its own geometry): `groups` runs of n / groups points, each
// cut into nchunks chunks as that run alone would be (group g's chunks are
// b in [g nchunks, (g + 1) nchunks)); groups = 1: the n points.
__kernel void point_grid_bounds(__global const float4* pos, uint n, uint nchunks, uint groups,
                                __global float4* part) {
    const uint b = get_global_id(0);
    if (b >= nchunks * groups) return;
    const uint per = n / groups, first = (b / nchunks) * per, c = b % nchunks;
    const uint size = (per + nchunks - 1u) / nchunks;
    const uint begin = first + min(c * size, per), end = first + min(c * size + size, per);
    float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
    for (uint s = begin; s < end; ++s) {
        const float4 p = (float4)(pos[s].xyz, 0.0f);
        lo = fmin(lo, p);
        hi = fmax(hi, p);
    }
    part[2 * b] = lo;
    part[2 * b + 1] = hi;
}

// One work-item per geometry: the box of its nchunks chunks, then the cell
// edge h >= h_min with at most max_cells cells over it.  Groups with their own
// geometry: item g reads group g's chunks and writes geo[2 g], geo[2 g + 1],
// whose w is then key_stride (the keys between groups, the same for all,
// >= each product); key_stride 0 (one geometry): the product of the dims.
// h_min: group g's is h_mins[g] when key_stride != 0 (h_mins unread else).
__kernel void point_grid_geometry(__global const float4* part, uint nchunks, float h_min,
                                  __global const float* h_mins, uint max_cells, uint groups, uint key_stride,
                                  __global float4* geo) {
    const uint gi = get_global_id(0);
    if (gi >= groups) return;
    if (key_stride) h_min = h_mins[gi];
    part += (size_t)2 * nchunks * gi;
    geo += (size_t)2 * gi;
    float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
    for (uint b = 0; b < nchunks; ++b) {
        lo = fmin(lo, part[2 * b]);
        hi = fmax(hi, part[2 * b + 1]);
    }
    float4 ext = hi - lo;
    // No points, or a box too large for a float volume: one cell (points are
    // clamped into it; queries stay exact, only slow).
    if (!(lo.x <= hi.x) || !(ext.x * ext.y * ext.z < INFINITY)) ext = (float4)(0.0f);
    if (!(lo.x <= hi.x)) lo = (float4)(0.0f);
    float h = fmax(h_min, cbrt(ext.x * ext.y * ext.z / (float)max_cells));
    float4 fd;
    for (;;) {  // cells per axis counted in float, so a huge extent cannot overflow
        fd = floor(ext / h) + 1.0f;
        const float m = (float)max_cells;
        if (fd.x <= m && fd.y <= m && fd.z <= m &&
            (ulong)fd.x * (ulong)fd.y * (ulong)fd.z <= (ulong)max_cells)
            break;
        h *= 1.25f;
    }
    const int4 dims = (int4)((int)fd.x, (int)fd.y, (int)fd.z, 0);
    geo[0] = (float4)(lo.xyz, 1.0f / h);
    geo[1] = (float4)(as_float(dims.x), as_float(dims.y), as_float(dims.z),
                      as_float(key_stride ? key_stride : (uint)(dims.x * dims.y * dims.z)));
}

// keys[s] = cell of slot s, slots[s] = s; *count = n (the radix sort's
// length).  Groups (worlds) of per_group consecutive slots each: group g's
// cells are keys [g cells, (g + 1) cells), so the sort orders by group, then
// cell (per_group = n: one group, keys the cells).  own_geometry: group g's
// cells are those of its own geometry geo[2 g], geo[2 g + 1].
__kernel void point_grid_keys(__global const float4* pos, uint n, uint per_group, uint own_geometry,
                              __global const float4* geo, __global uint* keys, __global uint* slots,
                              __global uint* count) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    if (s == 0) *count = n;
    if (own_geometry) geo += (size_t)2 * (s / per_group);
    const Grid g = grid_from_geometry(geo, 0);
    const uint cells = as_uint(geo[1].w);
    keys[s] = (s / per_group) * cells + grid_cell_index(&g, grid_cell_of(&g, (float4)(pos[s].xyz, 0.0f)));
    slots[s] = s;
}

// start[c] = first sorted slot of key c, for c in [0, groups ncells] (ncells:
// the geometry's): item k writes the keys in (key[k - 1], key[k]], item n
// the rest.
__kernel void point_grid_starts(__global const uint* skeys, uint n, uint groups, __global const float4* geo,
                                __global uint* start) {
    const uint k = get_global_id(0);
    if (k > n) return;
    const uint from = k == 0u ? 0u : skeys[k - 1u] + 1u;
    const uint to = k == n ? groups * as_uint(geo[1].w) : skeys[k];
    for (uint c = from; c <= to; ++c) start[c] = k;
}
