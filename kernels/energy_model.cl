// FASTSWARM (Xiang et al.): data-driven velocity selection by energy
// minimisation (§4, Eq. 1-15).  Every agent evaluates
//   E = E_rep + E_oa + E_cos + E_dir + E_acc + E_env + E_n + E_user
// over the dataset samples d = [v, a] of its speed group and the
// neighbouring groups (§5.2.1, reduced search), keeps the argmin (ties: the
// lowest sample index) and moves p <- p + v dt (Eq. 1).  Host side:
// host/models/energy_model.cpp; the choices where the paper is vague are in
// docs/energy-model.md.
//
// Built per configuration: the NOISE_* defines of the noise field (f_N, §4.3),
// EM_MAX_CAND (the most candidates of any agent), EM_TERMS (the checking
// variant that writes every term of every candidate and moves nothing) and
// EM_TAYLOR_OA (Eq. 6 by a second-order expansion, see below) and
// EM_KEEP_OUT (1: startling stimuli are kept out of, see em_environment_term),
// and ENERGY_<KEY>, the slots of the model's parameter block
// (ParamTable::device_defines, host/models/energy_params.cpp).
#include "lib/noise_field.cl"
#include "lib/grid_common.cl"

#ifndef EM_MAX_CAND
#define EM_MAX_CAND 64
#endif
#ifndef EM_KEEP_OUT
#define EM_KEEP_OUT 0
#endif
// energy_select reads each weight set as one float8 (order W_*): the table
// lays the eight rows of a set out one after the other.
#if ENERGY_WEIGHTS_USER != ENERGY_WEIGHTS_REP + 7 || ENERGY_DANGER_WEIGHTS_USER != ENERGY_DANGER_WEIGHTS_REP + 7
#error "the energy weights are not contiguous in the parameter block"
#endif

// Weights in this order (Table 1 columns).
#define W_REP 0
#define W_OA 1
#define W_COS 2
#define W_DIR 3
#define W_ACC 4
#define W_ENV 5
#define W_N 6
#define W_USER 7
#define EM_TERM_COUNT 8

#define STIM_ATTRACT 0.0f
#define GOAL_UNSET 0x7FFFFFFFu
#define GOAL_BACKWARD 0x80000000u

// Unit vector, or 0 for a zero vector (then |v^ - u^| = 1 for every unit u^:
// the term does not prefer any direction).
static inline float3 em_unit(float3 v) {
    const float l2 = v.x * v.x + v.y * v.y + v.z * v.z;
    return l2 > 0.0f ? v / sqrt(l2) : (float3)(0.0f);
}

static inline float em_len(float3 v) { return sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

// Speed group of speed s: the last group whose slowest sample is <= s.
static inline uint em_group(float s, __global const float* group_min_speed, uint groups) {
    uint g = 0;
    for (uint k = 1; k < groups; ++k)
        if (group_min_speed[k] <= s) g = k;
    return g;
}

// Candidates are evaluated EM_W at a time as float16 lanes: every term is
// the same arithmetic on each candidate, so the exponentials and square
// roots run as vector instructions (PoCL does not vectorise the candidate
// loop of a one-agent work-item by itself; 4-8x fewer instructions, measured
// in bench/energy_bench.cpp).  The dataset is read from structure-of-arrays
// planes (EM_P_*, each padded by EM_W zeros so a chunk never reads past its
// plane); lanes past the agent's candidate range are masked out.
#define EM_W 16
typedef float16 emv;
#define EM_CHUNKS ((EM_MAX_CAND + EM_W - 1) / EM_W)
#define EM_P_VX 0
#define EM_P_VY 1
#define EM_P_VZ 2
#define EM_P_VHX 3
#define EM_P_VHY 4
#define EM_P_VHZ 5
#define EM_P_AHX 6
#define EM_P_AHY 7
#define EM_P_AHZ 8
#define EM_P_AL 9
#define EM_LOAD(plane, c) vload16(0, ds + (size_t)(plane) * ds_stride + (c))
#define em_exp2 swcl_exp2_f16  // lib/exp2.cl

#include "lib/halves.cl"
#include "lib/exp2.cl"

static inline emv em_lenv(emv x, emv y, emv z) { return sqrt(x * x + y * y + z * z); }

// |v^ - u| over the lanes' unit vectors (hx, hy, hz) for one direction u.
static inline emv em_dirv(emv hx, emv hy, emv hz, float3 u) { return em_lenv(hx - u.x, hy - u.y, hz - u.z); }

// Stimulus s at time t: xyz = position + velocity t, w = kind.  The buffer
// holds (position, kind), (d_danger, velocity) per stimulus, uploaded when
// the stimuli are set, so a step needs no upload.
static inline float4 em_stimulus(__global const float4* stim, uint s, float t) {
    const float4 a = stim[2 * s], b = stim[2 * s + 1];
    return (float4)(a.xyz + b.yzw * t, a.w);
}

// Eq. 12's prediction over a horizon: the closest approach of an agent and a
// moving danger, min over tau in [0, h] of |r0 + u tau| (r0 = p - p_s, u = v -
// v_s: both move on at constant velocity).  h = dt, a still danger: Eq. 12's
// |p'_{t+1} - p_s|.
static inline float em_closest(float3 r0, float3 u, float h) {
    const float uu = dot(u, u);
    const float tau = uu > 0.0f ? clamp(-dot(r0, u) / uu, 0.0f, h) : 0.0f;
    return length(r0 + u * tau);
}

// em_closest over the lanes' candidate velocities (vx, vy, vz).
static inline emv em_closestv(float3 r0, float3 vs, emv vx, emv vy, emv vz, float h) {
    const emv ux = vx - vs.x, uy = vy - vs.y, uz = vz - vs.z;
    const emv uu = ux * ux + uy * uy + uz * uz;
    const emv tau = select((emv)(0.0f), clamp(-(r0.x * ux + r0.y * uy + r0.z * uz) / uu, 0.0f, h), uu > 0.0f);
    return em_lenv(r0.x + ux * tau, r0.y + uy * tau, r0.z + uz * tau);
}

// energy_select's arguments in groups, in the order EnergyModel::set_common_args
// sets them (host/device/kernel_args.hpp checks the count):
//   EM_STATE_PARAMS (Swarm::set_step_args): pos, vel (float4, slot order), ids, n;
//            dt, t, step;
//   EM_DATASET_PARAMS (sorted by speed): dv = (v, 0); ds = the EM_P_* planes
//            of v, v^, a^ and |a| (unit vectors and lengths precomputed on
//            the host), ds_stride floats apart; group_start (groups + 1),
//            group_min_speed, groups;
//   EM_WEIGHT_PARAMS: centre (xyz: swarm centre, from energy_centre_*);
//            params: the model's parameter block (params[ENERGY_<KEY>]: the
//            weights normally and in danger, rho, d_rep, d_att1, d_att2,
//            span (neighbouring groups searched, as_uint), danger_horizon,
//            keypoint_reach, keypoints_closed); accel_time (derived: the
//            config's, or the dataset's frame time when that is 0);
//   EM_SCENE_PARAMS: stim: 2 float4 per stimulus ((x, y, z, kind),
//            (d_danger, vx, vy, vz)) at t = 0, nstim; kp: keypoints (float4),
//            nkp, goal (per agent id);
//   EM_PREPARED_PARAMS (energy_prepare, noise_sample_w): pxyz, the positions
//            as x, y, z planes (slot order after EM_W slots of padding,
//            pstride floats apart), so a 16-slot window is a few vector
//            loads; noise_pre: f_N at each slot (EM_NOISE_PRE);
//   then GRID_PARAMS, NOISE_PARAMS and EM_OUTPUT_PARAMS (EM_TERMS: every
//   term of every candidate, the choice and the candidate range; otherwise
//   the new positions and velocities).
#define EM_STATE_PARAMS                                                                              \
    __global const float4 *pos, __global const float4 *vel, __global const uint *ids, uint n, float dt, \
        float t, uint step
#define EM_DATASET_PARAMS                                                                            \
    __global const float4 *dv, __global const float *ds, uint ds_stride, __global const uint *group_start, \
        __global const float *group_min_speed, uint groups
#define EM_WEIGHT_PARAMS __global const float4 *centre, __global const float *params, float accel_time
#define EM_SCENE_PARAMS                                                                              \
    __global const float4 *stim, uint nstim, __global const float4 *kp, uint nkp, __global uint *goal,      \
        uint goal_stride
#define EM_PREPARED_PARAMS __global const float *pxyz, uint pstride, __global const float4 *noise_pre
#ifdef EM_TERMS
#define EM_OUTPUT_PARAMS __global float *terms, __global uint *chosen, __global uint *cand_range
#else
#define EM_OUTPUT_PARAMS __global float4 *pos_out, __global float4 *vel_out
#endif
#define EM_SELECT_PARAMS                                                                             \
    EM_STATE_PARAMS, EM_DATASET_PARAMS, EM_WEIGHT_PARAMS, EM_SCENE_PARAMS, EM_PREPARED_PARAMS, GRID_WORLD_PARAMS, \
        NOISE_PARAMS, EM_OUTPUT_PARAMS

// Worlds (docs/architecture.md, "Worlds"): with -DSWCL_WORLDS (a swarm of
// several worlds) the kernels run over (work-items, W) and world w =
// get_global_id(1) of n agents starts by offsetting what is per agent (its
// slots [w n, (w + 1) n), the position planes too), its parameter and noise
// blocks and its centre; the grid is the world's view (GRID_MAKE_WORLD).
// The rest of each body is the one of a swarm alone, so world w is bitwise
// that swarm.  The dataset and the keypoints are the same for every world
// (read only); each world keeps its agents' goals (by id) from w goal_stride.
#ifdef SWCL_WORLDS
#define EM_WORLD_AGENTS(p) p += (size_t)get_global_id(1) * n;
#define EM_WORLD_BLOCKS(params, noise, centre)                        \
    params += (size_t)get_global_id(1) * ENERGY_FLOATS;               \
    noise += (size_t)get_global_id(1) * NOISE_BLOCK_FLOATS;           \
    noise_prims += get_global_id(1) * 2u * as_uint(noise[NOISE_SLOT_NPRIMS]); \
    centre += get_global_id(1);
#else  // one world: the kernels as before worlds
#define EM_WORLD_AGENTS(p)
#define EM_WORLD_BLOCKS(params, noise, centre)
#endif

// energy_select's parts below are always inlined (one work-item's private
// state stays in registers and on its stack as in one function; the split
// is for reading, measured no slower in bench/energy_bench.cpp).  Each keeps
// its statements as they were, so the arithmetic, and the results, are the
// same bit for bit.
#include "lib/inline.cl"
#define EM_INLINE SWCL_ALWAYS_INLINE static inline

#define EM_LANES ((int16)(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15))

// The neighbour windows' width EM_NW: the device's vector width where the
// host passes one (-DNOISE_WIDTH=8 with AVX2: a float16 there is two
// registers, and the expansion's eleven sums of 16 lanes did not fit in
// sixteen), else 16.  The candidates stay EM_W = 16 lanes (8 was slower:
// docs/energy-model.md, section 6).
#if defined(NOISE_WIDTH) && NOISE_WIDTH == 8
#define EM_NW 8
typedef float8 emnv;
typedef int8 emni;
#define EM_NLOAD vload8
#define EM_NSTORE vstore8
#define EM_NLANES ((int8)(0, 1, 2, 3, 4, 5, 6, 7))
#define em_any_n swcl_any8
#define em_sum_n swcl_sum8f
#define em_exp2_n swcl_exp2_f8
#else
#define EM_NW 16
typedef float16 emnv;
typedef int16 emni;
#define EM_NLOAD vload16
#define EM_NSTORE vstore16
#define EM_NLANES EM_LANES
#define em_any_n swcl_any16
#define em_sum_n swcl_sum16f
#define em_exp2_n swcl_exp2_f16
#endif

// Agent i as the terms see it.
typedef struct {
    float3 p, vt;  // position, velocity v_t
    float dt, t;   // time step, time
    float h;       // danger horizon: max(dt, danger_horizon)
    // Every exp(rho x) as 2^(rho2 x), rho2 = rho log2(e) (one rounding
    // more: relative error 1e-6 at most here): PoCL's exp2 on float16 is
    // cheaper than its exp (6-7% of the step on the 2-core AVX2 PoCL CPU,
    // bench/energy_bench.cpp, docs/energy-model.md section 6), and
    // lib/exp2.cl's cheaper again (section 6).
    float rho2;
} EmAgent;

// Agent i's candidates (§5.2.1, reduced search): samples [c0, c0 + nc) of
// the dataset planes, in nchunks chunks of EM_W lanes.
typedef struct {
    __global const float* ds;
    uint ds_stride;
    uint c0, nc, nchunks;
} EmCandidates;

// The candidates: the speed group of |v_t| and `span` groups on each side.
EM_INLINE EmCandidates em_candidates(float3 vt, __global const float* ds, uint ds_stride,
                                     __global const uint* group_start, __global const float* group_min_speed,
                                     uint groups, uint span) {
    const uint g = em_group(em_len(vt), group_min_speed, groups);
    const uint c0 = group_start[g > span ? g - span : 0u];
    const uint c1 = group_start[min(groups, g + span + 1u)];
    EmCandidates cs;
    cs.ds = ds;
    cs.ds_stride = ds_stride;
    cs.c0 = c0;
    cs.nc = c1 - c0;  // <= EM_MAX_CAND (host sizes it)
    cs.nchunks = (cs.nc + EM_W - 1u) / EM_W;
    return cs;
}

// f_CD (Eq. 15): the unit vector towards the agent's goal keypoint, 0
// without keypoints; *my_goal: the goal (nearest keypoint on the first step,
// ties: lowest index), GOAL_BACKWARD kept.
EM_INLINE float3 em_goal_direction(__global const float4* kp, uint nkp, __global const uint* goal, uint id,
                                   float4 p4, uint* my_goal) {
    float3 cd_hat = (float3)(0.0f);
    *my_goal = 0u;
    if (nkp > 0u) {
        uint g = goal[id];
        if ((g & ~GOAL_BACKWARD) == GOAL_UNSET) {
            uint best = 0u;
            float bd = INFINITY;
            for (uint k = 0; k < nkp; ++k) {
                const float d = dist2(kp[k], p4);
                if (d < bd) { bd = d; best = k; }
            }
            g = best | (g & GOAL_BACKWARD);
        }
        *my_goal = g;
        cd_hat = em_unit(kp[g & ~GOAL_BACKWARD].xyz - p4.xyz);
    }
    return cd_hat;
}

// In danger (Table 1, escaping): a startling stimulus comes within d_danger
// within the horizon at the agent's current velocity.
EM_INLINE bool em_in_danger(const EmAgent* a, __global const float4* stim, uint nstim) {
    bool danger = false;
    for (uint s = 0; s < nstim; ++s) {
        const float4 sp = em_stimulus(stim, s, a->t);
        if (sp.w != STIM_ATTRACT && em_closest(a->p - sp.xyz, a->vt - stim[2 * s + 1].yzw, a->h) < stim[2 * s + 1].x)
            danger = true;
    }
    return danger;
}

// What the neighbours contribute to each candidate (Eq. 4, 6): RN = others
// within d_rep, AN = others with d_att1 <= d <= d_att2 (current positions;
// the sets do not depend on the candidate).
typedef struct {
    emv rep[EM_CHUNKS];  // Eq. 4's sum per candidate
#ifdef EM_TAYLOR_OA
    // Eq. 6's sum as the expansion's coefficients (em_gather_neighbors).
    float s0, s3;
    float3 s1;
    float sxx, syy, szz, sxy, sxz, syz;
#else
    emv oa[EM_CHUNKS];  // Eq. 6's sum per candidate
#endif
    uint nrep, natt;  // |RN|, |AN|
} EmNeighborSums;

// |q + v dt| for the candidates of the chunk at sample c (velocities v):
// a neighbour at offset q as seen from each candidate's next position.
static inline emv em_moved_len(float3 q, __global const float* ds, uint ds_stride, uint c, float dt) {
    const emv x = q.x + EM_LOAD(EM_P_VX, c) * dt, y = q.y + EM_LOAD(EM_P_VY, c) * dt,
              z = q.z + EM_LOAD(EM_P_VZ, c) * dt;
    return em_lenv(x, y, z);
}

// The lanes `one` of a window visited one by one (their slots `slot`): RN
// (Eq. 4; each candidate's sum needs each of them), and AN without the
// expansion (Eq. 6).  Out of line: with the expansion only RN comes here,
// within d_rep, so few windows call it, and inlined, its candidate loops'
// registers left the window loop its sums on the stack.
__attribute__((noinline)) static void em_visit_lanes(emni one, emni slot, const EmAgent* a, float4 p4, float4 radii,
                                                     const EmCandidates* cs, __global const float4* pos,
                                                     __global const float4* vel, EmNeighborSums* sums) {
    const float3 p = a->p;
    const float dt = a->dt, rho2 = a->rho2;
    const float d_rep = radii.x, d_att1 = radii.y, d_att2 = radii.z;
    __global const float* const ds = cs->ds;  // for EM_LOAD
    const uint ds_stride = cs->ds_stride, c0 = cs->c0, nchunks = cs->nchunks;
    int nl[EM_NW], sl[EM_NW];
    EM_NSTORE(one, 0, nl);
    EM_NSTORE(slot, 0, sl);
    for (uint l = 0; l < (uint)EM_NW; ++l) {
        if (!nl[l]) continue;
        const uint jj = (uint)sl[l];
        const float4 pj = pos[jj];
        const float d = sqrt(dist2(p4, pj));
        if (d < d_rep) {
            const float3 q = p - (pj.xyz + vel[jj].xyz * dt);  // predicted positions (j keeps v_j,t)
            for (uint k = 0; k < nchunks; ++k)
                sums->rep[k] += em_exp2(rho2 * (1.0f - em_moved_len(q, ds, ds_stride, c0 + k * EM_W, dt) / d_rep));
            ++sums->nrep;
        } else if (d >= d_att1 && d <= d_att2) {
#ifndef EM_TAYLOR_OA  // (with it the windows sum AN)
            const float3 q = p - pj.xyz;
            for (uint k = 0; k < nchunks; ++k)
                sums->oa[k] += em_exp2(rho2 * (em_moved_len(q, ds, ds_stride, c0 + k * EM_W, dt) / d_att1 - 1.0f));
#endif
            ++sums->natt;
        }
    }
}

// The interaction sums, neighbours outer so the grid is walked once: the
// rows of the search box of radius max(d_rep, d_att2), EM_NW slots at a time.
EM_INLINE void em_gather_neighbors(const EmAgent* a, uint i, float4 p4, float4 radii, const EmCandidates* cs,
                                   __global const float4* pos, __global const float4* vel, Grid grid,
                                   __global const float* pxyz, uint pstride, EmNeighborSums* sums) {
    const float3 p = a->p;
    const float rho2 = a->rho2;
    const float d_rep = radii.x, d_att1 = radii.y, d_att2 = radii.z, rho = radii.w;
    const uint nchunks = cs->nchunks;
    for (uint k = 0; k < nchunks; ++k) sums->rep[k] = (emv)(0.0f);
    sums->nrep = 0u;
    sums->natt = 0u;
#ifdef EM_TAYLOR_OA
    // Eq. 6 summed over AN as a quadratic in the displacement d = v dt:
    // with q = p_i - p_j, r = |q|, u = q / r, a = rho / d_att1,
    //   exp(a |q + d| - rho) = f0 (1 + a u.d + (a^2/2 - a/(2r)) (u.d)^2 + a/(2r) |d|^2) + O((a|d|)^3)
    // (f0 = exp(a r - rho)), so the neighbours are visited once, not once
    // per candidate.  The host enables it only while a |d| <= 0.4 for the
    // fastest sample (relative error below 1.6%, docs/energy-model.md).
    float s0 = 0.0f, s3 = 0.0f;
    float3 s1 = (float3)(0.0f);
    float sxx = 0.0f, syy = 0.0f, szz = 0.0f, sxy = 0.0f, sxz = 0.0f, syz = 0.0f;
    const float a_oa = rho / d_att1, a2_oa = rho2 / d_att1;  // a, and a log2(e)
#else
    for (uint k = 0; k < nchunks; ++k) sums->oa[k] = (emv)(0.0f);
#endif
#ifdef EM_TAYLOR_OA
    // The expansion's sums over EM_NW neighbours at a time (lanes), added up
    // in a fixed order at the end.
    emnv v0 = (emnv)(0.0f), v3 = (emnv)(0.0f), v1x = (emnv)(0.0f), v1y = (emnv)(0.0f), v1z = (emnv)(0.0f);
    emnv vxx = (emnv)(0.0f), vyy = (emnv)(0.0f), vzz = (emnv)(0.0f), vxy = (emnv)(0.0f), vxz = (emnv)(0.0f),
        vyz = (emnv)(0.0f);
    emni vatt = (emni)(0);
#endif
    const emni lane = EM_NLANES;
    const float r_search = fmax(d_rep, d_att2);
    int4 blo, bhi;
    grid_search_box(&grid, p4, r_search, &blo, &bhi);
    // The rows of the box trimmed to the ball as grid_row_x_range does (the
    // same operations, so the same cells), the slab distance of each z and
    // the cell edge computed once and 8 rows (y) at a time in vector lanes.
    const float cell = 1.0f / grid.inv_cell;
    const float rr = r_search * 1.00001f, rr2 = rr * rr;
    // Windows of EM_NW slots, filled across rows: lanes [0, k) are slots
    // sa + lane, lanes [k, nv) slots sb + lane (a row's tail, then the next
    // row's head), so a row of 20 slots does not cost two whole windows.  The
    // planes are padded by EM_W (16) slots at both ends, so the loads of a window
    // stay inside the buffer; lanes past nv and agent i itself are masked.
    __global const float* const plane_x = pxyz + EM_W;
    __global const float* const plane_y = plane_x + pstride;
    __global const float* const plane_z = plane_y + pstride;
#define EM_WINDOW(SA, SB, K, NV)                                                                     \
    {                                                                                                \
        const emni first = lane < (emni)((int)(K));                                               \
        const emnv px = select(EM_NLOAD(0, plane_x + (int)(SB)), EM_NLOAD(0, plane_x + (int)(SA)), first);      \
        const emnv py = select(EM_NLOAD(0, plane_y + (int)(SB)), EM_NLOAD(0, plane_y + (int)(SA)), first);      \
        const emnv pz = select(EM_NLOAD(0, plane_z + (int)(SB)), EM_NLOAD(0, plane_z + (int)(SA)), first);      \
        const emni slot = select((emni)((int)(SB)), (emni)((int)(SA)), first) + lane;            \
        const emni valid = lane < (emni)((int)(NV)) && slot != (emni)((int)i);                   \
        const emnv qx = p.x - px, qy = p.y - py, qz = p.z - pz;                                      \
        const emnv d = sqrt(qx * qx + qy * qy + qz * qz);                                            \
        const emni near = valid && d < d_rep;                                                      \
        const emni att = valid && d >= d_att1 && d <= d_att2 && !(d < d_rep);                      \
        EM_WINDOW_ATTRACT                                                                            \
        if (em_any_n(one_by_one)) em_visit_lanes(one_by_one, slot, a, p4, radii, cs, pos, vel, sums);          \
    }
#ifdef EM_TAYLOR_OA
    // exp(rho (d / d_att1 - 1)) as exp2(a log2(e) d - rho2): no division.  RN
    // neighbours one by one: the candidates' sums need each of them.
#define EM_WINDOW_ATTRACT                                                                            \
        const emnv f0 = select((emnv)(0.0f), em_exp2_n(swcl_fma_fast(a2_oa, d, -rho2)), att);                  \
        const emnv inv_d = select((emnv)(0.0f), 1.0f / d, att);                                       \
        const emnv ux = qx * inv_d, uy = qy * inv_d, uz = qz * inv_d;                                \
        const emnv f0a = f0 * a_oa;                                                                   \
        const emnv h = f0a * inv_d;                                                                   \
        const emnv k2 = f0 * swcl_fma_fast(-0.5f * a_oa, inv_d, 0.5f * a_oa * a_oa);                 \
        const emnv kx = k2 * ux, ky = k2 * uy, kz = k2 * uz;                                          \
        v0 += f0;                                                                                   \
        v1x = swcl_fma_fast(f0a, ux, v1x); v1y = swcl_fma_fast(f0a, uy, v1y);                         \
        v1z = swcl_fma_fast(f0a, uz, v1z);                                                           \
        v3 += h; /* times 1/2 at the end */                                                         \
        vxx = swcl_fma_fast(kx, ux, vxx); vyy = swcl_fma_fast(ky, uy, vyy);                           \
        vzz = swcl_fma_fast(kz, uz, vzz); vxy = swcl_fma_fast(kx, uy, vxy);                           \
        vxz = swcl_fma_fast(kx, uz, vxz); vyz = swcl_fma_fast(ky, uz, vyz);                           \
        vatt -= att;                                                                                \
        const emni one_by_one = near;
#else
#define EM_WINDOW_ATTRACT const emni one_by_one = near | att;
#endif
    uint pa = 0u, pk = 0u;  // pending: slots [pa, pa + pk), pk < EM_NW, of rows already walked
    for (int gz = blo.z; gz <= bhi.z; ++gz) {
        const float ez = grid_slab_distance(p.z, grid.origin.z, cell, gz, grid.dims.z), ez2 = ez * ez;
        for (int gy0 = blo.y; gy0 <= bhi.y; gy0 += 8) {
            const float8 ey = grid_slab_distance8(p.y, grid.origin.y, cell,
                                                  (int8)(gy0) + (int8)(0, 1, 2, 3, 4, 5, 6, 7), grid.dims.y);
            const float8 rem = rr2 - ey * ey - ez2;
            const float8 rx = sqrt(fmax(rem, 0.0f));
            float remv[8];
            int x0v[8], x1v[8];
            vstore8(rem, 0, remv);
            vstore8(grid_axis8(p.x - rx, grid.origin.x, grid.inv_cell, grid.dims.x), 0, x0v);
            vstore8(grid_axis8(p.x + rx, grid.origin.x, grid.inv_cell, grid.dims.x), 0, x1v);
            const int rows = min(8, bhi.y - gy0 + 1);
            for (int l = 0; l < rows; ++l) {
                if (remv[l] < 0.0f) continue;
                const uint2 rng = grid_row_range(&grid, x0v[l], x1v[l], gy0 + l, gz);
                uint j = rng.x;
                while (j < rng.y) {
                    uint sa = j, sb = j, k = EM_NW, nv = EM_NW;
                    if (pk > 0u) {  // the pending slots, then this row's first ones
                        const uint m = min((uint)EM_NW - pk, rng.y - j);
                        sa = pa;
                        k = pk;
                        sb = j - pk;  // may be below 0 by up to EM_NW - 1: the padding
                        nv = pk + m;
                        j += m;
                        pk = 0u;
                    } else if (rng.y - j < (uint)EM_NW) {  // the row's tail waits for the next row
                        pa = j;
                        pk = rng.y - j;
                        break;
                    } else {
                        j += EM_NW;
                    }
                    EM_WINDOW(sa, sb, k, nv)
                }
            }
        }
    }
    if (pk > 0u) EM_WINDOW(pa, pa, pk, pk)
#ifdef EM_TAYLOR_OA
    s0 += em_sum_n(v0);
    s1 += (float3)(em_sum_n(v1x), em_sum_n(v1y), em_sum_n(v1z));
    s3 += 0.5f * em_sum_n(v3);
    sxx += em_sum_n(vxx); syy += em_sum_n(vyy); szz += em_sum_n(vzz);
    sxy += em_sum_n(vxy); sxz += em_sum_n(vxz); syz += em_sum_n(vyz);
    {
        int cnt[EM_NW];
        EM_NSTORE(vatt, 0, cnt);
        for (uint l = 0; l < (uint)EM_NW; ++l) sums->natt += (uint)cnt[l];
    }
    sums->s0 = s0; sums->s1 = s1; sums->s3 = s3;
    sums->sxx = sxx; sums->syy = syy; sums->szz = szz;
    sums->sxy = sxy; sums->sxz = sxz; sums->syz = syz;
#endif
#undef EM_WINDOW
#undef EM_WINDOW_ATTRACT
}

// Eq. 6's sum over AN for the candidates of chunk k (velocities vx, vy, vz):
// the exact sums, or the expansion at their displacements m = v dt.
EM_INLINE emv em_attraction_sum(const EmNeighborSums* sums, uint k, emv vx, emv vy, emv vz, float dt) {
#ifdef EM_TAYLOR_OA
    const float s0 = sums->s0, s3 = sums->s3, sxx = sums->sxx, syy = sums->syy, szz = sums->szz,
                sxy = sums->sxy, sxz = sums->sxz, syz = sums->syz;
    const float3 s1 = sums->s1;
    const emv mx = vx * dt, my = vy * dt, mz = vz * dt;  // the candidates' displacements
    const emv oa_c = s0 + (s1.x * mx + s1.y * my + s1.z * mz) + s3 * (mx * mx + my * my + mz * mz) +
                     (sxx * mx * mx + syy * my * my + szz * mz * mz) +
                     2.0f * (sxy * mx * my + sxz * mx * mz + syz * my * mz);
    return oa_c;
#else
    return sums->oa[k];
#endif
}

// E_rep (Eq. 4) and E_oa (Eq. 6): weight times the mean over RN / AN (0
// for an empty set).
EM_INLINE emv em_mean_term(float w, emv sum, uint count, float inv_count) {
    return count ? w * (sum * inv_count) : (emv)(0.0f);
}

// A direction term, w exp(rho |v^ - u^|) over the lanes' unit velocities
// (hx, hy, hz): E_cos (Eq. 7, u^ towards the centre), E_dir (Eq. 9, v^_t),
// E_n (Eq. 13, f_N), E_user (Eq. 14, f_CD).  Terms whose weight is 0 are 0
// (w * a finite exp): not evaluated.
EM_INLINE emv em_direction_term(float w, float rho2, emv hx, emv hy, emv hz, float3 u) {
    return w != 0.0f ? w * em_exp2(rho2 * em_dirv(hx, hy, hz, u)) : (emv)(0.0f);
}

// E_acc (Eq. 10) with a' = (v - v_t) / dt in m/s^2 like the dataset's a; the
// magnitude difference is taken per data frame (times accel_time = the
// data's frame time), the scale of the paper's a' = v - v_t.
EM_INLINE emv em_acceleration_term(float w, const EmAgent* a, float inv_dt, float accel_time, const EmCandidates* cs,
                                   uint c, emv vx, emv vy, emv vz) {
    if (w == 0.0f) return (emv)(0.0f);
    __global const float* const ds = cs->ds;  // for EM_LOAD
    const uint ds_stride = cs->ds_stride;
    const float3 vt = a->vt;
    const float rho2 = a->rho2;
    const emv ax = (vx - vt.x) * inv_dt, ay = (vy - vt.y) * inv_dt, az = (vz - vt.z) * inv_dt;
    const emv alen = em_lenv(ax, ay, az);
    const emv ainv = select((emv)(0.0f), 1.0f / alen, alen > 0.0f);  // em_unit: 0 for a zero vector
    const emv da = em_lenv(ax * ainv - EM_LOAD(EM_P_AHX, c), ay * ainv - EM_LOAD(EM_P_AHY, c),
                           az * ainv - EM_LOAD(EM_P_AHZ, c));
    return w * (em_exp2(rho2 * da) + accel_time * fabs(alen - EM_LOAD(EM_P_AL, c)));
}

// E_env (Eq. 11-12), summed over the stimuli.  A startling stimulus: Psi
// from the closest approach within the horizon, for an agent it startles
// (in reach within the horizon at its current velocity).  Keep-out
// (EM_KEEP_OUT, ours): *viol_out, how far the candidate would enter
// d_danger (0: not at all), is compared before the energy, whatever w_env.
EM_INLINE emv em_environment_term(float w, const EmAgent* a, __global const float4* stim, uint nstim, emv hx, emv hy,
                                  emv hz, emv vx, emv vy, emv vz, emv* viol_out) {
    const float3 p = a->p, vt = a->vt;
    const float rho2 = a->rho2, h = a->h;
    const bool env_on = w != 0.0f;
    emv env = (emv)(0.0f), viol = (emv)(0.0f);
    for (uint s = 0; s < (env_on || EM_KEEP_OUT ? nstim : 0u); ++s) {
        const float4 sp = em_stimulus(stim, s, a->t);
        if (sp.w == STIM_ATTRACT) {
            if (env_on) env += em_exp2(rho2 * em_dirv(hx, hy, hz, em_unit(sp.xyz - p)));
        } else {
            const float dd = stim[2 * s + 1].x;
            const float3 r0 = p - sp.xyz, vs = stim[2 * s + 1].yzw;
            const bool startled = env_on && em_closest(r0, vt - vs, h) < dd;
            if (startled || EM_KEEP_OUT) {
                const emv dmin = em_closestv(r0, vs, vx, vy, vz, h);
                if (startled) env += em_exp2(rho2 * (1.0f - dmin / dd));
                if (EM_KEEP_OUT) viol = fmax(viol, 1.0f - dmin / dd);
            }
        }
    }
    *viol_out = viol;
    return w * env;
}

// The directions the direction terms compare v^ with.
typedef struct {
    float3 centre;  // towards the swarm centre (Eq. 7)
    float3 vt;      // the current velocity (Eq. 9)
    float3 noise;   // f_N (Eq. 13)
    float3 goal;    // f_CD, towards the goal keypoint (Eq. 15)
} EmDirections;

// The eight terms of E (order W_*) for the candidates of chunk k, and their
// keep-out violation.
EM_INLINE void em_chunk_energies(uint k, const EmAgent* a, const EmCandidates* cs, const EmNeighborSums* sums,
                                 const EmDirections* dirs, float8 wt, float inv_dt, float inv_nrep, float inv_natt,
                                 float accel_time, __global const float4* stim, uint nstim, emv* e, emv* viol) {
    __global const float* const ds = cs->ds;  // for EM_LOAD
    const uint ds_stride = cs->ds_stride;
    const float rho2 = a->rho2;
    const uint c = cs->c0 + k * EM_W;
    const emv vx = EM_LOAD(EM_P_VX, c), vy = EM_LOAD(EM_P_VY, c), vz = EM_LOAD(EM_P_VZ, c);
    const emv hx = EM_LOAD(EM_P_VHX, c), hy = EM_LOAD(EM_P_VHY, c), hz = EM_LOAD(EM_P_VHZ, c);
    e[W_REP] = em_mean_term(wt.s0, sums->rep[k], sums->nrep, inv_nrep);                                // Eq. 4
    e[W_OA] = em_mean_term(wt.s1, em_attraction_sum(sums, k, vx, vy, vz, a->dt), sums->natt, inv_natt);  // Eq. 6
    e[W_COS] = em_direction_term(wt.s2, rho2, hx, hy, hz, dirs->centre);  // Eq. 7
    e[W_DIR] = em_direction_term(wt.s3, rho2, hx, hy, hz, dirs->vt);      // Eq. 9
    e[W_ACC] = em_acceleration_term(wt.s4, a, inv_dt, accel_time, cs, c, vx, vy, vz);  // Eq. 10
    e[W_ENV] = em_environment_term(wt.s5, a, stim, nstim, hx, hy, hz, vx, vy, vz, viol);  // Eq. 11-12
    e[W_N] = em_direction_term(wt.s6, rho2, hx, hy, hz, dirs->noise);     // Eq. 13
    e[W_USER] = em_direction_term(wt.s7, rho2, hx, hy, hz, dirs->goal);   // Eq. 14
}

// The argmin so far, per lane over the chunks (strict <: a lane keeps its
// first minimum).  The key is (keep-out violation, energy): least
// violation first.
typedef struct {
    emv v, viol;
    int16 k;  // the chunk
} EmArgmin;

EM_INLINE void em_argmin_init(EmArgmin* b) {
    b->v = (emv)(INFINITY);
    b->viol = (emv)(INFINITY);
    b->k = (int16)(0);
}

// Chunk k's candidates (terms e, violation viol; lanes past nc masked) into the argmin.
EM_INLINE void em_argmin_chunk(EmArgmin* b, uint k, uint nc, const emv* e, emv viol) {
    emv total = (emv)(0.0f);
    for (int q = 0; q < EM_TERM_COUNT; ++q) total += e[q];
    viol = fmax(viol, 0.0f);
    const int16 in_range = (int16)((int)(k * EM_W)) + EM_LANES < (int16)((int)nc);
    const int16 lower = in_range && (viol < b->viol || (viol == b->viol && total < b->v));
    b->viol = select(b->viol, viol, lower);
    b->v = select(b->v, total, lower);
    b->k = select(b->k, (int16)((int)k), lower);
}

// The argmin over the lanes with ties to the lower index: the first
// candidate (offset from c0) holding the minimum, as a scan in index order
// would pick.
EM_INLINE uint em_argmin_resolve(const EmArgmin* b) {
    uint best_c = 0u;
    float bv[EM_W], bviol[EM_W];
    int bk[EM_W];
    vstore16(b->v, 0, bv);
    vstore16(b->viol, 0, bviol);
    vstore16(b->k, 0, bk);
    float best = INFINITY, least_viol = INFINITY;
    for (uint l = 0; l < (uint)EM_W; ++l) {
        const uint cl = (uint)bk[l] * EM_W + l;
        if (bviol[l] < least_viol ||
            (bviol[l] == least_viol && (bv[l] < best || (bv[l] == best && best < INFINITY && cl < best_c)))) {
            least_viol = bviol[l];
            best = bv[l];
            best_c = cl;
        }
    }
    return best_c;
}

#ifdef EM_TERMS
// The checking variant's output: every term of chunk k's candidates.
EM_INLINE void em_write_terms(__global float* terms, uint id, uint k, uint nc, const emv* e) {
    const uint nl = min((uint)EM_W, nc - k * EM_W);
    for (int q = 0; q < EM_TERM_COUNT; ++q) {
        float tl[EM_W];
        vstore16(e[q], 0, tl);
        for (uint l = 0; l < nl; ++l)
            terms[((size_t)id * EM_MAX_CAND + k * EM_W + l) * EM_TERM_COUNT + q] = tl[l];
    }
}
#else
// Next keypoint once the goal is reached (§5.1.2), in the agent's direction;
// open curves turn back at their ends.  Returns the goal to keep.
EM_INLINE uint em_next_goal(__global const float4* kp, uint nkp, uint my_goal, float3 p_new, float reach,
                            int closed) {
    uint k = my_goal & ~GOAL_BACKWARD;
    uint back = my_goal & GOAL_BACKWARD;
    const float4 gk = kp[k];
    if (dist2(gk, (float4)(p_new, 0.0f)) < reach * reach && nkp > 1u) {
        if (closed) {
            k = back ? (k + nkp - 1u) % nkp : (k + 1u) % nkp;
        } else {
            if (back && k == 0u) back = 0u;
            else if (!back && k == nkp - 1u) back = GOAL_BACKWARD;
            k = back ? k - 1u : k + 1u;
        }
    }
    return k | back;
}
#endif

// One agent per work-item: the candidates, the directions and weights, the
// neighbour sums, then every candidate's energy and the argmin (Eq. 1-15).
__kernel void energy_select(EM_SELECT_PARAMS) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    EM_WORLD_AGENTS(pos)
    EM_WORLD_AGENTS(vel)
    EM_WORLD_AGENTS(ids)
    EM_WORLD_AGENTS(pxyz)
    EM_WORLD_AGENTS(noise_pre)
#ifndef EM_TERMS
    EM_WORLD_AGENTS(pos_out)
    EM_WORLD_AGENTS(vel_out)
#endif
    EM_WORLD_BLOCKS(params, noise_block, centre)
#ifdef SWCL_WORLDS
    goal += (size_t)get_global_id(1) * goal_stride;
#endif
    // The model's parameters (host/models/energy_params.cpp lays the block out).
    const float8 w = vload8(0, params + ENERGY_WEIGHTS_REP), wd = vload8(0, params + ENERGY_DANGER_WEIGHTS_REP);
    const float4 radii = (float4)(params[ENERGY_D_REP], params[ENERGY_D_ATT1], params[ENERGY_D_ATT2], params[ENERGY_RHO]);
    const float rho = radii.w;
    const uint span = as_uint(params[ENERGY_SPAN]);
    const float horizon = params[ENERGY_DANGER_HORIZON], reach = params[ENERGY_KEYPOINT_REACH];
    const int closed = params[ENERGY_KEYPOINTS_CLOSED] != 0.0f;
    const float4 p4 = pos[i];
    const uint id = ids[i];
    EmAgent a;
    a.p = p4.xyz;
    a.vt = vel[i].xyz;
    a.dt = dt;
    a.t = t;
    a.h = fmax(dt, horizon);
    a.rho2 = rho * 1.44269504088896341f;
    const float3 p = a.p;

    const EmCandidates cs = em_candidates(a.vt, ds, ds_stride, group_start, group_min_speed, groups, span);

    EmDirections dirs;
    dirs.vt = em_unit(a.vt);
    dirs.centre = em_unit(centre[0].xyz - p);  // Eq. 7
    float nx, ny, nz;
#ifdef EM_NOISE_PRE
    // Sampled for all agents beforehand by the noise module's explicit-width
    // kernel (noise_sample_w, the same field, the same values as the host
    // reference's NoiseField::sample).
    {
        const float4 nv = noise_pre[i];
        nx = nv.x; ny = nv.y; nz = nv.z;
    }
#else
    NOISE_VELOCITY_S(p.x, p.y, p.z, t, id, step, &nx, &ny, &nz);
#endif
    dirs.noise = em_unit((float3)(nx, ny, nz));  // f_N, Eq. 13
    uint my_goal;
    dirs.goal = em_goal_direction(kp, nkp, goal, id, p4, &my_goal);  // f_CD, Eq. 15
    const float8 wt = em_in_danger(&a, stim, nstim) ? wd : w;

    EmNeighborSums sums;
    em_gather_neighbors(&a, i, p4, radii, &cs, pos, vel, GRID_MAKE_WORLD(n), pxyz, pstride, &sums);

    EmArgmin best;
    em_argmin_init(&best);
    const float inv_dt = 1.0f / dt;
    const float inv_nrep = sums.nrep ? 1.0f / (float)sums.nrep : 0.0f;
    const float inv_natt = sums.natt ? 1.0f / (float)sums.natt : 0.0f;
    for (uint k = 0; k < cs.nchunks; ++k) {
        emv e[EM_TERM_COUNT], viol;
        em_chunk_energies(k, &a, &cs, &sums, &dirs, wt, inv_dt, inv_nrep, inv_natt, accel_time, stim, nstim, e, &viol);
        em_argmin_chunk(&best, k, cs.nc, e, viol);
#ifdef EM_TERMS
        em_write_terms(terms, id, k, cs.nc, e);
#endif
    }
    const uint best_c = em_argmin_resolve(&best);
#ifdef EM_TERMS
    chosen[id] = cs.c0 + best_c;
    cand_range[2 * id] = cs.c0;
    cand_range[2 * id + 1] = cs.c0 + cs.nc;
#else
    const float3 v_new = dv[cs.c0 + best_c].xyz;
    const float3 p_new = p + v_new * dt;  // Eq. 1
    pos_out[i] = (float4)(p_new, 0.0f);
    vel_out[i] = (float4)(v_new, 0.0f);
    if (nkp > 0u) goal[id] = em_next_goal(kp, nkp, my_goal, p_new, reach, closed);
#endif
}

// Before energy_select, once per step: the positions as x, y, z planes (the
// float4 -> planes transpose of a 16-slot window compiled to ~60 shuffles
// and scalar loads per window), and with `sum` the partial sums of the swarm
// centre (Eq. 7) without float atomics: chunk c sums slots
// [c * chunk, (c + 1) * chunk) in order, then one work-item sums the chunks
// in order.  Same state, same sum, on every run.  Worlds: world w's
// slots, its planes' slots and its nchunks partial sums, as alone.
__kernel void energy_prepare(__global const float4* pos, uint n, uint chunk, uint sum, uint nchunks,
                             __global float4* partial, __global float* pxyz, uint pstride) {
    const uint c = get_global_id(0);
    if (c >= nchunks) return;
    EM_WORLD_AGENTS(pos)
    EM_WORLD_AGENTS(pxyz)
#ifdef SWCL_WORLDS
    partial += (size_t)get_global_id(1) * nchunks;
#endif
    const uint b = c * chunk, e = min(n, b + chunk);
    float4 s = (float4)(0.0f);
    for (uint k = b; k < e; ++k) {
        const float4 p = pos[k];
        pxyz[EM_W + k] = p.x;  // after EM_W slots of padding (energy_select's windows)
        pxyz[pstride + EM_W + k] = p.y;
        pxyz[2u * (size_t)pstride + EM_W + k] = p.z;
        s += (float4)(p.xyz, 1.0f);
    }
    if (sum) partial[c] = s;
}

__kernel void energy_centre_final(__global const float4* partial, uint chunks, __global float4* centre) {
    if (get_global_id(0) != 0) return;
#ifdef SWCL_WORLDS
    partial += (size_t)get_global_id(1) * chunks;  // world w's chunks, its centre
    centre += get_global_id(1);
#endif
    float4 s = (float4)(0.0f);
    for (uint c = 0; c < chunks; ++c) s += partial[c];
    centre[0] = s.w > 0.0f ? (float4)(s.xyz / s.w, s.w) : (float4)(0.0f);
}
