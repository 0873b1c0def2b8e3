// The policy model (issue 15 item 7; paper drl-swarm-animation-rule-based-
// action-generator, §III-IV): a trained actor MLP drives a swarm that follows
// a leader.  Each step: the observations of Eq. 11-13 over the swarm's
// neighbour grid with the environment's code (lib/rl_common.cl), the MLP
// batched over agents (policy_mlp), Eq. 2's kinematics (policy_apply).  The
// leader is stepped by rl_env.cl's rl_leader_step.  docs/rl-swarm.md,
// "Policy model".
//
// Swarm state: pos[s] = (x, y, z, -), vel[s] = (u q, -): the velocity, so
// reads and recordings are the velocity.  Speed u = |vel.xyz|, heading
// q = vel.xyz / u; an agent at rest (u = 0) heads towards the leader (ours:
// the swarm has no other place to keep a heading).
#pragma OPENCL FP_CONTRACT OFF
#include "lib/grid_common.cl"
#include "lib/rl_common.cl"

// (q, u) of an agent at p with velocity v, the leader at lp.
SWCL_INLINE float4 policy_qu(float4 v, float3 p, float3 lp) {
    const float u = length(v.xyz);
    if (u > 0.0f) return (float4)(v.xyz / u, u);
    const float3 to = lp - p;
    const float l = length(to);
    return l > 0.0f ? (float4)(to / l, 0.0f) : (float4)(1.0f, 0.0f, 0.0f, 0.0f);
}

// Observations by slot (obs_dim floats per agent), rl_observe's values with
// the neighbour grid in place of the per-world loop: every agent within
// `search` (>= r_coh + body and >= r_nbr) is visited, in cell order, then
// the leader.  lst[0] = leader position, lst[1] = leader (q, u).
__kernel void policy_observe(__global const float4* pos, __global const float4* vel, uint n, GRID_PARAMS,
                             __global const float4* lst, float search, float r_coh, float r_nbr, float body,
                             __global const float4* box_c, __global const float4* box_h, uint nbox, int efs,
                             uint obs_dim, __global float* obs) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const Grid g = GRID_MAKE();
    const float4 p4 = pos[s];
    const float3 p = p4.xyz;
    const float3 lp = lst[0].xyz;
    const float4 lv = lst[1];
    const float4 qu = policy_qu(vel[s], p, lp);
    const float3 q = qu.xyz;
    const float u = qu.w;
    __global float* o = obs + (size_t)s * obs_dim;
    rl_obs_local(o, p, q, u, lp, lv.w);
    float3 fr, fu;
    rl_frame(q, &fr, &fu);
    RlObsAcc acc;
    rl_obs_begin(&acc);
    // The search box's rows trimmed to the ball of radius `search`
    // (grid_row_x_range), and candidates beyond it skipped before anything
    // else: rl_obs_target ignores them anyway (beyond r_nbr and r_coh + body).
    const float s2 = search * search * 1.0001f;
    int4 lo, hi;
    grid_search_box(&g, p4, search, &lo, &hi);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y) {
            int x0, x1;
            if (!grid_row_x_range(&g, p4, search, y, z, &x0, &x1)) continue;
            const uint2 rg = grid_row_range(&g, x0, x1, y, z);
            for (uint j = rg.x; j < rg.y; ++j) {
                const float3 pj = pos[j].xyz;
                const float3 dj = pj - p;
                if (j == s || dot(dj, dj) > s2) continue;  // s2 widened: rounding never drops one
                rl_obs_target(&acc, dj, 1, policy_qu(vel[j], pj, lp), q, u, fr, fu, r_nbr, r_coh, body, 0.0f, 1);
            }
        }
    rl_obs_target(&acc, lp - p, 0, (float4)(0.0f), q, u, fr, fu, r_nbr, r_coh, body, 0.0f, 1);
    rl_obs_finish(&acc, o, p, q, fr, fu, r_coh, box_c, box_h, nbox, efs);
}

// ---- the MLP (§IV-A, Fig. 6), batched over agents ---------------------------
// PM_W agents per work-item (1, 8 or 16 lanes: on CPU devices the lanes are
// the SIMD vector; weights are read once per PM_W agents).  Work-item t of a
// launch handles tile first_tile + t, agents tile * PM_W + lane.
// Activations live in `scratch`, per work-item 2 * max_width * PM_W floats,
// feature-major ([feature][lane]) so a feature of all lanes is one vector.
// params: every layer's weight (out x in, row-major) then bias, and the
// normalisation; layers[5 l ..] = {in, out, activation, weight offset, bias
// offset}; activation 0 relu, 1 linear, 2 tanh.  acc = fma(w, x, acc) in
// input order from the bias, as the C++ reference does.
#ifndef PM_W
#define PM_W 1
#endif
#if PM_W == 16
typedef float16 pm_f;
#define PM_LOAD(i, p) vload16(i, p)
#define PM_STORE(v, i, p) vstore16(v, i, p)
#elif PM_W == 8
typedef float8 pm_f;
#define PM_LOAD(i, p) vload8(i, p)
#define PM_STORE(v, i, p) vstore8(v, i, p)
#elif PM_W == 1
typedef float pm_f;
#define PM_LOAD(i, p) ((p)[i])
#define PM_STORE(v, i, p) ((p)[i] = (v))
#else
#error "PM_W must be 1, 8 or 16"
#endif

SWCL_INLINE pm_f pm_activate(pm_f x, uint act) {
    if (act == 0u) return fmax(x, (pm_f)(0.0f));
    if (act == 2u) return tanh(x);
    return x;
}

__kernel void policy_mlp(__global const float* obs, uint n, uint obs_dim, uint first_tile,
                         __global const float* params, __global const uint* layers, uint nlayers, int norm,
                         uint mean_off, uint std_off, float4 scale, uint max_width, __global float* scratch,
                         __global float* actions) {
    const uint t = get_global_id(0);
    const uint tile = first_tile + t;
    const uint a0 = tile * PM_W;
    if (a0 >= n) return;
    __global float* xa = scratch + (size_t)t * 2u * max_width * PM_W;
    __global float* xb = xa + (size_t)max_width * PM_W;
    // Input: obs gathered lane by lane (agents past n read agent n-1).
    for (uint i = 0; i < obs_dim; ++i) {
        for (uint l = 0; l < PM_W; ++l) {
            const uint a = min(a0 + l, n - 1u);
            float x = obs[(size_t)a * obs_dim + i];
            if (norm) x = (x - params[mean_off + i]) / params[std_off + i];
            xa[i * PM_W + l] = x;
        }
    }
    for (uint L = 0; L < nlayers; ++L) {
        const uint in = layers[5 * L], out = layers[5 * L + 1], act = layers[5 * L + 2];
        __global const float* W = params + layers[5 * L + 3];
        __global const float* B = params + layers[5 * L + 4];
        uint o = 0;
        for (; o + 4 <= out; o += 4) {  // four outputs per pass over the inputs
            pm_f c0 = (pm_f)(B[o]), c1 = (pm_f)(B[o + 1]), c2 = (pm_f)(B[o + 2]), c3 = (pm_f)(B[o + 3]);
            __global const float* w0 = W + (size_t)o * in;
            for (uint i = 0; i < in; ++i) {
                const pm_f x = PM_LOAD(i, xa);
                c0 = fma((pm_f)(w0[i]), x, c0);
                c1 = fma((pm_f)(w0[in + i]), x, c1);
                c2 = fma((pm_f)(w0[2 * in + i]), x, c2);
                c3 = fma((pm_f)(w0[3 * in + i]), x, c3);
            }
            PM_STORE(pm_activate(c0, act), o, xb);
            PM_STORE(pm_activate(c1, act), o + 1, xb);
            PM_STORE(pm_activate(c2, act), o + 2, xb);
            PM_STORE(pm_activate(c3, act), o + 3, xb);
        }
        for (; o < out; ++o) {
            pm_f c = (pm_f)(B[o]);
            __global const float* w0 = W + (size_t)o * in;
            for (uint i = 0; i < in; ++i) c = fma((pm_f)(w0[i]), PM_LOAD(i, xa), c);
            PM_STORE(pm_activate(c, act), o, xb);
        }
        __global float* tmp = xa;
        xa = xb;
        xb = tmp;
    }
    // Output: 4 actions per agent, times the action scale.
    for (uint l = 0; l < PM_W; ++l) {
        const uint a = a0 + l;
        if (a >= n) break;
        actions[4 * (size_t)a] = xa[l] * scale.x;
        actions[4 * (size_t)a + 1] = xa[PM_W + l] * scale.y;
        actions[4 * (size_t)a + 2] = xa[2 * PM_W + l] * scale.z;
        actions[4 * (size_t)a + 3] = xa[3 * PM_W + l] * scale.w;
    }
}

// ---- observations, PM_W agents per work-item (CPU devices) --------------------
// policy_observe's values for the PM_W consecutive slots of tile t (agents
// of neighbouring cells: the grid keeps the state in cell order), each
// candidate visited once for all lanes: the loop over the union of the lanes'
// search boxes has the same bounds in every lane, so the per-candidate work
// is vector arithmetic (the per-agent loop of policy_observe is not
// vectorised across work-items: its bounds differ).  The EFS sums add in the
// union's order, so they may differ from policy_observe's in the last bits;
// the rays are the same minima.
#if PM_W > 1
#if PM_W == 16
typedef int16 pm_i;
#define PM_CVT_I convert_int16
#else
typedef int8 pm_i;
#define PM_CVT_I convert_int8
#endif

__kernel void policy_observe_w(__global const float4* pos, __global const float4* vel, uint n, GRID_PARAMS,
                               __global const float4* lst, float search, float r_coh, float r_nbr, float body,
                               __global const float4* box_c, __global const float4* box_h, uint nbox, int efs,
                               uint obs_dim, __global float* obs) {
    const uint t = get_global_id(0);
    const uint s0 = t * PM_W;
    if (s0 >= n) return;
    const Grid g = GRID_MAKE();
    const float3 lp = lst[0].xyz;
    const float4 lv = lst[1];
    float lx[PM_W], ly[PM_W], lz[PM_W], lqx[PM_W], lqy[PM_W], lqz[PM_W], lu_[PM_W];
    float lrx[PM_W], lry[PM_W], lrz[PM_W], lux[PM_W], luy[PM_W], luz[PM_W];
    int lslot[PM_W];
    float4 bmin = (float4)(INFINITY), bmax = (float4)(-INFINITY);
    for (uint l = 0; l < PM_W; ++l) {
        const uint s = min(s0 + l, n - 1u);
        const float4 p4 = pos[s];
        const float4 qu = policy_qu(vel[s], p4.xyz, lp);
        float3 fr, fu;
        rl_frame(qu.xyz, &fr, &fu);
        lx[l] = p4.x; ly[l] = p4.y; lz[l] = p4.z;
        lqx[l] = qu.x; lqy[l] = qu.y; lqz[l] = qu.z; lu_[l] = qu.w;
        lrx[l] = fr.x; lry[l] = fr.y; lrz[l] = fr.z;
        lux[l] = fu.x; luy[l] = fu.y; luz[l] = fu.z;
        lslot[l] = (int)s;
        bmin = fmin(bmin, (float4)(p4.xyz, 0.0f));
        bmax = fmax(bmax, (float4)(p4.xyz, 0.0f));
    }
    const pm_f px = PM_LOAD(0, lx), py = PM_LOAD(0, ly), pz = PM_LOAD(0, lz);
    const pm_f qx = PM_LOAD(0, lqx), qy = PM_LOAD(0, lqy), qz = PM_LOAD(0, lqz), uu = PM_LOAD(0, lu_);
    const pm_f rx = PM_LOAD(0, lrx), ry = PM_LOAD(0, lry), rz = PM_LOAD(0, lrz);
    const pm_f ux = PM_LOAD(0, lux), uy = PM_LOAD(0, luy), uz = PM_LOAD(0, luz);
    const pm_i slot = PM_LOAD(0, lslot);
    pm_f ray[RL_RAYS];
    for (int k = 0; k < RL_RAYS; ++k) ray[k] = (pm_f)(INFINITY);
    pm_f su = (pm_f)(0.0f), sq = (pm_f)(0.0f), sd = (pm_f)(0.0f);
    pm_i nn = (pm_i)(0);
    const float b2 = body * body, s2 = search * search * 1.0001f, reach = r_coh + body;
    // One candidate at (cx, cy, cz) with (q, u) cq for every lane; follower
    // 0: the leader (rays only).  self: lanes that are this candidate.
#define PM_VISIT(cx, cy, cz, cq, follower, self)                                                              \
    {                                                                                                          \
        const pm_f dx = (pm_f)(cx) - px, dy = (pm_f)(cy) - py, dz = (pm_f)(cz) - pz;                           \
        const pm_f dd = dx * dx + dy * dy + dz * dz;                                                           \
        const pm_i cand = (dd <= (pm_f)(s2)) & ~(self);                                                        \
        if (any(cand)) {                                                                                       \
            const pm_f dist = sqrt(dd);                                                                        \
            if (follower) {                                                                                    \
                const pm_i m = cand & (dist <= (pm_f)(r_nbr));                                                 \
                const pm_f ex = (pm_f)((cq).x) - qx, ey = (pm_f)((cq).y) - qy, ez = (pm_f)((cq).z) - qz;       \
                nn -= m;                                                                                       \
                su += select((pm_f)(0.0f), (pm_f)((cq).w), m);                                                 \
                sq += select((pm_f)(0.0f), sqrt(ex * ex + ey * ey + ez * ez), m);                              \
                sd += select((pm_f)(0.0f), dist, m);                                                           \
            }                                                                                                  \
            const pm_i mr = cand & (dist <= (pm_f)(reach));                                                    \
            const pm_i inside = mr & (dd <= (pm_f)(b2));                                                       \
            if (any(inside))                                                                                   \
                for (int k = 0; k < RL_RAYS; ++k) ray[k] = select(ray[k], (pm_f)(0.0f), inside);               \
            const pm_i hitable = mr & ~inside;                                                                     \
            if (any(hitable)) {                                                                                    \
                const pm_f lf = dx * qx + dy * qy + dz * qz, lr = dx * rx + dy * ry + dz * rz,                 \
                           lu = dx * ux + dy * uy + dz * uz;                                                   \
                const pm_f h = sqrt(lf * lf + lr * lr), need = (dd - (pm_f)(b2)) - (pm_f)(1e-5f) * dd;        \
                for (int e = 0; e < RL_RAYS / 7; ++e) {                                                        \
                    const pm_f bound = (pm_f)(rl_row_cos[e]) * h + (pm_f)(rl_row_sin[e]) * lu;                 \
                    const pm_i mrow = hitable & (bound > (pm_f)(0.0f)) & (bound * bound >= need);                  \
                    if (!any(mrow)) continue;                                                                  \
                    for (int k = 7 * e; k < 7 * e + 7; ++k) {                                                  \
                        const pm_f tt = (pm_f)(rl_ray_table[3 * k]) * lf + (pm_f)(rl_ray_table[3 * k + 1]) * lr + \
                                        (pm_f)(rl_ray_table[3 * k + 2]) * lu;                                  \
                        const pm_f perp2 = dd - tt * tt;                                                       \
                        const pm_i hit = mrow & (tt > (pm_f)(0.0f)) & (perp2 < (pm_f)(b2));                    \
                        ray[k] = select(ray[k], fmin(ray[k], tt - sqrt(fmax((pm_f)(b2) - perp2, (pm_f)(0.0f)))), hit); \
                    }                                                                                          \
                }                                                                                              \
            }                                                                                                  \
        }                                                                                                      \
    }
    int4 lo, hi;
    grid_search_box(&g, bmin, search, &lo, &hi);
    int4 lo2, hi2;
    grid_search_box(&g, bmax, search, &lo2, &hi2);
    lo = min(lo, lo2);
    hi = max(hi, hi2);
    for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y) {
            const uint2 rg = grid_row_range(&g, lo.x, hi.x, y, z);
            for (uint j = rg.x; j < rg.y; ++j) {
                const float4 pj = pos[j];
                const float4 cq = policy_qu(vel[j], pj.xyz, lp);
                const pm_i self = slot == (pm_i)((int)j);
                PM_VISIT(pj.x, pj.y, pj.z, cq, 1, self)
            }
        }
    PM_VISIT(lp.x, lp.y, lp.z, lv, 0, (pm_i)(0))
#undef PM_VISIT
    // Each lane's observation: the accumulator of lib/rl_common.cl filled
    // from the vectors, then the shared rl_obs_local / rl_obs_finish.
    float tmp[PM_W];
    for (uint l = 0; l < PM_W && s0 + l < n; ++l) {
        RlObsAcc acc;
        for (int k = 0; k < RL_RAYS; ++k) {
            PM_STORE(ray[k], 0, tmp);
            acc.ray[k] = tmp[l];
        }
        PM_STORE(su, 0, tmp);
        acc.sum_u = tmp[l];
        PM_STORE(sq, 0, tmp);
        acc.sum_q = tmp[l];
        PM_STORE(sd, 0, tmp);
        acc.sum_d = tmp[l];
        acc.sum_du = acc.sum_dist = 0.0f;
        int itmp[PM_W];
        PM_STORE(nn, 0, itmp);
        acc.nn = (uint)itmp[l];
        const float3 p = (float3)(lx[l], ly[l], lz[l]), q = (float3)(lqx[l], lqy[l], lqz[l]);
        __global float* o = obs + (size_t)(s0 + l) * obs_dim;
        rl_obs_local(o, p, q, lu_[l], lp, lv.w);
        rl_obs_finish(&acc, o, p, q, (float3)(lrx[l], lry[l], lrz[l]), (float3)(lux[l], luy[l], luz[l]), r_coh,
                      box_c, box_h, nbox, efs);
    }
}
#endif

// ---- Eq. 2: the actions applied (rl_agents_step on the swarm's layout) -------
__kernel void policy_apply(__global float4* pos, __global float4* vel, __global const float* actions, uint n,
                           __global const float4* lst_before, float du_max, float dq_max, float u_max, float dt) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const float3 p = pos[s].xyz;
    const float4 qu = policy_qu(vel[s], p, lst_before[0].xyz);
    const float du = clamp(actions[4 * s], -du_max, du_max);
    const float3 dq = (float3)(actions[4 * s + 1], actions[4 * s + 2], actions[4 * s + 3]);
    const float u = clamp(qu.w + du, 0.0f, u_max);
    const float3 q = rl_turn(qu.xyz, dq, dq_max);
    vel[s] = (float4)(u * q, 0.0f);
    pos[s] = (float4)(p + (u * dt) * q, 0.0f);
}

// The leader's state as policy_observe reads it: lst[0] = position,
// lst[1] = (q, u); copied before the leader moves, so the followers'
// actions and rest headings use the state they were observed in.
__kernel void policy_leader_copy(__global const float4* lpos, __global const float4* lvel, __global float4* lst) {
    if (get_global_id(0) != 0) return;
    lst[0] = lpos[0];
    lst[1] = lvel[0];
}
