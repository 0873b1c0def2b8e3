// Building the neighbour grid: cell key per agent, a deterministic sort of
// agent slots by (cell, agent id) without atomics, cell ranges, and the
// reordering of agent data into cell order.
//
// The sort starts from the "layout", the order the state is in now: the cell
// of every slot (old_key) and the cell ranges (old_start) of the last build
// whose permutation was applied.  (An invalid layout has old_key = ncells,
// "no cell", and old_start all zero: every agent then counts as moved.)  An
// agent still in its layout cell is a "stayer"; the stayers, in slot order,
// are already sorted by (cell, id).  Only the "movers" are sorted: compacted
// in slot order, sorted by cell with a stable LSD radix sort (per-block digit
// histograms, no atomics), then each cell's movers are sorted by id and
// merged into its stayers.  With
//   L[c] = movers whose old cell is below c,  A[c] = movers whose new cell is below c,
// the new start of cell c is old_start[c] - L[c] + A[c]: no counts and no
// scan over the cells.  A simulation step moves a few agents to another
// cell, so a rebuild costs a few streaming passes over the slots and a sort
// of the movers; a fresh write in random order sorts everything with the
// same kernels.
//
// Every kernel's result depends only on its inputs (no atomics, fixed
// partitions), and the final order is by (cell, id): two runs give bitwise
// the same order, whatever the history.
//
// Chunked kernels: work-item b of `nchunks` loops serially over a contiguous
// chunk (no barriers or local memory; PoCL runs such loops well on a CPU).
#include "grid_common.cl"

inline uint chunk_size(uint n, uint nchunks) { return (n + nchunks - 1u) / nchunks; }

// Chunk b: keys[s] = cell of the agent in slot s, and counts[b] = movers in
// the chunk.  The cell is grid_cell_of()'s, computed as clamp then truncate,
// which equals floor then clamp for every input (truncation is floor on
// [0, dims-1]; below 0 and above dims-1 both clamp to the same bound; NaN
// goes through the same clamp) and is several times faster on PoCL than the
// scalar floor.
__kernel void grid_keys_count(__global const float4* pos, uint n, GRID_PARAMS, __global const uint* old_key,
                              uint nchunks, __global uint* keys, __global uint* counts) {
    const uint b = get_global_id(0);
    if (b >= nchunks) return;
    const uint size = chunk_size(n, nchunks);
    const uint begin = min(b * size, n), end = min(begin + size, n);
    const float4 hi = convert_float4(grid_dims - 1);
    const uint dx = (uint)grid_dims.x, dxy = (uint)grid_dims.x * (uint)grid_dims.y;
    uint count = 0;
    for (uint s = begin; s < end; ++s) {
        const float4 f = clamp((pos[s] - grid_origin) * grid_inv_cell, (float4)(0.0f), hi);
        const uint4 q = convert_uint4(f);
        const uint key = q.x + dx * q.y + dxy * q.z;
        keys[s] = key;
        count += key != old_key[s] ? 1u : 0u;
    }
    counts[b] = count;
}

// Compacts the movers in slot order: r_key = new cell, r_slot = slot, r_id =
// agent id, r_old = layout cell (ascending, as the layout is sorted by cell).
// The last chunk writes the number of movers to *m.
__kernel void grid_movers_write(__global const uint* keys, __global const uint* old_key, __global const uint* ids,
                                uint n, uint nchunks, __global const uint* counts, __global uint* r_key,
                                __global uint* r_slot, __global uint* r_id, __global uint* r_old,
                                __global uint* m) {
    const uint b = get_global_id(0);
    if (b >= nchunks) return;
    uint out = 0;
    for (uint i = 0; i < b; ++i) out += counts[i];
    if (b == nchunks - 1u) *m = out + counts[b];
    if (counts[b] == 0u) return;
    const uint size = chunk_size(n, nchunks);
    const uint begin = min(b * size, n), end = min(begin + size, n);
    for (uint s = begin; s < end; ++s) {
        const uint k = keys[s], o = old_key[s];
        if (k != o) {
            r_key[out] = k;
            r_slot[out] = s;
            r_id[out] = ids[s];
            r_old[out] = o;
            ++out;
        }
    }
}

// The first index of the ascending arr[0, m) whose value is >= v.
inline uint lower_bound(__global const uint* arr, uint m, uint v) {
    uint lo = 0u, hi = m;
    while (lo < hi) {
        const uint mid = lo + (hi - lo) / 2u;
        if (arr[mid] < v) lo = mid + 1u; else hi = mid;
    }
    return lo;
}

// Stable LSD radix sort of the *m movers by cell, one digit per pass.
// Pass 1: hist[d * nblocks + b] = values of digit d in block b.
__kernel void radix_hist(__global const uint* keys, __global const uint* m_ptr, uint shift, uint mask,
                         uint nblocks, __global uint* hist) {
    const uint b = get_global_id(0);
    if (b >= nblocks) return;
    for (uint d = 0; d <= mask; ++d) hist[d * nblocks + b] = 0u;
    const uint m = *m_ptr;
    const uint size = chunk_size(m, nblocks);
    const uint begin = min(b * size, m), end = min(begin + size, m);
    for (uint j = begin; j < end; ++j) hist[((keys[j] >> shift) & mask) * nblocks + b] += 1u;
}

// Pass 2: hist rows (one digit each) become exclusive prefixes over the
// blocks; totals[d] = values of digit d.
__kernel void radix_rows(__global uint* hist, uint nblocks, uint radix, __global uint* totals) {
    const uint d = get_global_id(0);
    if (d >= radix) return;
    __global uint* row = hist + d * nblocks;
    uint running = 0;
    for (uint b = 0; b < nblocks; ++b) {
        const uint v = row[b];
        row[b] = running;
        running += v;
    }
    totals[d] = running;
}

// Pass 3: block b adds the digit bases (prefix of totals: digit-major, so the
// order is stable) to its column of offsets, then scatters its values in
// order.
__kernel void radix_scatter(__global const uint* keys, __global const uint* slots, __global const uint* ids,
                            __global const uint* m_ptr, uint shift, uint mask, uint nblocks,
                            __global uint* offsets, __global const uint* totals, __global uint* keys_out, __global uint* slots_out,
                            __global uint* ids_out) {
    const uint b = get_global_id(0);
    if (b >= nblocks) return;
    const uint m = *m_ptr;
    const uint size = chunk_size(m, nblocks);
    const uint begin = min(b * size, m), end = min(begin + size, m);
    if (begin >= end) return;
    uint base = 0;
    for (uint d = 0; d <= mask; ++d) {
        offsets[d * nblocks + b] += base;
        base += totals[d];
    }
    for (uint j = begin; j < end; ++j) {
        const uint k = keys[j];
        const uint o = offsets[((k >> shift) & mask) * nblocks + b]++;
        keys_out[o] = k;
        slots_out[o] = slots[j];
        ids_out[o] = ids[j];
    }
}

// Sorts a few movers (slot[i], id[i]) by id: insertion sort when short or
// nearly sorted, heap sort for crowded cells so the cost stays n log n.
inline void swap_pair(__global uint* slot, __global uint* id, uint a, uint b) {
    const uint ts = slot[a], ti = id[a];
    slot[a] = slot[b];
    id[a] = id[b];
    slot[b] = ts;
    id[b] = ti;
}

inline void sift_down(__global uint* slot, __global uint* id, uint root, uint end) {
    while (2u * root + 1u < end) {
        uint child = 2u * root + 1u;
        if (child + 1u < end && id[child + 1u] > id[child]) child++;
        if (id[root] >= id[child]) return;
        swap_pair(slot, id, root, child);
        root = child;
    }
}

inline void sort_by_id(__global uint* slot, __global uint* id, uint len) {
    uint descents = 0;
    for (uint i = 1; i < len; ++i) descents += id[i - 1u] > id[i] ? 1u : 0u;
    if (descents == 0u) return;
    if (len <= 32u || descents <= 2u) {
        for (uint i = 1; i < len; ++i) {
            const uint vs = slot[i], vi = id[i];
            uint j = i;
            while (j > 0 && id[j - 1u] > vi) {
                slot[j] = slot[j - 1u];
                id[j] = id[j - 1u];
                --j;
            }
            slot[j] = vs;
            id[j] = vi;
        }
        return;
    }
    for (uint i = len / 2u; i-- > 0u;) sift_down(slot, id, i, len);
    for (uint e = len - 1u; e > 0u; --e) {
        swap_pair(slot, id, 0u, e);
        sift_down(slot, id, 0u, e);
    }
}

// The new order, cells [b * cells_per_item, ...) per work-item.  With the
// movers' layout cells r_old (ascending) and new cells m_key (sorted), L[c]
// and A[c] are positions in those arrays, found by one binary search per
// work-item and then walked.  start[c] = old_start[c] - L[c] + A[c];
// perm[new slot] = old slot: the cell's stayers (in layout order, so by id;
// every slot of the layout range when none left the cell) merged by id with
// its movers (m_slot/m_id [A[c], A[c+1]), sorted by id here in place);
// new_key[new slot] = cell (the next layout).  start[ncells] = n.
__kernel void grid_place(__global const uint* keys, uint n, __global const uint* old_start,
                         __global const uint* r_old, __global const uint* m_ptr, __global const uint* m_key,
                         __global uint* m_slot, __global uint* m_id, __global const uint* ids, uint ncells,
                         uint cells_per_item, __global uint* start, __global uint* perm, __global uint* new_key) {
    const uint b = get_global_id(0);
    const uint c0 = b * cells_per_item;
    if (c0 >= ncells) return;
    const uint c1 = min(c0 + cells_per_item, ncells);
    const uint m = *m_ptr;
    uint l = lower_bound(r_old, m, c0), a = lower_bound(m_key, m, c0);
    uint os = old_start[c0];
    uint t = os - l + a;
    for (uint c = c0; c < c1; ++c) {
        // Cells [c, e) before the next one a mover leaves or enters hold
        // stayers only, in layout order: their ranges all shift by the same
        // delta, so they are placed in streaming passes, not cell by cell
        // (the common case of a simulation step, and of sparse grids).
        const uint e = min(min(l < m ? r_old[l] : ncells, a < m ? m_key[a] : ncells), c1);
        if (e > c) {
            const uint delta = t - os;  // wraps as uint: start = old + delta
            for (uint k = c; k < e; ++k) start[k] = old_start[k] + delta;
            const uint oe = old_start[e];
            for (uint s = os; s < oe; ++s) {
                perm[s + delta] = s;
                new_key[s + delta] = keys[s];  // a stayer: its cell
            }
            t += oe - os;
            os = oe;
            c = e - 1u;
            continue;
        }
        const uint oe = old_start[c + 1u];
        uint l1 = l, a1 = a;
        while (l1 < m && r_old[l1] == c) ++l1;
        while (a1 < m && m_key[a1] == c) ++a1;
        const uint ns = t;
        start[c] = ns;
        if (l1 == l) {
            for (uint s = os; s < oe; ++s) perm[t++] = s;
        } else {
            for (uint s = os; s < oe; ++s)
                if (keys[s] == c) perm[t++] = s;
        }
        if (a1 > a) {
            const uint na = a1 - a;
            __global uint* ms = m_slot + a;
            __global uint* mi = m_id + a;
            sort_by_id(ms, mi, na);
            // Merge from the back: stayers perm[ns, t), movers [0, na).
            uint i = t - ns, j = na, k = t + na;
            uint si = i > 0u ? ids[perm[ns + i - 1u]] : 0u;
            while (j > 0u) {
                if (i > 0u && si > mi[j - 1u]) {
                    perm[--k] = perm[ns + --i];
                    si = i > 0u ? ids[perm[ns + i - 1u]] : 0u;
                } else {
                    perm[--k] = ms[--j];
                }
            }
            t += na;
        }
        for (uint s = ns; s < t; ++s) new_key[s] = c;
        os = oe;
        l = l1;
        a = a1;
    }
    if (c1 == ncells) start[ncells] = n;
}

// Reordering into cell order: dst[s] = src[perm[s]].
// Positions, velocities and ids in one pass over perm.
__kernel void permute_state(__global const float4* pos, __global const float4* vel, __global const uint* ids,
                            __global const uint* perm, uint n, __global float4* pos_out,
                            __global float4* vel_out, __global uint* ids_out) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const uint p = perm[s];
    pos_out[s] = pos[p];
    vel_out[s] = vel[p];
    ids_out[s] = ids[p];
}
