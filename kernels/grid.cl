// Building the neighbour grid: cell key per agent, a deterministic sort of
// agent slots by (cell, agent id) without atomics, cell ranges, and the
// reordering of agent data into cell order.
//
// The sort starts from the "layout", the order the state is in now: the cell
// of every slot (old_key) of the last build whose permutation was applied.
// (An invalid layout has old_key = ncells, "no cell": every agent then counts
// as moved.)  An agent still in its layout cell is a "stayer"; the stayers,
// in slot order, are already sorted by (cell, id).  Only the "movers" are
// sorted: compacted in slot order, sorted by cell in two passes of buckets
// on CPU devices ("Movers on a CPU" below) or with a stable LSD radix sort
// (per-block digit histograms, no atomics), then each run of equal cells by
// id.  The new order is the merge of the two sorted lists (merge
// path: every work-item finds its start by a binary search), and the cell
// starts follow from the merged keys in one pass.  A simulation step moves
// some agents to another cell, so a rebuild costs a few streaming passes over
// the slots and a sort of the movers; a fresh write in random order sorts
// everything with the same kernels.  (No pass visits the cells one by one:
// a sparse grid, 4 cells per agent, costs only the writes of its starts.)
//
// Every kernel's result depends only on its inputs (no atomics, fixed
// partitions), and the final order is by (cell, id): two runs give bitwise
// the same order, whatever the history.
//
// Chunked kernels: work-item b of `nchunks` loops serially over a contiguous
// chunk (no barriers or local memory; PoCL runs such loops well on a CPU).
#include "lib/grid_common.cl"
#include "lib/prefetch.cl"

static inline uint chunk_size(uint n, uint nchunks) { return (n + nchunks - 1u) / nchunks; }

// Whether `part` of `whole` is under an eighth or over seven eighths: then a
// branch on which kind comes next is predicted nearly always, and beats
// grid_movers_write's and grid_merge's branch-free loops (whose next loads
// wait on each compare: at 5 % movers the merge took 2.4 ms for 1.1 at 1M);
// at half movers (a field-model step at 1M) the branch-free ones win.
static inline bool mostly_one_kind(uint part, uint whole) {
    return 8ul * part < (ulong)whole || 8ul * part > 7ul * whole;
}

// Whether the build writes the ids in the new order (new_id) for the
// reorder to copy: where at least an eighth of the agents moved.  The
// reorder's gather of ids by the permutation then reads anywhere in the
// array (one random line an agent after a random-order build); with fewer
// movers it reads nearly in order, and the merge's extra read and write of
// every id would cost more (0.4 ms at 1M in grid order).
static inline bool ids_from_build(uint movers, uint n) { return 8ul * movers >= (ulong)n; }

// Whether nearly every agent moved (over seven eighths: a write of new
// positions in no spatial order): the bucket sort then writes its buckets
// at random, and prefetches the lines it will write.  In a step the movers
// come in their old cells' order, nearly in sequence, and the prefetches
// measured no gain (the field model's 1M step, 35-61 % moved;
// docs/benchmarks.md, "The bucket sort's scatter").
static inline bool movers_scattered(uint movers, uint n) { return 8ul * movers > 7ul * (ulong)n; }

// The key of an agent at p: the first cell of its world + its cell there.
static inline uint grid_key(float4 p, float4 origin, float inv_cell, int4 dims, uint first) {
    const float4 hi = convert_float4(dims - 1);
    const uint dx = (uint)dims.x, dxy = (uint)dims.x * (uint)dims.y;
    const float4 f = clamp((p - origin) * inv_cell, (float4)(0.0f), hi);
    const uint4 q = convert_uint4(f);
    return q.x + dx * q.y + dxy * q.z + first;
}

// Chunk b: keys[s] = cell of the agent in slot s, and counts[b] = movers in
// the chunk.  The cell is grid_cell_of()'s, computed as clamp then truncate,
// which equals floor then clamp for every input (truncation is floor on
// [0, dims-1]; below 0 and above dims-1 both clamp to the same bound; NaN
// goes through the same clamp) and is several times faster on PoCL than the
// scalar floor.
// With worlds (grid_common.cl) the key is world w's first cell + its cell
// in w's grid, for the slots of world w = s / world_agents (a swarm without
// worlds: world_agents >= n).
__kernel void grid_keys_count(__global const float4* pos, uint n, GRID_PARAMS, __global const uint* old_key,
                              uint nchunks, __global uint* keys, __global uint* counts, uint world_agents,
                              __global const float4* grid_worlds) {
    const uint b = get_global_id(0);
    if (b >= nchunks) return;
    const uint size = chunk_size(n, nchunks);
    const uint begin = min(b * size, n), end = min(begin + size, n);
    float4 origin = grid_origin;
    float inv_cell = grid_inv_cell;
    int4 dims = grid_dims;
    uint first = 0u;
#ifdef SWCL_WORLDS
    uint world = 0xFFFFFFFFu;
#endif
    uint count = 0;
    for (uint s = begin; s < end; ++s) {
#ifdef SWCL_WORLDS
        if (s / world_agents != world) {  // a chunk spans few worlds
            world = s / world_agents;
            const Grid g = grid_of_world(GRID_MAKE(), grid_worlds, world);
            origin = g.origin;
            inv_cell = g.inv_cell;
            dims = g.dims;
            first = (uint)(g.cell_start - grid_cell_start);
        }
#endif
        const uint key = grid_key(pos[s], origin, inv_cell, dims, first);
        keys[s] = key;
        count += key != old_key[s] ? 1u : 0u;
    }
    counts[b] = count;
}

// Compacts the movers in slot order: r_key = new cell, r_slot = slot, r_id =
// agent id; and the stayers' slots in slot order (st_slot: sorted by (cell,
// id), as the layout is).  The last chunk writes the number of movers to *m.
__kernel void grid_movers_write(__global const uint* keys, __global const uint* old_key, __global const uint* ids,
                                uint n, uint nchunks, __global const uint* counts, __global uint* r_key,
                                __global uint* r_slot, __global uint* r_id, __global uint* st_slot,
                                __global uint* m) {
    const uint b = get_global_id(0);
    if (b >= nchunks) return;
    uint out = 0;
    for (uint i = 0; i < b; ++i) out += counts[i];
    if (b == nchunks - 1u) *m = out + counts[b];
    const uint size = chunk_size(n, nchunks);
    const uint begin = min(b * size, n), end = min(begin + size, n);
    uint stay = begin - out;  // stayers before this chunk
    if (counts[b] == 0u) {
        for (uint s = begin; s < end; ++s) st_slot[stay++] = s;
        return;
    }
    // Both outputs written, one kept: no branch on whether the agent moved
    // (half of them do in a field-model step at 1M, unpredictably).  A
    // stayer's write to r_*[out] is overwritten by the chunk's next mover, a
    // mover's to st_slot[stay] by its next stayer; so while both have one
    // to come, which the chunk's count tells.  Then the rest are all one.
    if (mostly_one_kind(counts[b], end - begin)) {
        for (uint s = begin; s < end; ++s) {
            if (keys[s] != old_key[s]) {
                r_key[out] = keys[s];
                r_slot[out] = s;
                r_id[out] = ids[s];
                ++out;
            } else {
                st_slot[stay++] = s;
            }
        }
        return;
    }
    const uint out_end = out + counts[b], stay_end = stay + (end - begin - counts[b]);
    uint s = begin;
    for (; out < out_end && stay < stay_end; ++s) {
        const uint k = keys[s];
        const uint moved = k != old_key[s] ? 1u : 0u;
        r_key[out] = k;
        r_slot[out] = s;
        r_id[out] = ids[s];
        st_slot[stay] = s;
        out += moved;
        stay += 1u - moved;
    }
    for (; stay < stay_end; ++s) st_slot[stay++] = s;
    for (; out < out_end; ++s) {
        r_key[out] = keys[s];
        r_slot[out] = s;
        r_id[out] = ids[s];
        ++out;
    }
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
// Block b's values [*begin, *end) of the *m_ptr, and its column of
// offsets made places (the digit bases added); false when it has none.
static inline bool radix_block(__global const uint* m_ptr, uint mask, uint nblocks, __global uint* offsets,
                               __global const uint* totals, uint b, uint* begin, uint* end) {
    const uint m = *m_ptr;
    const uint size = chunk_size(m, nblocks);
    *begin = min(b * size, m);
    *end = min(*begin + size, m);
    if (*begin >= *end) return false;
    uint base = 0;
    for (uint d = 0; d <= mask; ++d) {
        offsets[d * nblocks + b] += base;
        base += totals[d];
    }
    return true;
}

// The place of block b's next value of key k (its digit's offset, advanced).
static inline uint radix_place(__global uint* offsets, uint k, uint shift, uint mask, uint nblocks, uint b) {
    return offsets[((k >> shift) & mask) * nblocks + b]++;
}

__kernel void radix_scatter(__global const uint* keys, __global const uint* slots, __global const uint* ids,
                            __global const uint* m_ptr, uint shift, uint mask, uint nblocks,
                            __global uint* offsets, __global const uint* totals, __global uint* keys_out, __global uint* slots_out,
                            __global uint* ids_out) {
    const uint b = get_global_id(0);
    uint begin, end;
    if (b >= nblocks || !radix_block(m_ptr, mask, nblocks, offsets, totals, b, &begin, &end)) return;
    for (uint j = begin; j < end; ++j) {
        const uint k = keys[j];
        const uint o = radix_place(offsets, k, shift, mask, nblocks, b);
        keys_out[o] = k;
        slots_out[o] = slots[j];
        ids_out[o] = ids[j];
    }
}

// Sorts a few movers (slot[i], id[i]) by id: by rank up to 16, else
// insertion sort when short or nearly sorted, heap sort for crowded cells so
// the cost stays n log n.
static inline void swap_pair(__global uint* slot, __global uint* id, uint a, uint b) {
    const uint ts = slot[a], ti = id[a];
    slot[a] = slot[b];
    id[a] = id[b];
    slot[b] = ts;
    id[b] = ti;
}

static inline void sift_down(__global uint* slot, __global uint* id, uint root, uint end) {
    while (2u * root + 1u < end) {
        uint child = 2u * root + 1u;
        if (child + 1u < end && id[child + 1u] > id[child]) child++;
        if (id[root] >= id[child]) return;
        swap_pair(slot, id, root, child);
        root = child;
    }
}

// A run of 2 to 16 by rank: each value's place is the count of smaller ids
// (unique within a cell's world), 16 compares a value whatever the length
// (the padding, UINT_MAX, is smaller than none), so no branch depends on
// the ids; every rank first, then the stores.  Insertion sort mispredicted
// about once a value: at 1M random movers it was most of the sort
// (docs/benchmarks.md, "Movers in buckets").
#define SHORT_RUN 16u
static inline void sort_short_run(__global uint* slot, __global uint* id, uint len) {
    uint a[SHORT_RUN], s[SHORT_RUN];
    for (uint k = 0; k < SHORT_RUN; ++k) a[k] = UINT_MAX;
    for (uint k = 0; k < len; ++k) {
        a[k] = id[k];
        s[k] = slot[k];
    }
    const uint16 v = vload16(0, a);
    int16 below = (int16)(0);
    for (uint j = 0; j < SHORT_RUN; ++j) below += v > (uint16)(a[j]);  // -1 where a[j] is smaller
    uint rank[SHORT_RUN];
    vstore16(as_uint16(-below), 0, rank);
    for (uint i = 0; i < len; ++i) {
        id[rank[i]] = a[i];
        slot[rank[i]] = s[i];
    }
}

static inline void sort_by_id(__global uint* slot, __global uint* id, uint len) {
    if (len <= SHORT_RUN) {
        sort_short_run(slot, id, len);
        return;
    }
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

// ---- Movers on a CPU: a bucket sort in two passes (NeighborGrid) ----
// The radix sort scattered three columns twice, into 512 places a block each
// time: at 1M random movers its writes were most of the build.  Here pass 1
// (radix_hist and radix_rows on the key's high digit, then bucket_scatter)
// moves each mover once, as one (key, slot, id) record into its bucket:
// stable, and in a simulation step nearly streaming, as movers come in slot
// order, which is their old cells' order.  Pass 2 (grid_sort_buckets) sorts
// each bucket, a few thousand records in the cache, by the low digit into
// the key, slot and id columns, then each run of equal keys by id: the
// radix sort and grid_sort_runs' result, bitwise.
// Either digit's counters live in private memory: at most 2^11 (8 KB; the
// host splits keys of up to 22 bits, the high digit no wider than the low).
#define BUCKET_MAX_LOW_BITS 11u

// The block's places are copied to private counters first: in the offsets
// table each digit's counter of the block is on its own cache line (digit-
// major, for radix_rows), and at 1M random movers a quarter of the scatter's
// samples waited on those loads.
__kernel void bucket_scatter(__global const uint* keys, __global const uint* slots, __global const uint* ids,
                             __global const uint* m_ptr, uint shift, uint mask, uint nblocks,
                             __global uint* offsets, __global const uint* totals, __global uint4* records,
                             uint n) {
    const uint b = get_global_id(0);
    uint begin, end;
    if (b >= nblocks || !radix_block(m_ptr, mask, nblocks, offsets, totals, b, &begin, &end)) return;
    uint place[1u << BUCKET_MAX_LOW_BITS];
    for (uint d = 0; d <= mask; ++d) place[d] = offsets[d * nblocks + b];
    const bool scattered = movers_scattered(*m_ptr, n);
    for (uint j = begin; j < end; ++j) {
        const uint k = keys[j];
        const uint o = place[(k >> shift) & mask]++;
        records[o] = (uint4)(k, slots[j], ids[j], 0u);
        if (scattered) SWCL_PREFETCH_WRITE(records + o + 4u);  // the bucket's next line
    }
}

// Work-item t of `items` sorts the buckets that start in its share of the
// *m records (bucket d holds totals[d] records, after those of buckets < d),
// so the items get records, not buckets, alike.
__kernel void grid_sort_buckets(__global const uint4* records, __global const uint* m_ptr,
                                __global const uint* totals, uint nbuckets, uint items, uint low_mask,
                                __global uint* out_key, __global uint* out_slot, __global uint* out_id, uint n) {
    const uint t = get_global_id(0);
    if (t >= items) return;
    const uint m = *m_ptr;
    const bool scattered = movers_scattered(m, n);
    const uint share = chunk_size(m, items);
    const uint first = min(t * share, m), last = min(first + share, m);
    if (first >= last) return;
    uint place[1u << BUCKET_MAX_LOW_BITS];
    uint lo = 0;
    for (uint d = 0; d < nbuckets && lo < last; ++d) {
        const uint hi = lo + totals[d];
        if (lo < first || hi == lo) {
            lo = hi;
            continue;
        }
        // 16 counters a store (2^11 counters for a few hundred records a
        // bucket on the field model's 4M-cell grid: the scalar loop was a
        // third of this kernel's samples there).
        uint v = 0;
        for (; v + 16u <= low_mask + 1u; v += 16u) vstore16((uint16)(0u), 0, place + v);
        for (; v <= low_mask; ++v) place[v] = 0u;
        for (uint j = lo; j < hi; ++j) {
#ifdef SWCL_PREFETCH_ISSUES
            if (scattered && ((j & 15u) == 0u || j == lo)) {
                SWCL_PREFETCH_WRITE(out_key + j);
                SWCL_PREFETCH_WRITE(out_slot + j);
                SWCL_PREFETCH_WRITE(out_id + j);
            }
#endif
            place[records[j].x & low_mask] += 1u;
        }
        // Exclusive prefix from lo, 8 counters at a time (an in-register
        // scan by shifted adds), the rest one by one.
        uint run = lo;
        v = 0;
        for (; v + 8u <= low_mask + 1u; v += 8u) {
            const uint8 c = vload8(0, place + v);
            uint8 x = c;
            x += (uint8)(0u, x.s0, x.s1, x.s2, x.s3, x.s4, x.s5, x.s6);
            x += (uint8)(0u, 0u, x.s0, x.s1, x.s2, x.s3, x.s4, x.s5);
            x += (uint8)(0u, 0u, 0u, 0u, x.s0, x.s1, x.s2, x.s3);
            vstore8(x - c + (uint8)(run), 0, place + v);
            run += x.s7;
        }
        for (; v <= low_mask; ++v) {
            const uint c = place[v];
            place[v] = run;
            run += c;
        }
        for (uint j = lo; j < hi; ++j) {
            const uint4 r = records[j];
            const uint o = place[r.x & low_mask]++;
            out_key[o] = r.x;
            out_slot[o] = r.y;
            out_id[o] = r.z;
        }
        for (uint j = lo; j < hi;) {
            uint e = j + 1u;
            while (e < hi && out_key[e] == out_key[j]) ++e;
            if (e - j > 1u) sort_by_id(out_slot + j, out_id + j, e - j);
            j = e;
        }
        lo = hi;
    }
}

// After the radix sort the movers are sorted by cell, in slot order within
// a cell: chunk b sorts by id each run of equal cells that starts in it.
__kernel void grid_sort_runs(__global const uint* m_ptr, __global const uint* m_key, __global uint* m_slot,
                             __global uint* m_id, uint nchunks) {
    const uint b = get_global_id(0);
    if (b >= nchunks) return;
    const uint m = *m_ptr;
    const uint size = chunk_size(m, nchunks);
    const uint begin = min(b * size, m), end = min(begin + size, m);
    uint j = begin;
    // A run that started in the chunk before is that chunk's.
    if (j > 0u) while (j < end && m_key[j] == m_key[j - 1u]) ++j;
    while (j < end) {
        uint e = j + 1u;
        while (e < m && m_key[e] == m_key[j]) ++e;
        if (e - j > 1u) sort_by_id(m_slot + j, m_id + j, e - j);
        j = e;
    }
}

// The new order is the merge by (cell, id) of the stayers (st_slot, in
// layout order) and the sorted movers (m_key, m_slot, m_id).  Work-item b
// writes the outputs [b * per_item, ...): it finds how many stayers come
// before its first output by a binary search on the merge path, then merges.
// perm[new slot] = old slot; new_key[new slot] = cell (the next layout);
// new_id[new slot] = its id where ids_from_build.
static inline bool stayer_first(uint sk, uint sid, uint mk, uint mid) { return sk < mk || (sk == mk && sid < mid); }


// The stayers among the first d outputs of the merge: a binary search on
// the merge path.
static inline uint merge_split(__global const uint* keys, __global const uint* ids, __global const uint* st_slot,
                               __global const uint* m_key, __global const uint* m_id, uint m, uint ns, uint d) {
    uint lo = d > m ? d - m : 0u, hi = min(d, ns);
    while (lo < hi) {
        const uint i = lo + (hi - lo) / 2u, j = d - 1u - i;
        const uint s = st_slot[i];
        if (stayer_first(keys[s], ids[s], m_key[j], m_id[j])) lo = i + 1u; else hi = i;
    }
    return lo;
}

// Output d of the merge without a branch, from i stayers and j movers
// before it: (cell, id) as one 64-bit key, one compare (the order of
// stayer_first()); an exhausted side compares as the largest.
static inline void merge_one(__global const uint* keys, __global const uint* ids, __global const uint* st_slot,
                             __global const uint* m_key, __global const uint* m_slot, __global const uint* m_id,
                             uint m, uint ns, uint d, uint* i, uint* j, __global uint* perm,
                             __global uint* new_key, __global uint* new_id) {
    const uint s = *i < ns ? st_slot[*i] : 0u;
    const uint jj = min(*j, m > 0u ? m - 1u : 0u);
    const uint sk = keys[s], mk = m_key[jj], sid = ids[s], mid = m_id[jj];
    const ulong sv = *i < ns ? upsample(sk, sid) : ULONG_MAX;
    const ulong mv = *j < m ? upsample(mk, mid) : ULONG_MAX;
    const uint take_stayer = sv < mv ? 1u : 0u;
    const uint ms = m_slot[jj];
    perm[d] = take_stayer ? s : ms;
    new_key[d] = take_stayer ? sk : mk;
    new_id[d] = take_stayer ? sid : mid;
    *i += take_stayer;
    *j += 1u - take_stayer;
}

__kernel void grid_merge(__global const uint* keys, __global const uint* ids, __global const uint* st_slot,
                         __global const uint* m_ptr, __global const uint* m_key, __global const uint* m_slot,
                         __global const uint* m_id, uint n, uint per_item, __global uint* perm,
                         __global uint* new_key, __global uint* new_id) {
    const uint b = get_global_id(0);
    const uint d0 = b * per_item;
    if (d0 >= n) return;
    const uint d1 = min(d0 + per_item, n);
    const uint m = *m_ptr, ns = n - m;
    uint i = merge_split(keys, ids, st_slot, m_key, m_id, m, ns, d0), j = d0 - i;
    if (mostly_one_kind(m, n)) {
        // Few movers (or few stayers): the branch is predicted, and the
        // loads of the next outputs need not wait for this compare.
        const bool with_ids = ids_from_build(m, n);
        for (uint d = d0; d < d1; ++d) {
            const uint s = i < ns ? st_slot[i] : 0u;
            if (i < ns && (j >= m || stayer_first(keys[s], ids[s], m_key[j], m_id[j]))) {
                perm[d] = s;
                new_key[d] = keys[s];
                if (with_ids) new_id[d] = ids[s];
                ++i;
            } else {
                perm[d] = m_slot[j];
                new_key[d] = m_key[j];
                if (with_ids) new_id[d] = m_id[j];
                ++j;
            }
        }
        return;
    }
    // Branch-free, each output's loads wait on the compare before it: so
    // the range merges as two halves side by side, two such chains at once.
    // (Here at least an eighth moved: the ids are written.)
    const uint second = (d1 - d0) / 2u, dm = d1 - second;
    uint i2 = merge_split(keys, ids, st_slot, m_key, m_id, m, ns, dm), j2 = dm - i2;
    for (uint k = 0; k < second; ++k) {
        merge_one(keys, ids, st_slot, m_key, m_slot, m_id, m, ns, d0 + k, &i, &j, perm, new_key, new_id);
        merge_one(keys, ids, st_slot, m_key, m_slot, m_id, m, ns, dm + k, &i2, &j2, perm, new_key, new_id);
    }
    if (d0 + second < dm)
        merge_one(keys, ids, st_slot, m_key, m_slot, m_id, m, ns, d0 + second, &i, &j, perm, new_key, new_id);
}

// Cell starts from the sorted keys: output d opens the cells after its
// predecessor's up to its own (start = d), the last output's successors up
// to ncells get n.  Every start written once; outputs [b * per_item, ...).
__kernel void grid_starts(__global const uint* new_key, uint n, uint ncells, uint per_item, __global uint* start) {
    const uint b = get_global_id(0);
    const uint d0 = b * per_item;
    if (d0 >= n) return;
    const uint d1 = min(d0 + per_item, n);
    uint c = d0 == 0u ? 0u : new_key[d0 - 1u] + 1u;
    // Cells up to lim are this work-item's to write.
    const uint lim = d1 == n ? ncells : new_key[d1 - 1u];
    for (uint d = d0; d < d1; ++d) {
        const uint k = new_key[d];
        if (k < c) continue;  // k's cell is open already
        // The cells up to k 8 at a time (a sparse grid, 4 cells an agent,
        // has gaps of 8 or more after one output in 7): cells past k get d
        // for now and their own output's value when it comes (later in this
        // loop, which starts again at k + 1); none past lim.
        uint e = c;
        for (; e <= k && e + 8u <= lim + 1u; e += 8u) vstore8((uint8)(d), 0, start + e);
        for (; e <= k; ++e) start[e] = d;
        c = k + 1u;
    }
    if (d1 == n)
        for (; c <= ncells; ++c) start[c] = n;
}

// ---- The build on GPUs: a counting sort (NeighborGrid, "counting" path) ----
// Thousands of short work-items instead of a few hundred long chunks: each
// agent takes a rank in its cell with an atomic increment, the counts become
// the cell starts by a prefix sum, every agent is written at start + rank,
// and each cell sorts its few agents by id.  The atomics decide only the
// order before that last sort; the result is the one order by (cell, id)
// (ids are unique within a world, and a cell belongs to one world), so it
// is bitwise the chunked path's.

// Slot s: keys[s] = its cell, rank[s] = its place among its cell's agents
// (in no set order); count[key] counts them (zeroed before).
__kernel void grid_count_cells(__global const float4* pos, uint n, GRID_PARAMS, uint world_agents,
                               __global const float4* grid_worlds, __global uint* keys, __global uint* rank,
                               __global uint* count) {
    const uint s = get_global_id(0);
    if (s >= n) return;
#ifdef SWCL_WORLDS
    const Grid g = grid_of_world(GRID_MAKE(), grid_worlds, s / world_agents);
#else
    const Grid g = GRID_MAKE();
#endif
    const uint key = grid_key(pos[s], g.origin, g.inv_cell, g.dims, (uint)(g.cell_start - grid_cell_start));
    keys[s] = key;
    rank[s] = atomic_inc(count + key);
}

// Exclusive prefix sum in place over data[0, len), in three launches of
// SCAN_LOCAL work-items per group (the host launches exactly that size):
// each group scans SCAN_PER_ITEM * SCAN_LOCAL values and leaves their total
// in sums[group]; one group scans the sums (any number, a tile at a time);
// every group adds its sum's prefix.
#define SCAN_LOCAL 256u
#define SCAN_PER_ITEM 8u
#define SCAN_BLOCK (SCAN_LOCAL * SCAN_PER_ITEM)

// The exclusive scan of one value per work-item of the group (Hillis-Steele
// in local memory); *total = the group's sum.
static inline uint group_exclusive_scan(uint v, __local uint* tmp, uint* total) {
    const uint l = get_local_id(0);
    tmp[l] = v;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint d = 1u; d < SCAN_LOCAL; d <<= 1) {
        const uint add = l >= d ? tmp[l - d] : 0u;
        barrier(CLK_LOCAL_MEM_FENCE);
        tmp[l] += add;
        barrier(CLK_LOCAL_MEM_FENCE);
    }
    *total = tmp[SCAN_LOCAL - 1u];
    const uint inclusive = tmp[l];
    barrier(CLK_LOCAL_MEM_FENCE);
    return inclusive - v;
}

__kernel void scan_blocks(__global uint* data, uint len, __global uint* sums) {
    if (get_group_id(0) * SCAN_BLOCK >= len) return;  // a whole group: no barrier is split
    __local uint tmp[SCAN_LOCAL];
    const uint base = get_group_id(0) * SCAN_BLOCK + get_local_id(0) * SCAN_PER_ITEM;
    uint v[SCAN_PER_ITEM];
    uint run = 0u;
    for (uint k = 0; k < SCAN_PER_ITEM; ++k) {
        v[k] = base + k < len ? data[base + k] : 0u;
        run += v[k];
    }
    uint total;
    uint prefix = group_exclusive_scan(run, tmp, &total);
    for (uint k = 0; k < SCAN_PER_ITEM; ++k) {
        if (base + k < len) data[base + k] = prefix;
        prefix += v[k];
    }
    if (get_local_id(0) == 0u) sums[get_group_id(0)] = total;
}

__kernel void scan_sums(__global uint* sums, uint count) {
    if (get_group_id(0) > 0u) return;  // one group
    __local uint tmp[SCAN_LOCAL];
    uint carry = 0u;
    for (uint t = 0; t < count; t += SCAN_LOCAL) {
        const uint i = t + get_local_id(0);
        const uint v = i < count ? sums[i] : 0u;
        uint total;
        const uint prefix = group_exclusive_scan(v, tmp, &total);
        if (i < count) sums[i] = carry + prefix;
        carry += total;
    }
}

__kernel void scan_add(__global uint* data, uint len, __global const uint* sums) {
    const uint base = get_group_id(0) * SCAN_BLOCK + get_local_id(0) * SCAN_PER_ITEM;
    if (base >= len) return;
    const uint add = sums[get_group_id(0)];
    for (uint k = 0; k < SCAN_PER_ITEM; ++k)
        if (base + k < len) data[base + k] += add;
}

// Slot s to place start[keys[s]] + rank[s] of the output: out_slot = s,
// out_id = its id.
__kernel void grid_scatter(__global const uint* keys, __global const uint* rank, __global const uint* ids,
                           __global const uint* start, uint n, __global uint* out_slot, __global uint* out_id) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const uint d = start[keys[s]] + rank[s];
    out_slot[d] = s;
    out_id[d] = ids[s];
}

// Cell c sorts its agents by id and writes its key for each (the next
// layout's keys, as grid_merge writes them).
__kernel void grid_sort_cells(__global const uint* start, uint ncells, __global uint* slot, __global uint* id,
                              __global uint* new_key) {
    const uint c = get_global_id(0);
    if (c >= ncells) return;
    const uint b = start[c], e = start[c + 1u];
    if (e - b > 1u) sort_by_id(slot + b, id + b, e - b);
    for (uint d = b; d < e; ++d) new_key[d] = c;
}

// Reordering into cell order: dst[s] = src[perm[s]], positions,
// velocities and ids in one pass over perm; the ids copied from the build's
// new_id where ids_from_build (the counting sort sets *m_ptr = n: it always
// writes them).
__kernel void permute_state(__global const float4* pos, __global const float4* vel, __global const uint* ids,
                            __global const uint* new_id, __global const uint* m_ptr, __global const uint* perm,
                            uint n, __global float4* pos_out, __global float4* vel_out, __global uint* ids_out) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const uint p = perm[s];
    pos_out[s] = pos[p];
    vel_out[s] = vel[p];
    ids_out[s] = ids_from_build(*m_ptr, n) ? new_id[s] : ids[p];
}

// permute_state on CPU devices: work-item b copies the slots of chunk b in
// order, asking for the sources PERMUTE_AHEAD slots ahead first.  The
// sources are anywhere in the arrays after a random-order build, and the
// one-slot-a-work-item kernel waits on them one gather at a time.
#define PERMUTE_AHEAD 16u
__kernel void permute_state_chunks(__global const float4* pos, __global const float4* vel,
                                   __global const uint* ids, __global const uint* new_id,
                                   __global const uint* m_ptr, __global const uint* perm, uint n, uint nchunks,
                                   __global float4* pos_out, __global float4* vel_out, __global uint* ids_out) {
    const uint b = get_global_id(0);
    if (b >= nchunks) return;
    const uint size = chunk_size(n, nchunks);
    const uint begin = min(b * size, n), end = min(begin + size, n);
    const bool copy_ids = ids_from_build(*m_ptr, n);
    for (uint s = begin; s < end; ++s) {
#ifdef SWCL_PREFETCH_ISSUES
        if (s + PERMUTE_AHEAD < end) {
            const uint q = perm[s + PERMUTE_AHEAD];
            SWCL_PREFETCH(pos + q);
            SWCL_PREFETCH(vel + q);
            if (!copy_ids) SWCL_PREFETCH(ids + q);
        }
#endif
        const uint p = perm[s];
        pos_out[s] = pos[p];
        vel_out[s] = vel[p];
        ids_out[s] = copy_ids ? new_id[s] : ids[p];
    }
}
