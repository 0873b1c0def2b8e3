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
// Each insect's pace (speed_spread): one N(0, 1) per insect, keyed by its id.
#define FM_STREAM_PACE 17u
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

// One candidate j of the alignment and attraction zones (Eq. 2-3) for the
// agent in slot `self` (the zone radii and sums of force_model_force in
// scope): skipped when it is the agent itself or outside R_att; inside R_rep
// it counts in the repulsion zone where rep_too (FM_REP_IN_WALK: its unit
// direction away, -r_ij/|r_ij|, as force_model_repulsion, unless it
// coincides with the agent) and else not at all (the repulsion kernel has
// those).  rep_too is a literal: fm_ali_att_s and fm_rep_ali_att_s below.
// Width 1: branches, and float4 arithmetic on p, u and the sums ali, att,
// rep (fm_zones_begin_s), component by component the lanes' (fm_zone_w,
// below); as float4 the scalar kernel is ~5 % faster than with three scalar
// components (PoCL, exact zones).  The squares and the sums are fma():
// correctly rounded, so the same bits at every width and on every device,
// and in the wide kernel a fused multiply-add instead of a multiply and an
// add (a force fit generation's stepping 1.17x faster,
// bench/results/force_fma/ab.json).
#define fm_zone_s(j, rep_too)                                                 \
    {                                                                         \
        const float4 q = (float4)(pos[j].xyz, 0.0f), dq = q - p;              \
        const float d2 = fma(dq.z, dq.z, fma(dq.y, dq.y, dq.x * dq.x));        \
        if (self != (j) && d2 <= r_att2) {                                    \
            if (d2 < r_rep2) {                                                \
                if ((rep_too) && d2 != 0.0f) {                                \
                    rep = fma(-dq, (float4)(rsqrt(d2)), rep);                 \
                    ++n_rep;                                                  \
                }                                                             \
            } else if (d2 < r_ali2) {                                         \
                const float4 du = (float4)(vel[j].xyz, 0.0f) - u;             \
                const float m2 = fma(du.z, du.z, fma(du.y, du.y, du.x * du.x)); \
                if (m2 > 0.0f) ali = fma(du, (float4)(rsqrt(m2)), ali);       \
                ++n_ali;                                                      \
            } else {                                                          \
                att = fma(dq, (float4)(rsqrt(d2)), att);                      \
                ++n_att;                                                      \
            }                                                                 \
        }                                                                     \
    }
#define fm_ali_att_s(j) fm_zone_s(j, 0)
#define fm_rep_ali_att_s(j) fm_zone_s(j, 1)
// Around the zone pass at width 1: the float4 position, velocity and sums
// fm_ali_att_s works on, and the sums back into the body's components.
#define fm_zones_begin_s                                                          \
    const float4 p = (float4)(px, py, pz, 0.0f), u = (float4)(ux, uy, uz, 0.0f);  \
    float4 ali = (float4)(ali_x, ali_y, ali_z, 0.0f), att = (float4)(att_x, att_y, att_z, 0.0f); \
    float4 rep = (float4)(rep_x, rep_y, rep_z, 0.0f);
#define fm_zones_end_s                    \
    ali_x = ali.x; ali_y = ali.y; ali_z = ali.z; \
    att_x = att.x; att_y = att.y; att_z = att.z; \
    rep_x = rep.x; rep_y = rep.y; rep_z = rep.z;

// Whether the force kernel sums the repulsion zone in its walk of the exact
// zones (every candidate within R_att is met there, so those within R_rep
// too) instead of reading force_model_repulsion's sums, for worlds of up to
// FM_REP_WALK_MAX_AGENTS agents (the host defines it): in a fit's small,
// dense swarms the repulsion kernel's own walk of the fine grid cost nearly
// as much as the force kernel's (300 insects in 0.2 m, 14-34 within R_rep,
// ~125 candidates each), and the fine grid's build is a dozen launches.  In
// larger swarms the walk meets many more candidates than the fine grid's
// box holds, and the separate kernel is faster (force_bench, moon and horse
// with exact zones: 1.07x at 1000 agents, even at 2000, 0.9x at 5000 and
// 20000).  Per world, from its parameter block and agent count, so a world
// of an ensemble decides as alone; models/force_model.cpp decides the same
// on the host (rep_in_walk).
#define FM_REP_IN_WALK(terms, sample_cap, r_rep, r_att, n)                                                  \
    (((terms) & FM_REP) != 0u && ((terms) & (FM_ALI | FM_ATT)) != 0u && (sample_cap) == 0u && (r_rep) <= (r_att) && \
     (n) <= FM_REP_WALK_MAX_AGENTS)

// ---- the fine grid of repulsion and MDE -----------------------------------
//
// R_rep (0.3 m) and the MDE distance are a fraction of the swarm grid's cell
// (interaction_radius, 2 m in the example scenarios), so walking that grid's
// cells visits hundreds of agents for each few within R_rep, and more as the
// shape densifies.  The force model therefore keeps a grid of its own for
// them, a point grid (point_grid.cl, spatial/point_grid.hpp): cells of edge
// max(R_rep, the cube root of the swarm's bounding box volume / max_cells)
// over the bounding box of the agents (computed on the device every build,
// so it follows the swarm), its slots sorted by (fine cell, slot); and here
// a copy of the positions in that order in x, y, z blocks.  The swarm's
// state and slot order are untouched.
//
// The copy's blocks are n + FM_SOA_PAD floats apart (vector loads may read
// past a row's end: the host zeroes the pads when it allocates the copy).
#define FM_SOA_PAD 16u

SWCL_INLINE Grid fm_fine_grid(__global const float4* geo, __global const uint* start) {
    return grid_from_geometry(geo, start);
}

// ---- worlds (docs/architecture.md, "Worlds") ------------------------------
//
// With -DSWCL_WORLDS (a swarm of several worlds) the kernels are launched
// over (work-items, W) and world w = get_global_id(1) of n agents starts by
// offsetting what it reads and writes; the rest of each body is the one of a
// swarm alone.  The fine grid is PointGrid::build_groups_apart: world w's
// geometry is geo[2 w], geo[2 w + 1] (the one it has alone, so its cells and
// the order of its neighbours' sums are those alone), its cells the keys
// [w stride, (w + 1) stride) with stride = as_uint(geo[1].w), its sorted
// positions [w n, (w + 1) n) (slot_base w n makes them the world's own);
// the sorted slots are slots of the whole swarm, so what is read or written
// through them is not offset.  The sorted copy of the positions keeps world
// w's x, y, z blocks at w 3 (n + FM_SOA_PAD).
#ifdef SWCL_WORLDS
#define FM_FINE_WORLD_VIEW(geo, start, slot)                         \
    const uint fm_world_ = (uint)get_global_id(1);                   \
    geo += (size_t)2 * fm_world_;                                    \
    start += (size_t)fm_world_ * as_uint(geo[1].w);                  \
    slot += (size_t)fm_world_ * n;
#define FM_FINE_SLOT_BASE(g) (g).slot_base = fm_world_ * n;
#define FM_SOA_WORLD(soa) soa += (size_t)get_global_id(1) * 3 * (n + FM_SOA_PAD);
#define FM_WORLD_AGENTS(p) p += (size_t)get_global_id(1) * n;
#define FM_WORLD_PARAMS(params) params += (size_t)get_global_id(1) * FORCE_FLOATS;
#else  // one world: the kernels as before worlds
#define FM_FINE_WORLD_VIEW(geo, start, slot)
#define FM_FINE_SLOT_BASE(g)
#define FM_SOA_WORLD(soa)
#define FM_WORLD_AGENTS(p)
#define FM_WORLD_PARAMS(params)
#endif

// The sorted copy of the positions (x, y, z blocks).
__kernel void force_model_fine_gather(__global const float4* pos, __global const uint* sslot, uint n,
                                      __global float* soa) {
    const uint k = get_global_id(0);
    if (k >= n) return;
#ifdef SWCL_WORLDS
    sslot += (size_t)get_global_id(1) * n;  // the world's sorted positions (slots of the swarm)
#endif
    FM_SOA_WORLD(soa)
    const float4 p = pos[sslot[k]];
    soa[k] = p.x;
    soa[(n + FM_SOA_PAD) + k] = p.y;
    soa[2 * (n + FM_SOA_PAD) + k] = p.z;
}

// Smallest and largest lane of v among the lanes `on`, at the bodies'
// widths (the _w ones below): at width 1 the agent's own coordinate.
SWCL_INLINE float fm_lane_min_s(float v, int on) { return select(INFINITY, v, on); }
SWCL_INLINE float fm_lane_max_s(float v, int on) { return select(-INFINITY, v, on); }

// The planes z of the grid that hold agents, when the grid was built on the
// positions pos[0, n) in its slot order: slots are in cell order (key x +
// dims.x (y + dims.y z), z slowest), so the first and the last slot's cells
// bound them (grid_cell_of is the build's cell, grid.cl).  A walk that skips
// the planes outside meets the same candidates in the same order; in a fit's
// small world (r_att 5 cells, the swarm in 2-3 of them) most rows of the
// box are empty: skipping their lookups gave 0.94-1.07x a step in three
// alternated runs, 2-3 % of the kernel's perf samples
// (bench/results/force_zocc/).
SWCL_INLINE int2 fm_occupied_z(const Grid* g, __global const float4* pos, uint n) {
    return (int2)(grid_cell_of(g, pos[0]).z, grid_cell_of(g, pos[n - 1u]).z);
}
#define FM_ALL_Z ((int2)(0, INT_MAX))

// Slots j of the union of the search boxes of radius r of the lanes `on`
// (cell of the smallest p - r to cell of the largest p + r: grid_cell_of is
// monotone) in the planes z of zs (fm_occupied_z, or FM_ALL_Z), at the width
// of the body that uses it (at width 1 the agent's own box, as
// GRID_FOR_EACH_CANDIDATE):
//   FM_LANES_WALK(&g, px, py, pz, on, r, zs, j) { ... } FM_LANES_WALK_END
#define FM_LANES_WALK(gp, px, py, pz, on, r, zs, j)                                                      \
    {                                                                                                   \
        const int4 fw_lo_ = grid_cell_of((gp), (float4)(SWCL_BFN(fm_lane_min)(px, on) - (r),             \
                                                         SWCL_BFN(fm_lane_min)(py, on) - (r),             \
                                                         SWCL_BFN(fm_lane_min)(pz, on) - (r), 0.0f));     \
        const int4 fw_hi_ = grid_cell_of((gp), (float4)(SWCL_BFN(fm_lane_max)(px, on) + (r),             \
                                                         SWCL_BFN(fm_lane_max)(py, on) + (r),             \
                                                         SWCL_BFN(fm_lane_max)(pz, on) + (r), 0.0f));     \
        for (int fw_z_ = max(fw_lo_.z, (zs).x); fw_z_ <= min(fw_hi_.z, (zs).y); ++fw_z_)                \
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
// Worlds: world w's d_min and seed are d_mins[w], seeds[w] (as the swarm's
// MDE pass, min_distance.cl), its counters moved[w] and moved[W + w].
#ifdef SWCL_WORLDS
#define FM_MDE_PARAMS __global const float *d_mins, float slack, __global const ulong *seeds
#else
#define FM_MDE_PARAMS float d_min, float slack, ulong seed
#endif
__kernel void force_model_mde(__global const float4* pos, __global const uint* ids, uint n,
                              __global const float4* fine_geo, __global const uint* fine_start,
                              __global const uint* fine_slot, FM_MDE_PARAMS,
                              __global float4* out, __global volatile uint* moved) {
    const uint k = get_global_id(0);
    if (k >= n) return;
    FM_FINE_WORLD_VIEW(fine_geo, fine_start, fine_slot)
#ifdef SWCL_WORLDS
    const float d_min = d_mins[fm_world_];
    const ulong seed = seeds[fm_world_];
    __global volatile uint* moved_now = moved + fm_world_;
    __global volatile uint* moved_sum = moved + get_global_size(1) + fm_world_;
    if (!(d_min > 0.0f)) {  // a world without MDE keeps its positions, as alone
        out[fine_slot[k]] = pos[fine_slot[k]];
        return;
    }
#else
    __global volatile uint* moved_now = moved;
    __global volatile uint* moved_sum = moved + 1;
#endif
    Grid g = fm_fine_grid(fine_geo, fine_start);
    FM_FINE_SLOT_BASE(g)
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
        atomic_inc(moved_now);
        atomic_inc(moved_sum);
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

// zones = (R_rep, R_ali, R_att, sigma of Eq. 5), weights = (w_rep, w_ali,
// w_att, w_dis), blend = (alpha, w_con, distance scale of Eq. 6, unused),
// frame_x/y/z = the rows of [R | offset], the shape frame's placement on the
// global path (§6): a target p of the shape is at R p + offset.
// Target data are by target index; target_of maps agent ids to target
// indices; by_target holds each target's insect position this step
// (force_model_scatter).
// The arguments of both force kernels (the wide one adds the x/y/z planes).
// params: the model's parameter block (models/force_params.cpp lays it out;
// the host defines FORCE_<KEY> as each parameter's slot).  spacing: the
// current targets' sqrt(A/N) (1 without targets), which sigma and the
// default distance scale derive from; seed: the sample seed (64 bits, not
// in the float block).
#define FM_FORCE_PARAMS                                                                                 \
    __global const float4 *pos, __global const float4 *vel, __global const uint *ids, uint n, GRID_WORLD_PARAMS, \
        __global const float *params, float spacing, ulong seed, uint has_targets,                          \
        __global const uint *target_of, __global const float4 *targets, __global const uint *nbr_start,    \
        __global const uint *nbr_index, __global const float4 *by_target, float4 frame_x, float4 frame_y,  \
        float4 frame_z, float t, uint step, __global float4 *force, __global const float4 *rep_in, NOISE_PARAMS

// (w / count) * sum added to acc where the count is not 0 (lane by lane).
#define FM_ADD_MEAN(acc, w, cnt, sum) acc = select(acc, acc + ((w) / swcl_bcvt_f(cnt)) * (sum), (cnt) != 0u)

// Width 1 loads, gathers and stores of the force body (the _w ones below).
SWCL_INLINE void fm_load_xyz_s(__global const float4* p, uint i, uint n, float* x, float* y, float* z) {
    const float4 v = p[i];
    *x = v.x; *y = v.y; *z = v.z;
}
SWCL_INLINE void fm_load_rep_s(__global const float4* rep_in, uint i, uint n, float* x, float* y, float* z,
                               uint* cnt) {
    const float4 r = rep_in[i];
    *x = r.x; *y = r.y; *z = r.z;
    *cnt = as_uint(r.w);
}
SWCL_INLINE float fm_gather_s(__global const float* a, uint j, int c) { return a[4 * (size_t)j + c]; }
SWCL_INLINE uint fm_gather_u_s(__global const uint* a, uint j) { return a[j]; }
SWCL_INLINE void fm_store_s(__global float4* o, uint i, uint n, float a, float b, float c) {
    o[i] = (float4)(a, b, c, 0.0f);
}

// The union force of every agent: one body for force_model_force and
// force_model_force_w (below).
#define SWCL_BW 1
#include "wide/force_model_force.inc.cl"
#undef SWCL_BW

#ifdef NOISE_WIDE
// ---- explicit width (CPU devices) ------------------------------------------
//
// The _w twins of the width 1 helpers above, for force_model_repulsion_w and
// force_model_force_w: SWCL_W consecutive slots per work-item in floatW
// lanes, as the noise module's wide kernels (PoCL does not vectorise the
// scalar force kernels across work-items, so they ran one scalar pair at a
// time).

// Component c of the float4 elements j of a (seen as floats), and elements j
// of a uint array, W lanes: one AVX-512 gather where there is one (as
// swcl_perm_w), else W loads.
#if SWCL_W == 16 && defined(__AVX512F__) && defined(__x86_64__) && SWCL_HAS_BUILTIN(__builtin_ia32_gathersiv16sf)
SWCL_INLINE swcl_fw fm_gather_w(__global const float* a, swcl_uw j, int c) {
    return __builtin_ia32_gathersiv16sf((float16)(0.0f), (const void*)(size_t)a, as_int16(j * 4u) + c,
                                        (ushort)0xffff, 4);
}
SWCL_INLINE swcl_uw fm_gather_u_w(__global const uint* a, swcl_uw j) {
    return as_uint16(__builtin_ia32_gathersiv16si((int16)(0), (const void*)(size_t)a, as_int16(j), (ushort)0xffff, 4));
}
#else
#define FM_GATHER_LANE_(k) a[4 * (size_t)SWCL_LANE(j, k) + c]
SWCL_INLINE swcl_fw fm_gather_w(__global const float* a, swcl_uw j, int c) { return (swcl_fw)(SWCL_LANES(FM_GATHER_LANE_)); }
#undef FM_GATHER_LANE_
#define FM_GATHER_LANE_(k) a[SWCL_LANE(j, k)]
SWCL_INLINE swcl_uw fm_gather_u_w(__global const uint* a, swcl_uw j) { return (swcl_uw)(SWCL_LANES(FM_GATHER_LANE_)); }
#undef FM_GATHER_LANE_
#endif

// fm_zone_s for candidate j in all lanes (px.., ux.., self, the zone radii
// and sums of force_model_force_w in scope): the same tests and arithmetic,
// each lane's sums changed only where j counts for it (a repulsion lane's
// rs is rsqrt(d2), as an attraction lane's).  The lanes work on the body's
// components: nothing around the zone pass.
#define fm_zones_begin_w
#define fm_zones_end_w
#define fm_zone_w(j, rep_too)                                                     \
    {                                                                             \
        const float4 q = pos[j], v = vel[j];                                      \
        const swcl_fw dx = q.x - px, dy = q.y - py, dz = q.z - pz;                \
        const swcl_fw d2 = fma(dz, dz, fma(dy, dy, dx * dx));                \
        const swcl_iw near = (self != (j)) & (d2 <= r_att2);                      \
        const swcl_iw in = near & (d2 >= r_rep2);                                 \
        const swcl_iw is_ali = in & (d2 < r_ali2), is_att = in & ~(d2 < r_ali2);  \
        const swcl_fw dux = v.x - ux, duy = v.y - uy, duz = v.z - uz;             \
        const swcl_fw m2 = fma(duz, duz, fma(duy, duy, dux * dux));          \
        /* a lane uses rsqrt(m2) (alignment) or rsqrt(d2), never both */        \
        const swcl_fw rs = rsqrt(select(d2, m2, is_ali));                         \
        const swcl_iw add_ali = is_ali & (m2 > 0.0f);                             \
        ali_x = select(ali_x, fma(dux, rs, ali_x), add_ali);                         \
        ali_y = select(ali_y, fma(duy, rs, ali_y), add_ali);                         \
        ali_z = select(ali_z, fma(duz, rs, ali_z), add_ali);                         \
        att_x = select(att_x, fma(dx, rs, att_x), is_att);                           \
        att_y = select(att_y, fma(dy, rs, att_y), is_att);                           \
        att_z = select(att_z, fma(dz, rs, att_z), is_att);                           \
        n_ali -= swcl_as_uw(is_ali); /* true is -1 */                             \
        n_att -= swcl_as_uw(is_att);                                              \
        if (rep_too) {                                                            \
            const swcl_iw is_rep = near & (d2 < r_rep2) & (d2 != 0.0f);           \
            rep_x = select(rep_x, fma(-dx, rs, rep_x), is_rep);                       \
            rep_y = select(rep_y, fma(-dy, rs, rep_y), is_rep);                       \
            rep_z = select(rep_z, fma(-dz, rs, rep_z), is_rep);                       \
            n_rep -= swcl_as_uw(is_rep);                                          \
        }                                                                         \
    }
#define fm_ali_att_w(j) fm_zone_w(j, 0)
#define fm_rep_ali_att_w(j) fm_zone_w(j, 1)


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

SWCL_INLINE void fm_load_xyz_w(__global const float4* p, uint base, uint n, swcl_fw* x, swcl_fw* y, swcl_fw* z) {
    noise_load_xyz_w((__global const float*)p, base, n, x, y, z);
}
SWCL_INLINE void fm_load_rep_w(__global const float4* rep_in, uint base, uint n, swcl_fw* x, swcl_fw* y,
                               swcl_fw* z, swcl_uw* cnt) {
    noise_load_xyz_w((__global const float*)rep_in, base, n, x, y, z);
    uint c_rep[SWCL_W];
    for (uint l = 0; l < SWCL_W; ++l) c_rep[l] = base + l < n ? as_uint(rep_in[base + l].w) : 0u;
    *cnt = swcl_vload_uw(0, c_rep);
}
SWCL_INLINE void fm_store_w(__global float4* o, uint base, uint n, swcl_fw a, swcl_fw b, swcl_fw c) {
    noise_store_w((__global float*)o, base, n, a, b, c);
}

#define SWCL_BW SWCL_W
#include "wide/force_model_force.inc.cl"
#undef SWCL_BW
#endif

// The insects' positions by target index (the target of agent ids[i]), so
// that Eq. 5 reads a target neighbour's insect with one lookup.
__kernel void force_model_scatter(__global const float4* pos, __global const uint* ids, uint n,
                                  __global const uint* target_of, __global float4* by_target) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    FM_WORLD_AGENTS(pos)
    FM_WORLD_AGENTS(ids)
    FM_WORLD_AGENTS(target_of)
    FM_WORLD_AGENTS(by_target)
    by_target[target_of[ids[i]]] = pos[i];
}

// §6, Eq. 9.
static inline float fm_ramp(float x) {
    if (x >= 1.0f) return 1.0f;
    const float x3 = x * x * x;
    return 1.875f * x - 1.25f * x3 + 0.375f * x3 * x * x;
}

// Unit outward normal and distance of obstacle k (curl_noise.cl primitives).
static inline float fm_obstacle(__global const float4* prims, uint k, float4 p, float4* nrm) {
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
static inline float fm_obstacle_bound(__global const float4* prims, uint k, float4 p) {
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
static inline float fm_mesh_obstacle(__global const float* phi, int4 dims, float4 origin_h, float4 p, float4* nrm) {
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

// Newton step (unit mass): with speed_relaxation > 0 the speed first relaxes
// towards preferred_speed (ours), then u += F dt, |u| <= max_speed (§6) and
// >= cruise_speed (ours), then near each
// obstacle the avoidance velocity of Eq. 8 with ramp(D / L) (Eq. 9), then
// r += u dt.  Eq. 8 as printed keeps ramp u + (1 - ramp) n (n.u), which at
// the surface (ramp 0) is the *normal* part only: the opposite of its stated
// goal u.n = 0 (Bridson's formula is for the potential, not the velocity).
// We remove the part of the normal velocity that points into the obstacle,
// scaled by 1 - ramp: u_a = u - (1 - ramp) n min(n.u, 0).  At the surface
// the insect slides tangentially; moving away is never slowed.
__kernel void force_model_integrate(__global float4* pos, __global float4* vel, __global const float4* force,
                                    uint n, float dt, __global const float* params,
                                    __global const float4* prims, uint nprims, uint has_mesh,
                                    __global const float* phi, int4 dims, float4 origin_h,
                                    __global const uint* ids, __global const ulong* seeds) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    FM_WORLD_AGENTS(pos)
    FM_WORLD_AGENTS(vel)
    FM_WORLD_AGENTS(force)
    FM_WORLD_AGENTS(ids)
    FM_WORLD_PARAMS(params)
    const float max_speed = params[FORCE_MAX_SPEED], cruise_speed = params[FORCE_CRUISE_SPEED];
    const float range = params[FORCE_OBSTACLE_RANGE];
    float4 p = (float4)(pos[i].xyz, 0.0f);
    float4 v = (float4)(vel[i].xyz, 0.0f);
    // Ours (docs/force-model.md): insect i's pace f = exp(s z - s^2/2) scales
    // its forces and speeds.  The step runs on v / f (the velocity at the
    // swarm's common pace), then scales back, so the limits below and the
    // relaxation's preferred speed are f times theirs for it.
    const float spread = params[FORCE_SPEED_SPREAD];
    float pace = 1.0f;
    if (spread > 0.0f) {
        // swcl_rand_gauss4(...).x, which Oclgrind's check crashed on here.
        const uint4 r = swcl_rand_u4(seeds[get_global_id(1)], ids[i], 0u, FM_STREAM_PACE, 0u);
        const float z = swcl_box_muller(r.x, r.y).x;
        pace = exp(spread * z - 0.5f * spread * spread);
        v /= pace;
    }
    // Ours (docs/force-model.md): the speed relaxes towards preferred_speed,
    // solved exactly over dt (stable for any rate), the heading kept.
    const float relax = params[FORCE_SPEED_RELAXATION];
    if (relax > 0.0f) {
        const float sv = length(v);
        if (sv > 0.0f) {
            const float s0 = params[FORCE_PREFERRED_SPEED];
            v *= (s0 + (sv - s0) * exp(-relax * dt)) / sv;
        }
    }
    float4 u = v + dt * force[i];
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
    if (spread > 0.0f) u *= pace;
    vel[i] = u;
    pos[i] = p + dt * u;
}

// Puts back on the surface any insect that a later stage (minimum distance
// enforcement) pushed into an obstacle.  Mesh obstacles push out to half a
// cell above their sampled surface: the trilinear distance overestimates
// the true one near edges and corners (a convex kink) by up to about a
// quarter of a cell, and the sampled normal is approximate, so a few
// iterations (docs/force-model.md).
// Worlds: the obstacles are one for every world; the primitives push out
// only in the worlds that enforce a minimum distance (world_d_min > 0, as
// the host decides for one world alone).
__kernel void force_model_project(__global float4* pos, uint n, __global const float4* prims, uint nprims,
                                  uint has_mesh, __global const float* phi, int4 dims, float4 origin_h,
                                  __global const float* world_d_min) {
    const uint i = get_global_id(0);
    if (i >= n) return;
#ifdef SWCL_WORLDS
    FM_WORLD_AGENTS(pos)
    if (!(world_d_min[get_global_id(1)] > 0.0f)) nprims = 0u;
#endif
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
