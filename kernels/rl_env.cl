// The leader-following RL environment (issue 15; paper
// drl-swarm-animation-rule-based-action-generator, §III): W independent
// worlds of N followers and one leader each.  Agent slot s = w * N + k; a
// world's followers are contiguous, so the neighbour loops below visit only
// their own world (worlds never see each other).  docs/rl-swarm.md has the
// layouts and every choice the paper leaves open.
//
// State: pos[s] = (x, y, z, 0); vel[s] = (q.x, q.y, q.z, u) with q the unit
// heading and u the speed; the same for the leaders (lpos[w], lvel[w]).
#pragma OPENCL FP_CONTRACT OFF
#include "lib/rl_common.cl"

// ---- kinematics (§III-B, Eq. 2) ----------------------------------------------
// actions[4 s ..]: {v, ω.x, ω.y, ω.z}; v clamped to ±du_max, the turn to
// dq_max; the speed kept in [0, u_max]; then p += u q Δt.
__kernel void rl_agents_step(__global float4* pos, __global float4* vel, __global const float* actions, uint n,
                             float du_max, float dq_max, float u_max, float dt) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const float4 v = vel[s];
    const float du = clamp(actions[4 * s], -du_max, du_max);
    const float3 dq = (float3)(actions[4 * s + 1], actions[4 * s + 2], actions[4 * s + 3]);
    const float u = clamp(v.w + du, 0.0f, u_max);
    const float3 q = rl_turn(v.xyz, dq, dq_max);
    vel[s] = (float4)(q, u);
    pos[s] = (float4)(pos[s].xyz + (u * dt) * q, 0.0f);
}

// ---- the leader (§III-B Eq. 1, §IV-A2) ----------------------------------------
// mode 0 (joystick): ctl[w] = {Δu, Δq.xyz} applied like an action (Eq. 1 with
// h = one step).  mode 1 (navigation): waypoints[k] = (x, y, z, target
// speed); the leader turns towards waypoint wp[w] and its speed towards that
// waypoint's target speed, both within the leader's clamps; within `reach`
// of it, the next one; after the last, done[w] = 1 and the leader stops.
// mode 2: navigation that starts over at waypoint 0 after the last.
__kernel void rl_leader_step(__global float4* lpos, __global float4* lvel, __global const float4* ctl, uint worlds,
                             int mode, __global const float4* waypoints, uint wp_count, __global uint* wp,
                             __global uint* done, float reach, float du_max, float dq_max, float u_max, float dt) {
    const uint w = get_global_id(0);
    if (w >= worlds) return;
    float4 v = lvel[w];
    float3 p = lpos[w].xyz;
    float du;
    float3 dq;
    if (mode == 0) {
        du = ctl[w].x;
        dq = ctl[w].yzw;
    } else {
        if (done[w]) {
            lvel[w] = (float4)(v.xyz, 0.0f);
            return;
        }
        uint k = wp[w];
        float3 to = waypoints[k].xyz - p;
        if (length(to) <= reach) {
            ++k;
            wp[w] = k;
            if (k >= wp_count && mode == 2) {  // a closed tour (the policy model's leader)
                k = 0;
                wp[w] = 0;
            } else if (k >= wp_count) {
                done[w] = 1u;
                lvel[w] = (float4)(v.xyz, 0.0f);
                return;
            }
            to = waypoints[k].xyz - p;
        }
        const float tl = length(to);
        dq = tl > 1e-6f ? to / tl - v.xyz : (float3)(0.0f);
        du = waypoints[k].w - v.w;
    }
    du = clamp(du, -du_max, du_max);
    const float u = clamp(v.w + du, 0.0f, u_max);
    const float3 q = rl_turn(v.xyz, dq, dq_max);
    lvel[w] = (float4)(q, u);
    lpos[w] = (float4)(p + (u * dt) * q, 0.0f);
}

// ---- rule-based action generator (§III-C3, Eq. 8-10) ---------------------------
// The three-zone force over the world's followers within r_coh; v' = v + F Δt,
// converted to {|v'| - |v|, q' - q} with q' the heading of v' turned at most
// dq_max from q and |v'| - |v| clamped to ±du_max: the action the kinematics
// then executes unchanged.
// The leader (the paper does not say how its RAG follows it; docs/rl-swarm.md):
// leader_pd != 0 (ours, the default): a proportional-derivative pull of its
// own, F += k_p max(|p_L - p| - r_ali, 0) (p_L - p)/|p_L - p| + k_d (v_L - v),
// at any distance, and the leader counts in Eq. 8's sums only within r_sep
// (separation); leader_pd == 0: the leader is one more Eq. 8 term at any
// distance (its zone by Eq. 9, beyond r_coh counted as attraction), the
// coupling that surges and brakes around r_ali.
__kernel void rl_rag(__global const float4* pos, __global const float4* vel, __global const float4* lpos,
                     __global const float4* lvel, uint agents, uint n, float r_sep, float r_ali, float r_coh,
                     float w_sep, float w_ali, float w_coh, float du_max, float dq_max, float dt, int leader_pd,
                     float k_p, float k_d, __global float* actions) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const uint w = s / agents;
    const uint first = w * agents;
    const float3 p = pos[s].xyz;
    const float4 vs = vel[s];
    const float3 v = vs.w * vs.xyz;
    float3 f_sep = (float3)(0.0f), f_ali = (float3)(0.0f), f_coh = (float3)(0.0f);
    uint n_sep = 0, n_ali = 0, n_coh = 0;
    for (uint j = first; j <= first + agents; ++j) {  // j == first + agents: the leader
        const bool leader = j == first + agents;
        if (j == s) continue;
        const float3 pj = leader ? lpos[w].xyz : pos[j].xyz;
        const float4 vj4 = leader ? lvel[w] : vel[j];
        const float3 pij = pj - p;
        const float d = length(pij);
        if (!leader && d > r_coh) continue;
        if (leader && leader_pd && d > r_sep) continue;
        if (!(d > 0.0f)) continue;
        const float T = rl_zone(d, r_sep, r_ali);
        const float3 vij = vj4.w * vj4.xyz - v;
        const float vl = length(vij);
        float3 term = T * (pij / d);
        if (vl > 1e-6f) term += (1.0f - T * T) * (vij / vl);
        if (T < 0.0f) { f_sep += term; ++n_sep; }
        else if (T == 0.0f) { f_ali += term; ++n_ali; }
        else { f_coh += term; ++n_coh; }
    }
    float3 F = (float3)(0.0f);
    if (n_sep) F += (w_sep / (float)n_sep) * f_sep;
    if (n_ali) F += (w_ali / (float)n_ali) * f_ali;
    if (n_coh) F += (w_coh / (float)n_coh) * f_coh;
    if (leader_pd) {
        const float3 to_l = lpos[w].xyz - p;
        const float dl = length(to_l);
        if (dl > r_ali) F += (k_p * (dl - r_ali) / dl) * to_l;
        F += k_d * (lvel[w].w * lvel[w].xyz - v);
    }
    const float3 v1 = v + dt * F;
    const float u1 = length(v1);
    const float du = clamp(u1 - vs.w, -du_max, du_max);
    const float3 q1 = u1 > 1e-6f ? rl_turn(vs.xyz, v1 / u1 - vs.xyz, dq_max) : vs.xyz;
    const float3 dq = q1 - vs.xyz;
    actions[4 * s] = du;
    actions[4 * s + 1] = dq.x;
    actions[4 * s + 2] = dq.y;
    actions[4 * s + 3] = dq.z;
}

// ---- observations (Eq. 11-13) and rewards (Eq. 14-19) ---------------------------
// obs[s * obs_dim ..]: 0 u, 1-3 q, 4-6 p_leader - p, 7 |p_leader - p|,
// 8 u_leader - u, 9-50 rays (rl_ray_dir order: distance to the first agent,
// leader included, of radius body; minus the distance to the first obstacle;
// r_coh when nothing is hit), 51-53 EFS (Eq. 12; 0 without neighbours;
// absent when efs == 0, obs_dim 51).  Neighbours: the world's other
// followers within r_nbr.  prm: the reward weights and rates (RlRewardParams
// order, host/rl/leader_env.hpp).
__kernel void rl_observe(__global const float4* pos, __global const float4* vel, __global const float4* lpos,
                         __global const float4* lvel, uint agents, uint n, float r_sep, float r_ali, float r_coh,
                         float r_nbr, float body, __global const float4* box_c, __global const float4* box_h,
                         uint nbox, int efs, uint obs_dim, __constant float* prm, __global float* obs,
                         __global float* rewards) {
    const uint s = get_global_id(0);
    if (s >= n) return;
    const uint w = s / agents;
    const uint first = w * agents;
    const float3 p = pos[s].xyz;
    const float4 vs = vel[s];
    const float3 q = vs.xyz;
    const float u = vs.w;
    const float3 lp = lpos[w].xyz;
    __global float* o = obs + (size_t)s * obs_dim;
    const float3 to_l = lp - p;
    const float dl = length(to_l);
    rl_obs_local(o, p, q, u, lp, lvel[w].w);

    float3 fr, fu;
    rl_frame(q, &fr, &fu);
    RlObsAcc acc;
    rl_obs_begin(&acc);
    const float d_target = prm[10];
    for (uint j = first; j <= first + agents; ++j) {  // j == first + agents: the leader
        if (j == s) continue;
        const bool leader = j == first + agents;
        rl_obs_target(&acc, leader ? to_l : pos[j].xyz - p, !leader, leader ? (float4)(0.0f) : vel[j], q, u, fr,
                      fu, r_nbr, r_coh, body, d_target, 0);
    }
    rl_obs_finish(&acc, o, p, q, fr, fu, r_coh, box_c, box_h, nbox, efs);
    const uint nn = acc.nn;
    const float sum_du = acc.sum_du, sum_q = acc.sum_q, sum_dist = acc.sum_dist;
    const float inv = nn ? 1.0f / (float)nn : 0.0f;
    // Rewards: prm = {w_spd, w_dir, w_leader, w_obs, w_dist,
    //                 l_spd, l_dir, l_leader, l_obs, (unused), d_target}.
    float r = 0.0f;
    if (nn) {
        r += prm[0] * exp(-prm[5] * sum_du * inv);                 // Eq. 15
        r += prm[1] * exp(-prm[6] * sum_q * inv);                  // Eq. 16
        r += prm[4] - sum_dist * inv;                              // Eq. 19 (r_dist)
    }
    r += prm[2] * exp(-prm[7] * (dl + r_sep));                     // Eq. 17
    if (nbox) {                                                    // Eq. 18 as read in docs/rl-swarm.md
        const float dobs = rl_sdf(p, box_c, box_h, nbox);
        if (dobs < r_coh) r -= prm[3] * exp(-prm[8] * fmax(dobs - r_sep, 0.0f));
    }
    rewards[s] = r;
}
