// The force model of the shape-constrained flying insects paper (Chen et al.
// 2019): per agent the union force of Eq. 1,
//   F = alpha F_internal + (1 - alpha) F_external,
//   F_internal = F_rep + F_ali + F_att (§4.1, Eq. 2-3) + F_cur (§4.2, Eq. 4),
//   F_external = F_con (§5.2, Eq. 5) + F_dis (§5.3, Eq. 6-7),
// then a Newton step with a speed limit and the obstacle ramp of §6
// (Eq. 8-9).  Built per noise configuration (NOISE_* defines, like
// field_model.cl).  Choices where the paper is vague: docs/force-model.md
// and the comments below.  Plain C++ reference: tests/test_force_model.cpp.
#include "lib/noise_field.cl"
#include "lib/grid_common.cl"
#include "lib/philox.cl"
#include "lib/min_distance_common.cl"

// Philox stream of the neighbour sample (keyed by seed, sample group, step).
#define FM_STREAM_SAMPLE 16u
// Agents of one sample group: the slots [16 g, 16 g + 16) share their
// neighbour sample (docs/force-model.md).  A multiple of the wide kernel's
// SWCL_W (8 or 16), so one work-item's lanes share one sample.
#define FM_SAMPLE_GROUP 16u

// Bits of `terms`: which forces are on (all in a run; one at a time in the
// tests that compare each term with its reference).
#define FM_REP 1u
#define FM_ALI 2u
#define FM_ATT 4u
#define FM_CUR 8u
#define FM_CON 16u
#define FM_DIS 32u

// Row r of [R | offset] applied to the target (x, y, z): component by
// component, the same arithmetic in the scalar and the wide kernel.
#define FM_ROW(r, a, b, c) ((r).x * (a) + (r).y * (b) + (r).z * (c) + (r).w)

// One candidate j of the alignment and attraction zones (Eq. 2-3): skipped
// outside R_att and inside R_rep (the repulsion loop has those).
#define FM_ALI_ATT(j)                                                         \
    {                                                                         \
        const float4 q = (float4)(pos[j].xyz, 0.0f);                          \
        const float d2 = dist2(q, p);                                         \
        if (d2 <= r_att2 && d2 >= r_rep2) {                                   \
            if (d2 < r_ali2) {                                                \
                const float4 du = (float4)(vel[j].xyz, 0.0f) - u;             \
                const float m2 = du.x * du.x + du.y * du.y + du.z * du.z;     \
                if (m2 > 0.0f) ali += du * rsqrt(m2);                         \
                ++n_ali;                                                      \
            } else {                                                          \
                att += (q - p) * rsqrt(d2);                                   \
                ++n_att;                                                      \
            }                                                                 \
        }                                                                     \
    }

// ---- the fine grid of repulsion and MDE -----------------------------------
//
// R_rep (0.3 m) and the MDE distance are a fraction of the swarm grid's cell
// (interaction_radius, 2 m in the example scenarios), so walking that grid's
// cells visits hundreds of agents for each few within R_rep, and more as the
// shape densifies.  The force model therefore keeps a grid of its own for
// them: cells of edge max(R_rep, the cube root of the swarm's bounding box
// volume / max_cells) over the bounding box of the agents (computed on the
// device every build, so it follows the swarm), and a copy of the positions
// sorted by (fine cell, slot) in x, y, z blocks.  The swarm's state and slot
// order are untouched.  Everything here is deterministic: min/max are exact,
// the sort is grid.cl's stable radix sort of the slots, and each cell's
// range is written by exactly one work-item.
//
// Geometry (geo[0], geo[1]): origin xyz and 1 / cell edge in w; cells per
// axis and their product as int bits.  The copy's blocks are n + FM_SOA_PAD
// floats apart (vector loads may read past a row's end).
#define FM_SOA_PAD 16u

SWCL_INLINE Grid fm_fine_grid(__global const float4* geo, __global const uint* start) {
    const float4 a = geo[0], b = geo[1];
    return grid_make((float4)(a.xyz, 0.0f), a.w, (int4)(as_int(b.x), as_int(b.y), as_int(b.z), 0), start);
}

// Chunk b's bounding box: part[2 b], part[2 b + 1] (empty: +inf, -inf).
__kernel void force_model_fine_bounds(__global const float4* pos, uint n, uint nchunks, __global float4* part) {
    const uint b = get_global_id(0);
    if (b >= nchunks) return;
    const uint size = (n + nchunks - 1u) / nchunks;
    const uint begin = min(b * size, n), end = min(begin + size, n);
    float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
    for (uint s = begin; s < end; ++s) {
        const float4 p = (float4)(pos[s].xyz, 0.0f);
        lo = fmin(lo, p);
        hi = fmax(hi, p);
    }
    part[2 * b] = lo;
    part[2 * b + 1] = hi;
}

// One work-item: the box of all chunks, then the cell edge h >= h_min with at
// most max_cells cells over it.
__kernel void force_model_fine_geometry(__global const float4* part, uint nchunks, float h_min, uint max_cells,
                                        __global float4* geo) {
    if (get_global_id(0) != 0) return;
    float4 lo = (float4)(INFINITY), hi = (float4)(-INFINITY);
    for (uint b = 0; b < nchunks; ++b) {
        lo = fmin(lo, part[2 * b]);
        hi = fmax(hi, part[2 * b + 1]);
    }
    float4 ext = hi - lo;
    // No agents, or a box too large for a float volume: one cell (agents are
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
    geo[1] = (float4)(as_float(dims.x), as_float(dims.y), as_float(dims.z), as_float(dims.x * dims.y * dims.z));
}

// keys[s] = fine cell of slot s, slots[s] = s; *count = n (the radix sort's
// length).
__kernel void force_model_fine_keys(__global const float4* pos, uint n, __global const float4* geo,
                                    __global uint* keys, __global uint* slots, __global uint* count) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    if (s == 0) *count = n;
    const Grid g = fm_fine_grid(geo, 0);
    keys[s] = grid_cell_index(&g, grid_cell_of(&g, (float4)(pos[s].xyz, 0.0f)));
    slots[s] = s;
}

// start[c] = first sorted slot of cell c, for c in [0, ncells] (ncells: the
// geometry's): item k writes the cells in (key[k - 1], key[k]], item n the
// rest.
__kernel void force_model_fine_starts(__global const uint* skeys, uint n, __global const float4* geo,
                                      __global uint* start) {
    const uint k = get_global_id(0);
    if (k > n) return;
    const uint from = k == 0u ? 0u : skeys[k - 1u] + 1u;
    const uint to = k == n ? as_uint(geo[1].w) : skeys[k];
    for (uint c = from; c <= to; ++c) start[c] = k;
}

// The sorted copy of the positions (x, y, z blocks).
__kernel void force_model_fine_gather(__global const float4* pos, __global const uint* sslot, uint n,
                                      __global float* soa) {
    const uint k = get_global_id(0);
    if (k >= n) return;
    const float4 p = pos[sslot[k]];
    soa[k] = p.x;
    soa[(n + FM_SOA_PAD) + k] = p.y;
    soa[2 * (n + FM_SOA_PAD) + k] = p.z;
}

// A position of the sorted copy.
#define FM_SOA_AT(soa, n, k) \
    ((float4)((soa)[k], (soa)[((n) + FM_SOA_PAD) + (k)], (soa)[2 * ((n) + FM_SOA_PAD) + (k)], 0.0f))

// Smallest and largest lane of v among the lanes `on`, at the bodies'
// widths (the _w ones below): at width 1 the agent's own coordinate.
SWCL_INLINE float fm_lane_min_s(float v, int on) { return select(INFINITY, v, on); }
SWCL_INLINE float fm_lane_max_s(float v, int on) { return select(-INFINITY, v, on); }

// Slots j of the union of the search boxes of radius r of the lanes `on`
// (cell of the smallest p - r to cell of the largest p + r: grid_cell_of is
// monotone), at the width of the body that uses it (at width 1 the agent's
// own box, as GRID_FOR_EACH_CANDIDATE):
//   FM_LANES_WALK(&g, px, py, pz, on, r, j) { ... } FM_LANES_WALK_END
#define FM_LANES_WALK(gp, px, py, pz, on, r, j)                                                          \
    {                                                                                                   \
        const int4 fw_lo_ = grid_cell_of((gp), (float4)(SWCL_BFN(fm_lane_min)(px, on) - (r),             \
                                                         SWCL_BFN(fm_lane_min)(py, on) - (r),             \
                                                         SWCL_BFN(fm_lane_min)(pz, on) - (r), 0.0f));     \
        const int4 fw_hi_ = grid_cell_of((gp), (float4)(SWCL_BFN(fm_lane_max)(px, on) + (r),             \
                                                         SWCL_BFN(fm_lane_max)(py, on) + (r),             \
                                                         SWCL_BFN(fm_lane_max)(pz, on) + (r), 0.0f));     \
        for (int fw_z_ = fw_lo_.z; fw_z_ <= fw_hi_.z; ++fw_z_)                                          \
            for (int fw_y_ = fw_lo_.y; fw_y_ <= fw_hi_.y; ++fw_y_) {                                    \
                const uint2 fw_rng_ = grid_row_range((gp), fw_lo_.x, fw_hi_.x, fw_y_, fw_z_);           \
                for (uint j = fw_rng_.x; j < fw_rng_.y; ++j)
#define FM_LANES_WALK_END }}

// Repulsion of every agent in the fine grid's order: one body for
// force_model_repulsion and force_model_repulsion_w (below).
#define SWCL_BW 1
#include "wide/force_model_repulsion.inc.cl"
#undef SWCL_BW

// Minimum distance enforcement (the pair rule MDE_CANDIDATE of
// min_distance_common.cl, as the swarm's MDE pass) through the fine grid
// built on the current positions: out[i] = pos[i] + the pushes of every other
// agent closer than d_min, in the fine grid's order.
// One agent per work-item in the fine grid's order.  The grid may be the one
// built for this step's forces, before the Newton step moved every agent by
// at most `slack` (max speed * dt, with margin): then an agent within d_min
// of p now was within d_min + slack of it at the build, so the box of that
// radius (widened by the rounding of coordinates of p's magnitude) holds its
// cell, and the test uses the current positions pos[slot].
__kernel void force_model_mde(__global const float4* pos, __global const uint* ids, uint n,
                              __global const float4* fine_geo, __global const uint* fine_start,
                              __global const uint* fine_slot, float d_min, float slack, ulong seed,
                              __global float4* out, __global volatile uint* moved) {
    const uint k = get_global_id(0);
    if (k >= n) return;
    const Grid g = fm_fine_grid(fine_geo, fine_start);
    const uint i = fine_slot[k];
    const float4 p = (float4)(pos[i].xyz, 0.0f);
    const float reach = d_min + slack + 1e-6f * (1.0f + fabs(p.x) + fabs(p.y) + fabs(p.z));
    const float d2_min = d_min * d_min;
    float3 push = (float3)(0.0f);
    bool touched = false;
    GRID_FOR_EACH_CANDIDATE(&g, p, reach, j) {
        const uint sj = fine_slot[j];
        MDE_CANDIDATE(i, sj)
    } GRID_END_FOR
    out[i] = (float4)(p.xyz + push, 0.0f);
    if (touched) {
        atomic_inc(&moved[0]);
        atomic_inc(&moved[1]);
    }
}

// Start and stride of the neighbour sample of sample group grp (Philox keyed
// by seed, group, step): j_k = start + k stride (mod n), start uniform over
// the n slots, stride in [1, n - 1].
SWCL_INLINE uint fm_sample_start(ulong seed, uint grp, uint step, uint n, uint* stride) {
    const uint4 r = swcl_rand_u4(seed, grp, step, FM_STREAM_SAMPLE, 0u);
    *stride = n > 1u ? 1u + (uint)(((ulong)r.y * (ulong)(n - 1u)) >> 32) : 0u;
    return (uint)(((ulong)r.x * (ulong)n) >> 32);
}

// Alignment and attraction zones, exact: every agent of the R_att box.
SWCL_INLINE void fm_ali_att_exact(__global const float4* pos, __global const float4* vel, const Grid* g, uint i,
                                  float4 p, float4 u, float4 zones, float4* ali_, uint* n_ali_, float4* att_,
                                  uint* n_att_) {
    const float r_rep2 = zones.x * zones.x, r_ali2 = zones.y * zones.y, r_att2 = zones.z * zones.z;
    float4 ali = *ali_, att = *att_;
    uint n_ali = *n_ali_, n_att = *n_att_;
    GRID_FOR_EACH_CANDIDATE(g, p, zones.z, j) {
        if (j == i) continue;
        FM_ALI_ATT(j);
    }
    GRID_END_FOR
    *ali_ = ali; *att_ = att; *n_ali_ = n_ali; *n_att_ = n_att;
}

// §5.2, Eq. 5 on the insects: the sample neighbours of this insect's target
// are the targets of other insects; their current positions push this
// insect away with a Gaussian of the Manhattan distance, spreading the swarm
// over the surface ("we use F_con to scatter the insects along the mesh").
// sigma is a length (docs/force-model.md).  Returns w_con times the mean.
SWCL_INLINE float4 fm_shape_force(__global const uint* nbr_start, __global const uint* nbr_index,
                                  __global const float4* by_target, uint tgt, float4 p, float sigma, float w_con) {
    const uint k0 = nbr_start[tgt], k1 = nbr_start[tgt + 1];
    float4 con = (float4)(0.0f);
    const float inv2s2 = 1.0f / (2.0f * sigma * sigma);
    for (uint k = k0; k < k1; ++k) {
        const float4 q = (float4)(by_target[nbr_index[k]].xyz, 0.0f);
        const float4 dq = p - q;
        const float m = fabs(dq.x) + fabs(dq.y) + fabs(dq.z);
        const float l = sqrt(dq.x * dq.x + dq.y * dq.y + dq.z * dq.z);
        if (l > 0.0f) con += (exp(-m * m * inv2s2) / l) * dq;  // one division, not three
    }
    return k1 > k0 ? (w_con / (float)(k1 - k0)) * con : (float4)(0.0f);
}

// zones = (R_rep, R_ali, R_att, sigma of Eq. 5), weights = (w_rep, w_ali,
// w_att, w_dis), blend = (alpha, w_con, distance scale of Eq. 6, unused),
// frame_x/y/z = the rows of [R | offset], the shape frame's placement on the
// global path (§6): a target p of the shape is at R p + offset.
// Target data are by target index; target_of maps agent ids to target
// indices; by_target holds each target's insect position this step
// (force_model_scatter).
// The arguments of both force kernels (the wide one adds the x/y/z planes).
#define FM_FORCE_PARAMS                                                                                 \
    __global const float4 *pos, __global const float4 *vel, __global const uint *ids, uint n, GRID_PARAMS, \
        float4 zones, float4 weights, float4 blend, uint terms, uint sample_cap, ulong seed, uint has_targets, \
        __global const uint *target_of, __global const float4 *targets, __global const uint *nbr_start,    \
        __global const uint *nbr_index, __global const float4 *by_target, float4 frame_x, float4 frame_y,  \
        float4 frame_z, float t, uint step, __global float4 *force, __global const float4 *rep_in, NOISE_PARAMS

__kernel void force_model_force(FM_FORCE_PARAMS) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float4 p = (float4)(pos[i].xyz, 0.0f);
    const float4 u = (float4)(vel[i].xyz, 0.0f);
    const uint id = ids[i];

    // §4.1, Eq. 2-3: each neighbour counts in exactly one zone (S = -1, 0, 1
    // below R_rep, below R_ali, up to R_att); each zone's sum is averaged over
    // its own neighbours.  S = +-1 leaves the unit direction r_ij/|r_ij|
    // (towards the neighbour for attraction, away for repulsion); S = 0
    // leaves the unit velocity difference.  The paper's u_ij = u_i - u_j
    // would steer an insect away from its neighbours' velocity
    // (anti-alignment, against the zone's name and the paper's ref. 5), so
    // alignment uses u_j - u_i.  Coincident agents (r_ij = 0) have no
    // direction and are skipped; equal velocities add 0 but count.
    float4 rep = (float4)(0.0f), ali = (float4)(0.0f), att = (float4)(0.0f);
    uint n_rep = 0, n_ali = 0, n_att = 0;
    const Grid g = GRID_MAKE();
    if (terms & FM_REP) {  // force_model_repulsion's
        const float4 r = rep_in[i];
        rep = (float4)(r.xyz, 0.0f);
        n_rep = as_uint(r.w);
    }
    if (terms & (FM_ALI | FM_ATT)) {
        if (sample_cap == 0u) {
            fm_ali_att_exact(pos, vel, &g, i, p, u, zones, &ali, &n_ali, &att, &n_att);
        } else {
            // Sampled (not in the paper; docs/force-model.md): sample_cap
            // agents of the whole swarm, j = start + k * stride (mod n) with
            // start and stride drawn per sample group and step by Philox
            // (fm_sample_start): for each agent every other agent is equally
            // likely to be sampled, and slots being in cell order, a large
            // stride spreads the sample over the swarm.  The 16 agents of a
            // group (neighbours in cell order) share the sample, so the wide
            // kernel loads each sampled agent once for all its lanes.  Those
            // within R_att count in their zone, so each zone's mean in Eq. 2
            // is estimated from its sampled neighbours, at O(cap) per agent
            // instead of the O(N) that R_att = 30 m costs when the swarm is
            // smaller than that.
            const float r_rep2 = zones.x * zones.x, r_ali2 = zones.y * zones.y, r_att2 = zones.z * zones.z;
            uint stride;
            uint j = fm_sample_start(seed, i / FM_SAMPLE_GROUP, step, n, &stride);
            for (uint k = 0; k < sample_cap; ++k) {
                if (j != i) FM_ALI_ATT(j);
                j += stride;
                if (j >= n) j -= n;
            }
        }
    }

    float4 f_int = (float4)(0.0f);
    if ((terms & FM_REP) && n_rep) f_int += (weights.x / (float)n_rep) * rep;
    if ((terms & FM_ALI) && n_ali) f_int += (weights.y / (float)n_ali) * ali;
    if ((terms & FM_ATT) && n_att) f_int += (weights.z / (float)n_att) * att;
    // §4.2, Eq. 4: curl of the Perlin potential (p(s1), p(s2), p(s3))(r / rho)
    // * eta, from the noise module with scale = rho and gain = eta / rho (the
    // module takes the curl in noise coordinates, Eq. 4 in metres).
    if (terms & FM_CUR) {
        float cx, cy, cz;
        NOISE_VELOCITY_S(p.x, p.y, p.z, t, id, step, &cx, &cy, &cz);
        f_int += (float4)(cx, cy, cz, 0.0f);
    }

    float4 f_ext = (float4)(0.0f);
    if (has_targets) {
        const uint tgt = target_of[id];
        if (terms & FM_CON) f_ext += fm_shape_force(nbr_start, nbr_index, by_target, tgt, p, zones.w, blend.y);
        // §5.3, Eq. 6-7: the harmonic distance force along the unit vector to
        // the target, with d normalised by the distance scale and clamped to
        // 1 (the paper's H(d) = 0 beyond 1 would leave far insects with no
        // pull at all).  4 (d - 0.5)^(1/3) + 0.5 is positive (towards the
        // target) above d = 0.498 and negative below: insects hover about
        // their target instead of sitting on it.
        if (terms & FM_DIS) {
            const float3 tp = targets[tgt].xyz;
            const float4 s = (float4)(FM_ROW(frame_x, tp.x, tp.y, tp.z), FM_ROW(frame_y, tp.x, tp.y, tp.z),
                                      FM_ROW(frame_z, tp.x, tp.y, tp.z), 0.0f);
            const float4 rs = s - p;
            const float dd = sqrt(rs.x * rs.x + rs.y * rs.y + rs.z * rs.z);
            if (dd > 0.0f) {
                const float dn = fmin(dd / blend.z, 1.0f);
                f_ext += (weights.w * (4.0f * cbrt(dn - 0.5f) + 0.5f) / dd) * rs;
            }
        }
    }
    // §3, Eq. 1.
    force[i] = blend.x * f_int + (1.0f - blend.x) * f_ext;
}

#ifdef NOISE_WIDE
// ---- explicit-width force (CPU devices) ------------------------------------
//
// force_model_force on SWCL_W consecutive slots per work-item (launch
// ceil(n / SWCL_W) work-items), as the noise module's wide kernels: PoCL
// does not vectorise force_model_force across work-items, so it ran one
// scalar pair at a time.  Here every term runs in floatW lanes with the
// scalar kernel's tests and arithmetic in the same order (bitwise the same
// forces: tests/test_force_model.cpp): each candidate of the shared sample
// and of the union of the lanes' R_att boxes (exact zones) is loaded once
// and tested against all lanes; Eq. 5's target neighbours are gathered per
// lane.  Repulsion comes from force_model_repulsion_w (below, in the fine
// grid's order), read by slot.
#if SWCL_W == 16
typedef uint16 fm_uw;
#define FM_VLOAD_W vload16
#define FM_AS_UW as_uint16
#else
typedef uint8 fm_uw;
#define FM_VLOAD_W vload8
#define FM_AS_UW as_uint8
#endif
#define FM_LANE_INDEX_(k) SWCL_LANE_I(k)

// Component c of the float4 elements j of a (seen as floats), and elements j
// of a uint array, W lanes: one AVX-512 gather where there is one (as
// swcl_perm_w), else W loads.
#if SWCL_W == 16 && defined(__AVX512F__) && defined(__x86_64__) && SWCL_HAS_BUILTIN(__builtin_ia32_gathersiv16sf)
SWCL_INLINE swcl_fw fm_gather_w(__global const float* a, fm_uw j, int c) {
    return __builtin_ia32_gathersiv16sf((float16)(0.0f), (const void*)(size_t)a, as_int16(j * 4u) + c,
                                        (ushort)0xffff, 4);
}
SWCL_INLINE fm_uw fm_gather_u_w(__global const uint* a, fm_uw j) {
    return as_uint16(__builtin_ia32_gathersiv16si((int16)(0), (const void*)(size_t)a, as_int16(j), (ushort)0xffff, 4));
}
#else
#define FM_GATHER_LANE_(k) a[4 * (size_t)SWCL_LANE(j, k) + c]
SWCL_INLINE swcl_fw fm_gather_w(__global const float* a, fm_uw j, int c) { return (swcl_fw)(SWCL_LANES(FM_GATHER_LANE_)); }
#undef FM_GATHER_LANE_
#define FM_GATHER_LANE_(k) a[SWCL_LANE(j, k)]
SWCL_INLINE fm_uw fm_gather_u_w(__global const uint* a, fm_uw j) { return (fm_uw)(SWCL_LANES(FM_GATHER_LANE_)); }
#undef FM_GATHER_LANE_
#endif

// FM_ALI_ATT for candidate j in all lanes (px.., ux.., self, the zone radii
// and sums of force_model_force_w in scope): the same tests and arithmetic,
// each lane's sums changed only where j counts for it.
#define FM_ALI_ATT_W(j)                                                           \
    {                                                                             \
        const float4 q = pos[j], v = vel[j];                                      \
        const swcl_fw dx = q.x - px, dy = q.y - py, dz = q.z - pz;                \
        const swcl_fw d2 = dx * dx + dy * dy + dz * dz;                           \
        const swcl_iw in = (self != (j)) & (d2 <= r_att2) & (d2 >= r_rep2);       \
        const swcl_iw is_ali = in & (d2 < r_ali2), is_att = in & ~(d2 < r_ali2);  \
        const swcl_fw dux = v.x - ux, duy = v.y - uy, duz = v.z - uz;             \
        const swcl_fw m2 = dux * dux + duy * duy + duz * duz;                     \
        /* a lane uses rsqrt(m2) (alignment) or rsqrt(d2), never both */        \
        const swcl_fw rs = rsqrt(select(d2, m2, is_ali));                         \
        const swcl_iw add_ali = is_ali & (m2 > 0.0f);                             \
        ali_x = select(ali_x, ali_x + dux * rs, add_ali);                         \
        ali_y = select(ali_y, ali_y + duy * rs, add_ali);                         \
        ali_z = select(ali_z, ali_z + duz * rs, add_ali);                         \
        att_x = select(att_x, att_x + dx * rs, is_att);                           \
        att_y = select(att_y, att_y + dy * rs, is_att);                           \
        att_z = select(att_z, att_z + dz * rs, is_att);                           \
        n_ali -= FM_AS_UW(is_ali); /* true is -1 */                               \
        n_att -= FM_AS_UW(is_att);                                                \
    }


// Smallest and largest lane of v among the lanes `on`.
SWCL_INLINE float fm_lane_min_w(swcl_fw v, swcl_iw on) {
    v = select((swcl_fw)(INFINITY), v, on);
    float m = v.s0;
#define FM_MIN_(k) m = fmin(m, SWCL_LANE(v, k));
    SWCL_EACH_LANE(FM_MIN_)
#undef FM_MIN_
    return m;
}
SWCL_INLINE float fm_lane_max_w(swcl_fw v, swcl_iw on) {
    v = select((swcl_fw)(-INFINITY), v, on);
    float m = v.s0;
#define FM_MAX_(k) m = fmax(m, SWCL_LANE(v, k));
    SWCL_EACH_LANE(FM_MAX_)
#undef FM_MAX_
    return m;
}

#define SWCL_BW SWCL_W
#include "wide/force_model_repulsion.inc.cl"
#undef SWCL_BW

// (w / count) * sum added to acc in the lanes whose count is not 0.
#define FM_ADD_MEAN_W(acc, w, cnt, sum) acc = select(acc, acc + ((w) / swcl_cvt_fw(cnt)) * (sum), (cnt) != 0u)

__kernel void force_model_force_w(FM_FORCE_PARAMS) {
    const uint base = get_global_id(0) * SWCL_W;
    if (base >= n) return;
    __global const float* pf = (__global const float*)pos;
    __global const float* vf = (__global const float*)vel;
    swcl_fw px, py, pz, ux, uy, uz;
    noise_load_xyz_w(pf, base, n, &px, &py, &pz);
    noise_load_xyz_w(vf, base, n, &ux, &uy, &uz);
    const Grid g = GRID_MAKE();

    const fm_uw self = (fm_uw)(base) + (fm_uw)(SWCL_LANES(FM_LANE_INDEX_));
    const float r_rep2 = zones.x * zones.x, r_ali2 = zones.y * zones.y, r_att2 = zones.z * zones.z;
    const swcl_fw zero = (swcl_fw)(0.0f);
    swcl_fw rep_x = zero, rep_y = zero, rep_z = zero, ali_x = zero, ali_y = zero, ali_z = zero;
    swcl_fw att_x = zero, att_y = zero, att_z = zero;
    fm_uw n_rep = (fm_uw)(0u), n_ali = (fm_uw)(0u), n_att = (fm_uw)(0u);

    const swcl_iw live = self < n;
    if (terms & FM_REP) {
        // force_model_repulsion(_w)'s sums and counts, by slot.
        noise_load_xyz_w((__global const float*)rep_in, base, n, &rep_x, &rep_y, &rep_z);
        uint c_rep[SWCL_W];
        for (uint l = 0; l < SWCL_W; ++l) c_rep[l] = base + l < n ? as_uint(rep_in[base + l].w) : 0u;
        n_rep = FM_VLOAD_W(0, c_rep);
    }
    // The exact zones walk the union of the lanes' R_att boxes (many cells
    // each, so the union adds few), each candidate tested against all lanes.
    // A lane's own box lies inside the union and both walks go row by row
    // (z, y) in slot order, so each lane meets its neighbours in the scalar
    // kernel's order; the extra candidates are farther than R_att from it
    // and fail its distance test.
    if ((terms & (FM_ALI | FM_ATT)) && sample_cap == 0u) {
        FM_LANES_WALK(&g, px, py, pz, live, zones.z, j) {
            FM_ALI_ATT_W(j);
        }
        FM_LANES_WALK_END
    } else if (terms & (FM_ALI | FM_ATT)) {
        // The lanes' shared sample (SWCL_W divides FM_SAMPLE_GROUP), one
        // load per sampled agent.
        uint stride;
        uint j = fm_sample_start(seed, base / FM_SAMPLE_GROUP, step, n, &stride);
        for (uint k = 0; k < sample_cap; ++k) {
            FM_ALI_ATT_W(j);
            j += stride;
            if (j >= n) j -= n;
        }
    }

    swcl_fw fx = zero, fy = zero, fz = zero;
    if (terms & FM_REP) {
        FM_ADD_MEAN_W(fx, weights.x, n_rep, rep_x);
        FM_ADD_MEAN_W(fy, weights.x, n_rep, rep_y);
        FM_ADD_MEAN_W(fz, weights.x, n_rep, rep_z);
    }
    if (terms & FM_ALI) {
        FM_ADD_MEAN_W(fx, weights.y, n_ali, ali_x);
        FM_ADD_MEAN_W(fy, weights.y, n_ali, ali_y);
        FM_ADD_MEAN_W(fz, weights.y, n_ali, ali_z);
    }
    if (terms & FM_ATT) {
        FM_ADD_MEAN_W(fx, weights.z, n_att, att_x);
        FM_ADD_MEAN_W(fy, weights.z, n_att, att_y);
        FM_ADD_MEAN_W(fz, weights.z, n_att, att_z);
    }
    if (terms & FM_CUR) {  // Eq. 4
        swcl_fw cx, cy, cz;
        NOISE_VELOCITY_W(px, py, pz, t, &cx, &cy, &cz);
        fx += cx; fy += cy; fz += cz;
    }

    swcl_fw ex = zero, ey = zero, ez = zero;
    if (has_targets) {
        // Each lane's target (lanes at or above n: agent n - 1's).
        const fm_uw tgt = fm_gather_u_w(target_of, fm_gather_u_w(ids, min(self, n - 1u)));
        if (terms & FM_CON) {
            // fm_shape_force in lanes: each lane's target neighbours, up to
            // the longest list; finished lanes read slot 0 (always there) and
            // add nothing.
            const fm_uw k0 = fm_gather_u_w(nbr_start, tgt);
            const fm_uw cnt = select((fm_uw)(0u), fm_gather_u_w(nbr_start, tgt + 1u) - k0, live);
            uint longest = 0;
#define FM_LONGEST_(k) longest = max(longest, SWCL_LANE(cnt, k));
            SWCL_EACH_LANE(FM_LONGEST_)
#undef FM_LONGEST_
            const float inv2s2 = 1.0f / (2.0f * zones.w * zones.w);
            __global const float* bf = (__global const float*)by_target;
            swcl_fw cx = zero, cy = zero, cz = zero;
            for (uint k = 0; k < longest; ++k) {
                const swcl_iw act = (fm_uw)(k) < cnt;
                const fm_uw at = select((fm_uw)(0u), k0 + k, act);
                const fm_uw o = select((fm_uw)(0u), fm_gather_u_w(nbr_index, at), act);
                const swcl_fw qx = px - fm_gather_w(bf, o, 0), qy = py - fm_gather_w(bf, o, 1),
                              qz = pz - fm_gather_w(bf, o, 2);
                const swcl_fw m = fabs(qx) + fabs(qy) + fabs(qz);
                const swcl_fw l = sqrt(qx * qx + qy * qy + qz * qz);
                const swcl_fw el = exp(-m * m * inv2s2) / l;
                const swcl_iw on = act & (l > 0.0f);
                cx = select(cx, cx + el * qx, on);
                cy = select(cy, cy + el * qy, on);
                cz = select(cz, cz + el * qz, on);
            }
            const swcl_fw wc = blend.y / swcl_cvt_fw(cnt);
            const swcl_iw some = cnt != 0u;
            ex += select(zero, wc * cx, some);
            ey += select(zero, wc * cy, some);
            ez += select(zero, wc * cz, some);
        }
        if (terms & FM_DIS) {  // Eq. 6-7 as in force_model_force
            __global const float* tf = (__global const float*)targets;
            const swcl_fw tx = fm_gather_w(tf, tgt, 0), ty = fm_gather_w(tf, tgt, 1), tz = fm_gather_w(tf, tgt, 2);
            const swcl_fw rx = FM_ROW(frame_x, tx, ty, tz) - px, ry = FM_ROW(frame_y, tx, ty, tz) - py,
                          rz = FM_ROW(frame_z, tx, ty, tz) - pz;
            const swcl_fw dd = sqrt(rx * rx + ry * ry + rz * rz);
            const swcl_fw dn = fmin(dd / blend.z, 1.0f);
            const swcl_fw h = weights.w * (4.0f * cbrt(dn - 0.5f) + 0.5f) / dd;
            const swcl_iw on = dd > 0.0f;
            ex = select(ex, ex + h * rx, on);
            ey = select(ey, ey + h * ry, on);
            ez = select(ez, ez + h * rz, on);
        }
    }
    // §3, Eq. 1.
    noise_store_w((__global float*)force, base, n, blend.x * fx + (1.0f - blend.x) * ex,
                  blend.x * fy + (1.0f - blend.x) * ey, blend.x * fz + (1.0f - blend.x) * ez);
}
#endif

// The insects' positions by target index (the target of agent ids[i]), so
// that Eq. 5 reads a target neighbour's insect with one lookup.
__kernel void force_model_scatter(__global const float4* pos, __global const uint* ids, uint n,
                                  __global const uint* target_of, __global float4* by_target) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    by_target[target_of[ids[i]]] = pos[i];
}

// §6, Eq. 9.
inline float fm_ramp(float x) {
    if (x >= 1.0f) return 1.0f;
    const float x3 = x * x * x;
    return 1.875f * x - 1.25f * x3 + 0.375f * x3 * x * x;
}

// Unit outward normal and distance of obstacle k (curl_noise.cl primitives).
inline float fm_obstacle(__global const float4* prims, uint k, float4 p, float4* nrm) {
    const swcl_dist b = swcl_prim_dist(prims[2 * k], prims[2 * k + 1], 0, p.xyz);
    const float gl = length(b.g);
    *nrm = gl > 0.0f ? (float4)(b.g / gl, 0.0f) : (float4)(0.0f, 0.0f, 1.0f, 0.0f);
    return b.d;
}

// A lower bound of fm_obstacle's distance without its square roots and
// Hessian, for skipping obstacles out of reach: for a rounded box
// (swcl_dist_box) the same m = max(|p - c| - (h - rr), 0) as there, and
// its d = m ||t||_4 - rr with t = qa / m, whose largest component is exactly
// 1, so the norm is >= 1 and d >= m - rr; less 1e-6 m, far more than the
// rounding of the norm's square roots, so the bound holds for the computed d
// too and skipping changes no bit.  -inf (no bound) for other primitives,
// which are cheap.
inline float fm_obstacle_bound(__global const float4* prims, uint k, float4 p) {
    const float4 a = prims[2 * k], b = prims[2 * k + 1];
    if (swcl_prim_type(a) != SWCL_PRIM_BOX) return -INFINITY;
    const float3 q = fabs(p.xyz - a.xyz) - (b.xyz - b.w);
    const float3 qa = fmax(q, (float3)(0.0f));
    const float m = fmax(qa.x, fmax(qa.y, qa.z));
    return m > 0.0f ? (m - b.w) - 1e-6f * m : -INFINITY;
}

// Mesh obstacles: the signed distance grid of their union (host
// fields/sdf.hpp, cell-centred; origin_h = min corner, cell edge) read
// trilinearly, with the gradient of that trilinear interpolant as the
// outward normal.  Outside the grid's cell centres the meshes are farther
// than the ramp's range (the host grows the grid by range + 2 cells):
// INFINITY.
inline float fm_mesh_obstacle(__global const float* phi, int4 dims, float4 origin_h, float4 p, float4* nrm) {
    const float3 u = (p.xyz - origin_h.xyz) / origin_h.w - (float3)(0.5f);
    const float3 top = convert_float3(dims.xyz - (int3)(1));
    if (any(u < (float3)(0.0f)) || any(u > top)) {
        *nrm = (float4)(0.0f, 0.0f, 1.0f, 0.0f);
        return INFINITY;
    }
    const int3 i0 = min(convert_int3(u), dims.xyz - (int3)(2));
    const float3 w = u - convert_float3(i0);
    const int sy = dims.x, sz = dims.x * dims.y;
    __global const float* c = phi + (i0.x + sy * i0.y + sz * i0.z);
    const float c000 = c[0], c100 = c[1], c010 = c[sy], c110 = c[sy + 1];
    const float c001 = c[sz], c101 = c[sz + 1], c011 = c[sz + sy], c111 = c[sz + sy + 1];
    const float x00 = mix(c000, c100, w.x), x10 = mix(c010, c110, w.x);
    const float x01 = mix(c001, c101, w.x), x11 = mix(c011, c111, w.x);
    const float y0 = mix(x00, x10, w.y), y1 = mix(x01, x11, w.y);
    const float gx = mix(mix(c100 - c000, c110 - c010, w.y), mix(c101 - c001, c111 - c011, w.y), w.z);
    const float gy = mix(x10 - x00, x11 - x01, w.z);
    const float gz = y1 - y0;
    const float3 g = (float3)(gx, gy, gz);
    const float gl = length(g);
    *nrm = gl > 0.0f ? (float4)(g / gl, 0.0f) : (float4)(0.0f, 0.0f, 1.0f, 0.0f);
    return mix(y0, y1, w.z);
}

// Newton step (unit mass): u += F dt, |u| <= max_speed (§6), then near each
// obstacle the avoidance velocity of Eq. 8 with ramp(D / L) (Eq. 9), then
// r += u dt.  Eq. 8 as printed keeps ramp u + (1 - ramp) n (n.u), which at
// the surface (ramp 0) is the *normal* part only: the opposite of its stated
// goal u.n = 0 (Bridson's formula is for the potential, not the velocity).
// We remove the part of the normal velocity that points into the obstacle,
// scaled by 1 - ramp: u_a = u - (1 - ramp) n min(n.u, 0).  At the surface
// the insect slides tangentially; moving away is never slowed.
__kernel void force_model_integrate(__global float4* pos, __global float4* vel, __global const float4* force,
                                    uint n, float dt, float max_speed, float cruise_speed,
                                    __global const float4* prims, uint nprims, float range, uint has_mesh,
                                    __global const float* phi, int4 dims, float4 origin_h) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    float4 p = (float4)(pos[i].xyz, 0.0f);
    float4 u = (float4)(vel[i].xyz, 0.0f) + dt * force[i];
    const float s = length(u);
    if (s > max_speed) u *= max_speed / s;
    else if (s < cruise_speed && s > 0.0f) u *= cruise_speed / s;
    for (uint k = 0; k < nprims; ++k) {
        if (fm_obstacle_bound(prims, k, p) >= range) continue;  // d >= range: nothing to do
        float4 nrm;
        const float d = fm_obstacle(prims, k, p, &nrm);
        if (d < range) {
            const float un = dot(nrm, u);
            if (un < 0.0f) u -= (1.0f - fm_ramp(fmax(d, 0.0f) / range)) * un * nrm;
        }
    }
    if (has_mesh) {  // the same ramp with the mesh obstacles' sampled distance
        float4 nrm;
        const float d = fm_mesh_obstacle(phi, dims, origin_h, p, &nrm);
        if (d < range) {
            const float un = dot(nrm, u);
            if (un < 0.0f) u -= (1.0f - fm_ramp(fmax(d, 0.0f) / range)) * un * nrm;
        }
    }
    vel[i] = u;
    pos[i] = p + dt * u;
}

// Puts back on the surface any insect that a later stage (minimum distance
// enforcement) pushed into an obstacle.  Mesh obstacles push out to half a
// cell above their sampled surface: the trilinear distance overestimates
// the true one near edges and corners (a convex kink) by up to about a
// quarter of a cell, and the sampled normal is approximate, so a few
// iterations (docs/force-model.md).
__kernel void force_model_project(__global float4* pos, uint n, __global const float4* prims, uint nprims,
                                  uint has_mesh, __global const float* phi, int4 dims, float4 origin_h) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    float4 p = (float4)(pos[i].xyz, 0.0f);
    for (uint k = 0; k < nprims; ++k) {
        if (fm_obstacle_bound(prims, k, p) >= 0.0f) continue;  // d >= 0: outside
        float4 nrm;
        const float d = fm_obstacle(prims, k, p, &nrm);
        if (d < 0.0f) p -= d * nrm;
    }
    if (has_mesh) {
        const float skin = 0.5f * origin_h.w;
        for (int it = 0; it < 4; ++it) {
            float4 nrm;
            const float d = fm_mesh_obstacle(phi, dims, origin_h, p, &nrm);
            if (d >= skin) break;
            p -= (d - skin) * nrm;
        }
    }
    pos[i] = p;
}

// The mesh obstacles' sampled normal and distance (xyz, w) at points (tests).
__kernel void force_model_mesh_distance(__global const float4* pts, uint n, __global const float* phi, int4 dims,
                                        float4 origin_h, __global float4* out) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    float4 nrm;
    const float d = fm_mesh_obstacle(phi, dims, origin_h, (float4)(pts[i].xyz, 0.0f), &nrm);
    out[i] = (float4)(nrm.xyz, d);
}
