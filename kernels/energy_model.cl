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
// EM_TAYLOR_OA (Eq. 6 by a second-order expansion, see below).
#include "noise_field.cl"
#include "grid_common.cl"

#ifndef EM_MAX_CAND
#define EM_MAX_CAND 64
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
inline float3 em_unit(float3 v) {
    const float l2 = v.x * v.x + v.y * v.y + v.z * v.z;
    return l2 > 0.0f ? v / sqrt(l2) : (float3)(0.0f);
}

inline float em_len(float3 v) { return sqrt(v.x * v.x + v.y * v.y + v.z * v.z); }

// Speed group of speed s: the last group whose slowest sample is <= s.
inline uint em_group(float s, __global const float* group_min_speed, uint groups) {
    uint g = 0;
    for (uint k = 1; k < groups; ++k)
        if (group_min_speed[k] <= s) g = k;
    return g;
}

// Kernel arguments (EnergyModel::set_step_args):
//   state: pos, vel (float4, slot order), ids, n;
//   time: dt, t, step;
//   dataset (sorted by speed): dv = (v, 0), dvh = (v^, |v|), dah = (a^, |a|)
//            (unit vectors and lengths precomputed on the host), group_start (groups + 1),
//            group_min_speed, groups, span (neighbouring groups searched);
//   centre: float4 (xyz: swarm centre, from energy_centre_*);
//   w, wd: weights normally and in danger (float8, order W_*);
//   radii: (d_rep, d_att1, d_att2, rho); extra: (accel_time, danger_horizon, keypoint_reach, keypoints_closed);
//   stim: 2 float4 per stimulus ((x, y, z, kind), (d_danger, 0, 0, 0)), nstim;
//   kp: keypoints (float4), nkp, goal (per agent id);
//   grid, noise.
__kernel void energy_select(__global const float4* pos, __global const float4* vel, __global const uint* ids,
                            uint n, float dt, float t, uint step,
                            __global const float4* dv, __global const float4* dvh, __global const float4* dah,
                            __global const uint* group_start, __global const float* group_min_speed,
                            uint groups, uint span,
                            __global const float4* centre, float8 w, float8 wd, float4 radii, float4 extra,
                            __global const float4* stim, uint nstim,
                            __global const float4* kp, uint nkp, __global uint* goal,
                            GRID_PARAMS, NOISE_PARAMS,
#ifdef EM_TERMS
                            __global float* terms, __global uint* chosen, __global uint* cand_range
#else
                            __global float4* pos_out, __global float4* vel_out
#endif
) {
    const uint i = get_global_id(0);
    if (i >= n) return;
    const float d_rep = radii.x, d_att1 = radii.y, d_att2 = radii.z, rho = radii.w;
    const float accel_time = extra.x, horizon = extra.y, reach = extra.z;
    const int closed = extra.w != 0.0f;
    const float4 p4 = pos[i];
    const float3 p = p4.xyz;
    const float3 vt = vel[i].xyz;
    const uint id = ids[i];

    // Candidates: the agent's speed group and `span` groups on each side.
    const uint g = em_group(em_len(vt), group_min_speed, groups);
    const uint c0 = group_start[g > span ? g - span : 0u];
    const uint c1 = group_start[min(groups, g + span + 1u)];
    const uint nc = c1 - c0;  // <= EM_MAX_CAND (host sizes it)

    // Directions the terms compare v^ with.
    const float3 vt_hat = em_unit(vt);
    const float3 centre_hat = em_unit(centre[0].xyz - p);  // Eq. 7
    float nx, ny, nz;
    NOISE_VELOCITY_S(p.x, p.y, p.z, t, id, step, &nx, &ny, &nz);
    const float3 noise_hat = em_unit((float3)(nx, ny, nz));  // f_N, Eq. 13
    // f_CD (Eq. 15): towards the agent's goal keypoint.
    float3 cd_hat = (float3)(0.0f);
    uint my_goal = 0u;
    if (nkp > 0u) {
        my_goal = goal[id];
        if ((my_goal & ~GOAL_BACKWARD) == GOAL_UNSET) {
            // First step: the nearest keypoint is the first goal (ties: lowest index).
            uint best = 0u;
            float bd = INFINITY;
            for (uint k = 0; k < nkp; ++k) {
                const float d = dist2(kp[k], p4);
                if (d < bd) { bd = d; best = k; }
            }
            my_goal = best | (my_goal & GOAL_BACKWARD);
        }
        cd_hat = em_unit(kp[my_goal & ~GOAL_BACKWARD].xyz - p);
    }
    // In danger (Table 1, escaping): a startling stimulus within d_danger.
    bool danger = false;
    for (uint s = 0; s < nstim; ++s)
        if (stim[2 * s].w != STIM_ATTRACT && dist2(stim[2 * s], p4) < stim[2 * s + 1].x * stim[2 * s + 1].x)
            danger = true;
    const float8 wt = danger ? wd : w;

    // Interaction sums per candidate (Eq. 4, 6), neighbours outer so the grid
    // is walked once: RN = others within d_rep, AN = others with
    // d_att1 <= d <= d_att2 (current positions; the sets do not depend on the
    // candidate).
    float rep[EM_MAX_CAND];
    for (uint c = 0; c < nc; ++c) rep[c] = 0.0f;
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
    const float a_oa = rho / d_att1;
#else
    float oa[EM_MAX_CAND];
    for (uint c = 0; c < nc; ++c) oa[c] = 0.0f;
#endif
    uint nrep = 0u, natt = 0u;
    const Grid grid = GRID_MAKE();
    const float r_search = fmax(d_rep, d_att2);
    GRID_FOR_EACH_CANDIDATE(&grid, p4, r_search, j) {
        if (j == i) continue;
        const float4 pj = pos[j];
        const float d = sqrt(dist2(p4, pj));
        if (d < d_rep) {
            // Predicted positions of both agents (j keeps v_j,t).
            const float3 q = p - (pj.xyz + vel[j].xyz * dt);
            for (uint c = 0; c < nc; ++c)
                rep[c] += exp(rho * (1.0f - em_len(q + dv[c0 + c].xyz * dt) / d_rep));
            ++nrep;
        } else if (d >= d_att1 && d <= d_att2) {
            const float3 q = p - pj.xyz;
#ifdef EM_TAYLOR_OA
            const float f0 = exp(rho * (d / d_att1 - 1.0f));
            const float3 u = q / d;  // d >= d_att1 > 0
            const float k2 = f0 * (0.5f * a_oa * a_oa - 0.5f * a_oa / d);
            s0 += f0;
            s1 += (f0 * a_oa) * u;
            s3 += f0 * 0.5f * a_oa / d;
            sxx += k2 * u.x * u.x; syy += k2 * u.y * u.y; szz += k2 * u.z * u.z;
            sxy += k2 * u.x * u.y; sxz += k2 * u.x * u.z; syz += k2 * u.y * u.z;
#else
            for (uint c = 0; c < nc; ++c)
                oa[c] += exp(rho * (em_len(q + dv[c0 + c].xyz * dt) / d_att1 - 1.0f));
#endif
            ++natt;
        }
    }
    GRID_END_FOR

    float best = INFINITY;
    uint best_c = 0u;
    for (uint c = 0; c < nc; ++c) {
        const float3 v = dv[c0 + c].xyz;
        const float4 vh = dvh[c0 + c], ah = dah[c0 + c];
        const float3 v_hat = vh.xyz;
        float e[EM_TERM_COUNT];
        e[W_REP] = nrep ? wt.s0 * (rep[c] / (float)nrep) : 0.0f;                    // Eq. 4
#ifdef EM_TAYLOR_OA
        const float3 m = v * dt;  // the candidate's displacement
        const float oa_c = s0 + dot(s1, m) + s3 * dot(m, m) +
                           (sxx * m.x * m.x + syy * m.y * m.y + szz * m.z * m.z) +
                           2.0f * (sxy * m.x * m.y + sxz * m.x * m.z + syz * m.y * m.z);
#else
        const float oa_c = oa[c];
#endif
        e[W_OA] = natt ? wt.s1 * (oa_c / (float)natt) : 0.0f;                       // Eq. 6
        e[W_COS] = wt.s2 * exp(rho * em_len(v_hat - centre_hat));                   // Eq. 7
        e[W_DIR] = wt.s3 * exp(rho * em_len(v_hat - vt_hat));                       // Eq. 9
        // Eq. 10 with a' = (v - v_t) / dt in m/s^2 like the dataset's a; the
        // magnitude difference is taken per data frame (times accel_time =
        // the data's frame time), the scale of the paper's a' = v - v_t.
        const float3 a1 = (v - vt) / dt;
        e[W_ACC] = wt.s4 * (exp(rho * em_len(em_unit(a1) - ah.xyz)) + accel_time * fabs(em_len(a1) - ah.w));
        // Eq. 11-12, summed over the stimuli.
        float env = 0.0f;
        for (uint s = 0; s < nstim; ++s) {
            const float4 sp = stim[2 * s];
            if (sp.w == STIM_ATTRACT) {
                env += exp(rho * em_len(v_hat - em_unit(sp.xyz - p)));
            } else {
                const float dd = stim[2 * s + 1].x;
                // Startled only within d_danger; the prediction looks
                // `horizon` seconds ahead (at least one step).
                if (dist2(sp, p4) < dd * dd)
                    env += exp(rho * (1.0f - em_len(p + v * fmax(dt, horizon) - sp.xyz) / dd));
            }
        }
        e[W_ENV] = wt.s5 * env;
        e[W_N] = wt.s6 * exp(rho * em_len(v_hat - noise_hat));                      // Eq. 13
        e[W_USER] = wt.s7 * exp(rho * em_len(v_hat - cd_hat));                      // Eq. 14
        float total = 0.0f;
        for (int k = 0; k < EM_TERM_COUNT; ++k) total += e[k];
#ifdef EM_TERMS
        for (int k = 0; k < EM_TERM_COUNT; ++k)
            terms[((size_t)id * EM_MAX_CAND + c) * EM_TERM_COUNT + k] = e[k];
#endif
        if (total < best) {  // strict: ties keep the lowest sample index
            best = total;
            best_c = c;
        }
    }
#ifdef EM_TERMS
    chosen[id] = c0 + best_c;
    cand_range[2 * id] = c0;
    cand_range[2 * id + 1] = c1;
#else
    const float3 v_new = dv[c0 + best_c].xyz;
    const float3 p_new = p + v_new * dt;  // Eq. 1
    pos_out[i] = (float4)(p_new, 0.0f);
    vel_out[i] = (float4)(v_new, 0.0f);
    // Next keypoint once the goal is reached (§5.1.2), in the agent's direction;
    // open curves turn back at their ends.
    if (nkp > 0u) {
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
        goal[id] = k | back;
    }
#endif
}

// Swarm centre (Eq. 7) without float atomics: chunk c sums slots
// [c * chunk, (c + 1) * chunk) in order, then one work-item sums the chunks
// in order.  Same state, same sum, on every run.
__kernel void energy_centre_partial(__global const float4* pos, uint n, uint chunk, __global float4* partial) {
    const uint c = get_global_id(0);
    const uint b = c * chunk, e = min(n, b + chunk);
    float4 s = (float4)(0.0f);
    for (uint k = b; k < e; ++k) s += (float4)(pos[k].xyz, 1.0f);
    partial[c] = s;
}

__kernel void energy_centre_final(__global const float4* partial, uint chunks, __global float4* centre) {
    if (get_global_id(0) != 0) return;
    float4 s = (float4)(0.0f);
    for (uint c = 0; c < chunks; ++c) s += partial[c];
    centre[0] = s.w > 0.0f ? (float4)(s.xyz / s.w, s.w) : (float4)(0.0f);
}
