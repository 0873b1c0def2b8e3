// policy_observe (SWCL_BW = 1: one agent per work-item, GPUs) and
// policy_observe_w (SWCL_BW = SWCL_W consecutive slots per work-item, CPU
// devices; launch ceil(n / SWCL_W)): the observations of Eq. 11-13 (paper
// drl-swarm-animation-rule-based-action-generator, §III-C) by slot,
// obs_dim floats per agent: rl_observe's values (kernels/rl_env.cl) with the
// swarm's neighbour grid in place of the per-world loop.  lst[0] = leader
// position, lst[1] = leader (q, u); qu4[s] = agent s's (q, u) (policy_headings);
// `search` >= r_coh + body and >= r_nbr.
//
// One body, so every width has the same tests and arithmetic in the same
// order (bitwise the same observations: tests/test_policy.cpp,
// PolicyObserve.EveryWidthGivesTheScalarKernelsBits).  The lanes are
// neighbouring agents (the grid keeps the state in cell order); each
// candidate is loaded once and tested against every lane.  Every width
// walks the rows of the lanes' bounding box [bmin, bmax] trimmed to the
// union of their balls (grid_row_x_range_box; width 1: its own ball), the
// loop bounds the same in every lane, so the work per candidate is vector
// arithmetic.  The walk goes row by row (z, y) in slot order, so each lane meets the
// candidates that can count for it — within `search` (r_nbr <= search,
// r_coh + body <= search), which every walk visits — in the same order;
// any other candidate changes nothing (it fails every test below).  Then
// the leader (rays only).  The candidates' sums (Eq. 12's EFS) and ray
// minima are lib/rl_common.cl's rl_obs_target written out in lanes; the
// agent's own entries and the finish are rl_obs_local / rl_obs_finish.
// A reach beyond the world's own (worlds with other radii) only adds
// candidates that fail every test.
// Included by policy.cl once per width.
#include "wide/width.inc.cl"

__kernel void SWCL_KERNEL(policy_observe)(__global const float4* pos, __global const float4* qu4, uint n,
                                          GRID_WORLD_PARAMS, __global const float4* lst, float search,
                                          __global const float* params,
                                          __global const float4* box_c, __global const float4* box_h, uint nbox,
                                          int efs, uint obs_dim, __global float* obs) {
    const uint base = get_global_id(0) * SWCL_BW;
    if (base >= n) return;
#ifdef SWCL_WORLDS
    // World get_global_id(1) of a swarm of worlds, n agents each
    // (lib/grid_common.cl): its agents, observations, leader state and
    // parameter block.
    const size_t world = get_global_id(1), world_base = world * n;
    pos += world_base;
    qu4 += world_base;
    obs += world_base * obs_dim;
    lst += 2 * world;
    params += world * POLICY_FLOATS;
#endif
    // The model's parameter block (models/policy_params.cpp, POLICY_<KEY>
    // slots); the search reach (at least every world's) comes from the host.
    const float r_coh = params[POLICY_R_COH], body = params[POLICY_BODY_RADIUS];
    const float r_nbr = params[POLICY_NEIGHBOR_RADIUS] > 0.0f ? params[POLICY_NEIGHBOR_RADIUS] : r_coh;
    const Grid g = GRID_MAKE_WORLD(n);
    const float3 lp = lst[0].xyz;
    const float4 lv = lst[1];
    // Each lane's agent (lanes past n repeat agent n - 1): position, (q, u)
    // (policy_qu) and heading frame (rl_frame); the lanes' bounding box.
    float lx[SWCL_BW], ly[SWCL_BW], lz[SWCL_BW], lqx[SWCL_BW], lqy[SWCL_BW], lqz[SWCL_BW], lu_[SWCL_BW];
    float lrx[SWCL_BW], lry[SWCL_BW], lrz[SWCL_BW], lux[SWCL_BW], luy[SWCL_BW], luz[SWCL_BW];
    float4 bmin = (float4)(INFINITY), bmax = (float4)(-INFINITY);
    for (uint l = 0; l < SWCL_BW; ++l) {
        const uint s = min(base + l, n - 1u);
        const float4 p4 = pos[s];
        const float4 qu = qu4[s];
        float3 fr, fu;
        rl_frame(qu.xyz, &fr, &fu);
        lx[l] = p4.x; ly[l] = p4.y; lz[l] = p4.z;
        lqx[l] = qu.x; lqy[l] = qu.y; lqz[l] = qu.z; lu_[l] = qu.w;
        lrx[l] = fr.x; lry[l] = fr.y; lrz[l] = fr.z;
        lux[l] = fu.x; luy[l] = fu.y; luz[l] = fu.z;
        bmin = fmin(bmin, (float4)(p4.xyz, 0.0f));
        bmax = fmax(bmax, (float4)(p4.xyz, 0.0f));
    }
    const swcl_bf px = SWCL_BVLOAD(lx), py = SWCL_BVLOAD(ly), pz = SWCL_BVLOAD(lz);
    const swcl_bf qx = SWCL_BVLOAD(lqx), qy = SWCL_BVLOAD(lqy), qz = SWCL_BVLOAD(lqz);
    const swcl_bf rx = SWCL_BVLOAD(lrx), ry = SWCL_BVLOAD(lry), rz = SWCL_BVLOAD(lrz);
    const swcl_bf ux = SWCL_BVLOAD(lux), uy = SWCL_BVLOAD(luy), uz = SWCL_BVLOAD(luz);
    const swcl_bu slot = SWCL_BLAST((swcl_bu)(base) + SWCL_BLANE_IDS, n);
    const swcl_bf zero = (swcl_bf)(0.0f);
    swcl_bf ray[RL_RAYS];
    for (int k = 0; k < RL_RAYS; ++k) ray[k] = (swcl_bf)(INFINITY);
    swcl_bf su = zero, sq = zero, sd = zero;
    swcl_bu nn = (swcl_bu)(0u);
    // s2 widened: rounding never drops a candidate within `search`.
    const float b2 = body * body, s2 = search * search * 1.0001f, reach = r_coh + body;
    // Ray k's test in the lanes of row mask mrow (rl_obs_target's): its
    // parameter tt at the target's centre, the centre's squared distance from
    // the ray, the lanes it hits.
#define PO_RAY_TEST(k)                                                                                         \
    const swcl_bf tt =                                                                                         \
        rl_ray_table[3 * (k)] * lf + rl_ray_table[3 * (k) + 1] * lr + rl_ray_table[3 * (k) + 2] * lu;          \
    const swcl_bf perp2 = dd - tt * tt;                                                                        \
    const swcl_bi hit = mrow & (tt > 0.0f) & (perp2 < b2);
    // One candidate at (cx, cy, cz) with (q, u) cq for every lane; follower
    // 0: the leader (rays only).  self: the lanes that are this candidate.
    // rl_obs_target's tests in its order: a follower within r_nbr is a
    // neighbour (Eq. 12's sums); a target within r_coh + body may be hit by
    // the rays, every ray at 0 from inside it, else each ray row whose bound
    // allows a hit (the cull) is tested ray by ray.
#define PO_VISIT(cx, cy, cz, cq, follower, self)                                                              \
    {                                                                                                          \
        const swcl_bf dx = (swcl_bf)(cx) - px, dy = (swcl_bf)(cy) - py, dz = (swcl_bf)(cz) - pz;               \
        /* The lanes that are this candidate at +inf: cand is one compare (a mask combined with & is     \
           packed to bytes and back on AVX2); every later mask is within cand. */                              \
        const swcl_bf dd = select(dx * dx + dy * dy + dz * dz, (swcl_bf)(INFINITY), self);                    \
        const swcl_bi cand = dd <= s2;                                                                         \
        if (SWCL_BANY(cand)) {                                                                                 \
            const swcl_bf dist = sqrt(dd);                                                                     \
            if (follower) {                                                                                    \
                const swcl_bi m = dist <= r_nbr; /* within cand: r_nbr <= search */                          \
                const swcl_bf ex = (swcl_bf)((cq).x) - qx, ey = (swcl_bf)((cq).y) - qy,                        \
                              ez = (swcl_bf)((cq).z) - qz;                                                     \
                SWCL_BCOUNT_IF(nn, m);                                                                         \
                su = select(su, su + (swcl_bf)((cq).w), m);                                                    \
                sq = select(sq, sq + sqrt(ex * ex + ey * ey + ez * ez), m);                                    \
                sd = select(sd, sd + dist, m);                                                                 \
            }                                                                                                  \
            const swcl_bi mr = dist <= reach; /* within cand: reach <= search */                             \
            const swcl_bi inside = mr & (dd <= b2);                                                            \
            if (SWCL_BANY(inside))                                                                             \
                for (int k = 0; k < RL_RAYS; ++k) ray[k] = select(ray[k], zero, inside);                       \
            const swcl_bi hitable = mr & ~inside;                                                              \
            if (SWCL_BANY(hitable)) {                                                                          \
                const swcl_bf lf = dx * qx + dy * qy + dz * qz, lr = dx * rx + dy * ry + dz * rz,              \
                              lu = dx * ux + dy * uy + dz * uz;                                                \
                /* h bounds lf cos(az) + lr sin(az) over the rays' azimuths, -90 to 90 degrees (the rays    \
                   point forward): |(lf, lr)| for a target ahead, |lr| behind, so targets behind the agent      \
                   pass the rows' cull only near its sides. */                                                  \
                const swcl_bf h = select(fabs(lr), sqrt(lf * lf + lr * lr), lf >= 0.0f);                       \
                const swcl_bf need = (dd - b2) - 1e-5f * dd;                                                   \
                /* The rows' tests unrolled: 4 % of policy_bench's observations at 100k agents    \
                   (bench/results/policy_observe/unrolled_rows_ab.json). */                                     \
                swcl_bi mrows[RL_RAYS / 7], any_row = (swcl_bi)(0);                                            \
                _Pragma("unroll") for (int e = 0; e < RL_RAYS / 7; ++e) {                                      \
                    const swcl_bf bound = rl_row_cos[e] * h + rl_row_sin[e] * lu;                              \
                    mrows[e] = hitable & (bound > 0.0f) & (bound * bound >= need);                             \
                    any_row |= mrows[e];                                                                       \
                }                                                                                              \
                if (SWCL_BANY(any_row))                                                                        \
                for (int e = 0; e < RL_RAYS / 7; ++e) {                                                        \
                    const swcl_bi mrow = mrows[e];                                                             \
                    if (!SWCL_BANY(mrow)) continue;                                                            \
                    /* The row's seven tests first (most rows that pass the cull hit no ray), then the    \
                       rays some lane hits, tested again alike. */                                             \
                    swcl_bi any_hit = (swcl_bi)(0);                                                            \
                    for (int k = 7 * e; k < 7 * e + 7; ++k) {                                                  \
                        PO_RAY_TEST(k)                                                                         \
                        any_hit |= hit;                                                                        \
                    }                                                                                          \
                    if (SWCL_BANY(any_hit))                                                                    \
                        for (int k = 7 * e; k < 7 * e + 7; ++k) {                                              \
                            PO_RAY_TEST(k)                                                                     \
                            if (SWCL_BANY(hit))                                                                \
                                ray[k] = select(ray[k], fmin(ray[k], tt - sqrt(fmax(b2 - perp2, 0.0f))), hit); \
                        }                                                                                      \
                }                                                                                              \
            }                                                                                                  \
        }                                                                                                      \
    }
    int4 lo, hi, lo2, hi2;
    grid_search_box(&g, bmin, search, &lo, &hi);
    grid_search_box(&g, bmax, search, &lo2, &hi2);
    lo = min(lo, lo2);
    hi = max(hi, hi2);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y) {
            int x0 = lo.x, x1 = hi.x;
            if (!grid_row_x_range_box(&g, bmin, bmax, search, y, z, &x0, &x1)) continue;
            const uint2 rg = grid_row_range(&g, x0, x1, y, z);
            for (uint j = rg.x; j < rg.y; ++j) {
                const float4 pj = pos[j];
                const float4 cq = qu4[j];
                PO_VISIT(pj.x, pj.y, pj.z, cq, 1, slot == (swcl_bu)(j))
            }
        }
    PO_VISIT(lp.x, lp.y, lp.z, lv, 0, (swcl_bi)(0))
#undef PO_VISIT
#undef PO_RAY_TEST
    // Each lane's observation: rl_common.cl's accumulator filled from the
    // lanes, then the shared rl_obs_local / rl_obs_finish.
    float rays[RL_RAYS][SWCL_BW], lsu[SWCL_BW], lsq[SWCL_BW], lsd[SWCL_BW];
    uint lnn[SWCL_BW];
    for (int k = 0; k < RL_RAYS; ++k) SWCL_BVSTORE(ray[k], rays[k]);
    SWCL_BVSTORE(su, lsu);
    SWCL_BVSTORE(sq, lsq);
    SWCL_BVSTORE(sd, lsd);
    SWCL_BVSTORE(nn, lnn);
    for (uint l = 0; l < SWCL_BW && base + l < n; ++l) {
        RlObsAcc acc;
        for (int k = 0; k < RL_RAYS; ++k) acc.ray[k] = rays[k][l];
        acc.sum_u = lsu[l];
        acc.sum_q = lsq[l];
        acc.sum_d = lsd[l];
        acc.sum_du = acc.sum_dist = 0.0f;  // the environment's rewards only
        acc.nn = lnn[l];
        const float3 p = (float3)(lx[l], ly[l], lz[l]), q = (float3)(lqx[l], lqy[l], lqz[l]);
        __global float* o = obs + (size_t)(base + l) * obs_dim;
        rl_obs_local(o, p, q, lu_[l], lp, lv.w);
        rl_obs_finish(&acc, o, p, q, (float3)(lrx[l], lry[l], lrz[l]), (float3)(lux[l], luy[l], luz[l]), r_coh,
                      box_c, box_h, nbox, efs);
    }
}
