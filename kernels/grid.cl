// Building the neighbour grid: cell key per agent, a stable deterministic
// counting sort of agents by cell, cell ranges, and the reordering of agent
// data into cell order.
//
// Determinism without ordered atomics: the scatter takes slots inside a cell
// with atomics (order varies run to run), then each cell's slice is sorted by
// agent id.  The result depends only on (cell, id): bitwise the same order on
// every run, and stable with respect to agent id.
#include "grid_common.cl"

// keys[s] = cell of the agent in slot s; counts[cell] += 1 (counts zeroed).
__kernel void grid_count(__global const float4* pos, uint n, GRID_PARAMS,
                         __global uint* keys, __global volatile uint* counts) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const Grid g = GRID_MAKE();
    const uint key = grid_cell_index(&g, grid_cell_of(&g, pos[s]));
    keys[s] = key;
    atomic_inc(&counts[key]);
}

// Scan, pass 1: sums[b] = sum of counts in block b.
__kernel void grid_scan_blocks(__global const uint* counts, uint ncells, uint block,
                               __global uint* sums) {
    const uint b = get_global_id(0);
    const uint begin = b * block;
    if (begin >= ncells) return;
    const uint end = min(begin + block, ncells);
    uint total = 0;
    for (uint c = begin; c < end; ++c) total += counts[c];
    sums[b] = total;
}

// Scan, pass 2 (one work-item): exclusive scan of the block sums in place.
__kernel void grid_scan_top(__global uint* sums, uint nblocks) {
    if (get_global_id(0) != 0) return;
    uint running = 0;
    for (uint b = 0; b < nblocks; ++b) {
        const uint v = sums[b];
        sums[b] = running;
        running += v;
    }
}

// Scan, pass 3: start[c] = exclusive prefix of counts; start[ncells] = n.
__kernel void grid_scan_write(__global const uint* counts, uint ncells, uint block,
                              __global const uint* sums, __global uint* start, uint n) {
    const uint b = get_global_id(0);
    const uint begin = b * block;
    if (begin >= ncells) return;
    const uint end = min(begin + block, ncells);
    uint running = sums[b];
    for (uint c = begin; c < end; ++c) {
        start[c] = running;
        running += counts[c];
    }
    if (end == ncells) start[ncells] = n;
}

// Scatter: perm[new slot] = old slot.  Decrementing the counts takes a slot in
// the cell and leaves the counts at zero, ready for the next build.
__kernel void grid_scatter(__global const uint* keys, uint n, __global const uint* start,
                           __global volatile uint* counts, __global uint* perm) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const uint key = keys[s];
    const uint slot = start[key] + atomic_dec(&counts[key]) - 1u;
    perm[slot] = s;
}

// Sorts each cell's slice of perm by agent id.  Cells are small (a few agents)
// so insertion sort; a crowded cell (everything in one cell) falls back to
// heap sort so the cost stays n log n.
inline void sift_down(__global uint* a, __global const uint* ids, uint root, uint end) {
    while (2u * root + 1u < end) {
        uint child = 2u * root + 1u;
        if (child + 1u < end && ids[a[child + 1u]] > ids[a[child]]) child++;
        if (ids[a[root]] >= ids[a[child]]) return;
        const uint t = a[root]; a[root] = a[child]; a[child] = t;
        root = child;
    }
}

__kernel void grid_sort_cells(__global const uint* start, uint ncells, __global const uint* ids,
                              __global uint* perm) {
    const uint c = get_global_id(0);
    if (c >= ncells) return;
    const uint begin = start[c], end = start[c + 1];
    const uint len = end - begin;
    if (len < 2u) return;
    __global uint* a = perm + begin;
    if (len <= 32u) {
        for (uint i = 1; i < len; ++i) {
            const uint v = a[i];
            const uint key = ids[v];
            uint j = i;
            while (j > 0 && ids[a[j - 1]] > key) { a[j] = a[j - 1]; --j; }
            a[j] = v;
        }
        return;
    }
    for (uint i = len / 2u; i-- > 0u;) sift_down(a, ids, i, len);
    for (uint e = len - 1u; e > 0u; --e) {
        const uint t = a[0]; a[0] = a[e]; a[e] = t;
        sift_down(a, ids, 0u, e);
    }
}

// Reordering into cell order: dst[s] = src[perm[s]].
__kernel void permute_float4(__global const float4* src, __global const uint* perm, uint n,
                             __global float4* dst) {
    const uint s = get_global_id(0);
    if (s < n) dst[s] = src[perm[s]];
}

// ids follow the permutation; slot_of maps each id back to its new slot.
__kernel void permute_ids(__global const uint* src_ids, __global const uint* perm, uint n,
                          __global uint* dst_ids, __global uint* slot_of) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const uint id = src_ids[perm[s]];
    dst_ids[s] = id;
    slot_of[id] = s;
}
