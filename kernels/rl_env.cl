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
#ifndef SWCL_INLINE
#define SWCL_INLINE __attribute__((always_inline)) inline
#endif

#define RL_RAYS 42
#define RL_OBS_LOCAL 9

// Rotates unit q towards normalize(q + dq) by at most max_angle (radians):
// Eq. 2's q' = q + ω with Table 1's Δq = 4° clamp.  A zero or opposite target
// keeps q / turns about an arbitrary perpendicular axis.
SWCL_INLINE float3 rl_turn(float3 q, float3 dq, float max_angle) {
    const float3 t0 = q + dq;
    const float len = length(t0);
    if (!(len > 1e-6f)) return q;
    const float3 t = t0 / len;
    const float c = clamp(dot(q, t), -1.0f, 1.0f);
    const float angle = acos(c);
    if (angle <= max_angle) return t;
    float3 w = t - c * q;
    float wl = length(w);
    if (!(wl > 1e-6f)) {
        w = fabs(q.x) < 0.9f ? cross(q, (float3)(1.0f, 0.0f, 0.0f)) : cross(q, (float3)(0.0f, 1.0f, 0.0f));
        wl = length(w);
    }
    w /= wl;
    const float3 r = cos(max_angle) * q + sin(max_angle) * w;
    return r / length(r);
}

// Heading frame: forward f, right r, up u (z up; x up when f is vertical).
SWCL_INLINE void rl_frame(float3 f, float3* r, float3* u) {
    float3 up = (float3)(0.0f, 0.0f, 1.0f);
    if (fabs(f.z) > 0.999f) up = (float3)(1.0f, 0.0f, 0.0f);
    *r = normalize(cross(f, up));
    *u = cross(*r, f);
}

// Ray k (0..41): azimuth -90..90° in 30° steps (7) x elevation -75..75° in
// 30° steps (6), k = 7 * elevation index + azimuth index; every ray lies in
// the heading hemisphere (forward component cos(el) cos(az) >= 0).  The
// table holds (forward, right, up) = (cos el cos az, cos el sin az, sin el).
__constant float rl_ray_table[3 * RL_RAYS] = {
    1.584809576e-17f, -2.588190451e-01f, -9.659258263e-01f,
    1.294095226e-01f, -2.241438680e-01f, -9.659258263e-01f,
    2.241438680e-01f, -1.294095226e-01f, -9.659258263e-01f,
    2.588190451e-01f, 0.000000000e+00f, -9.659258263e-01f,
    2.241438680e-01f, 1.294095226e-01f, -9.659258263e-01f,
    1.294095226e-01f, 2.241438680e-01f, -9.659258263e-01f,
    1.584809576e-17f, 2.588190451e-01f, -9.659258263e-01f,
    4.329780281e-17f, -7.071067812e-01f, -7.071067812e-01f,
    3.535533906e-01f, -6.123724357e-01f, -7.071067812e-01f,
    6.123724357e-01f, -3.535533906e-01f, -7.071067812e-01f,
    7.071067812e-01f, 0.000000000e+00f, -7.071067812e-01f,
    6.123724357e-01f, 3.535533906e-01f, -7.071067812e-01f,
    3.535533906e-01f, 6.123724357e-01f, -7.071067812e-01f,
    4.329780281e-17f, 7.071067812e-01f, -7.071067812e-01f,
    5.914589857e-17f, -9.659258263e-01f, -2.588190451e-01f,
    4.829629131e-01f, -8.365163037e-01f, -2.588190451e-01f,
    8.365163037e-01f, -4.829629131e-01f, -2.588190451e-01f,
    9.659258263e-01f, 0.000000000e+00f, -2.588190451e-01f,
    8.365163037e-01f, 4.829629131e-01f, -2.588190451e-01f,
    4.829629131e-01f, 8.365163037e-01f, -2.588190451e-01f,
    5.914589857e-17f, 9.659258263e-01f, -2.588190451e-01f,
    5.914589857e-17f, -9.659258263e-01f, 2.588190451e-01f,
    4.829629131e-01f, -8.365163037e-01f, 2.588190451e-01f,
    8.365163037e-01f, -4.829629131e-01f, 2.588190451e-01f,
    9.659258263e-01f, 0.000000000e+00f, 2.588190451e-01f,
    8.365163037e-01f, 4.829629131e-01f, 2.588190451e-01f,
    4.829629131e-01f, 8.365163037e-01f, 2.588190451e-01f,
    5.914589857e-17f, 9.659258263e-01f, 2.588190451e-01f,
    4.329780281e-17f, -7.071067812e-01f, 7.071067812e-01f,
    3.535533906e-01f, -6.123724357e-01f, 7.071067812e-01f,
    6.123724357e-01f, -3.535533906e-01f, 7.071067812e-01f,
    7.071067812e-01f, 0.000000000e+00f, 7.071067812e-01f,
    6.123724357e-01f, 3.535533906e-01f, 7.071067812e-01f,
    3.535533906e-01f, 6.123724357e-01f, 7.071067812e-01f,
    4.329780281e-17f, 7.071067812e-01f, 7.071067812e-01f,
    1.584809576e-17f, -2.588190451e-01f, 9.659258263e-01f,
    1.294095226e-01f, -2.241438680e-01f, 9.659258263e-01f,
    2.241438680e-01f, -1.294095226e-01f, 9.659258263e-01f,
    2.588190451e-01f, 0.000000000e+00f, 9.659258263e-01f,
    2.241438680e-01f, 1.294095226e-01f, 9.659258263e-01f,
    1.294095226e-01f, 2.241438680e-01f, 9.659258263e-01f,
    1.584809576e-17f, 2.588190451e-01f, 9.659258263e-01f,
};

SWCL_INLINE float3 rl_ray_dir(int k, float3 f, float3 r, float3 u) {
    return rl_ray_table[3 * k] * f + rl_ray_table[3 * k + 1] * r + rl_ray_table[3 * k + 2] * u;
}

// Signed distance to the nearest axis-aligned box obstacle (centre c, half
// extents h); INFINITY without obstacles.
SWCL_INLINE float rl_sdf(float3 p, __global const float4* box_c, __global const float4* box_h, uint nbox) {
    float best = INFINITY;
    for (uint b = 0; b < nbox; ++b) {
        const float3 d = fabs(p - box_c[b].xyz) - box_h[b].xyz;
        const float outside = length(fmax(d, (float3)(0.0f)));
        const float inside = fmin(fmax(d.x, fmax(d.y, d.z)), 0.0f);
        best = fmin(best, outside + inside);
    }
    return best;
}

// Distance along unit dir from p to the first box obstacle (exact slab
// test; 0 from inside a box), INFINITY when none is hit.  The boxes are
// analytic, so the rays need no sphere tracing of their distance field.
// One axis of the slab test: narrows [t0, t1], or marks a miss.
SWCL_INLINE void rl_slab(float p, float d, float lo, float hi, float* t0, float* t1, int* miss) {
    if (fabs(d) < 1e-12f) {
        if (p < lo || p > hi) *miss = 1;
        return;
    }
    const float ta = (lo - p) / d, tb = (hi - p) / d;
    *t0 = fmax(*t0, fmin(ta, tb));
    *t1 = fmin(*t1, fmax(ta, tb));
}

// Distance along unit dir from p to box (c, h): exact slab test, 0 from
// inside, INFINITY when missed.  The boxes are analytic, so the rays need no
// sphere tracing of their distance field.
SWCL_INLINE float rl_ray_box(float3 p, float3 dir, float4 c, float4 h) {
    float t0 = 0.0f, t1 = INFINITY;
    int miss = 0;
    rl_slab(p.x, dir.x, c.x - h.x, c.x + h.x, &t0, &t1, &miss);
    rl_slab(p.y, dir.y, c.y - h.y, c.y + h.y, &t0, &t1, &miss);
    rl_slab(p.z, dir.z, c.z - h.z, c.z + h.z, &t0, &t1, &miss);
    return (!miss && t0 <= t1) ? t0 : INFINITY;
}

// Eq. 9: the zone of a neighbour at distance d.
SWCL_INLINE float rl_zone(float d, float r_sep, float r_ali) {
    return d <= r_sep ? -1.0f : (d <= r_ali ? 0.0f : 1.0f);
}

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
            if (k >= wp_count) {
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
// The three-zone force over the world's followers within r_coh, plus the
// leader at any distance (its zone by Eq. 9, beyond r_coh counted as
// attraction), v' = v + F Δt, converted to {|v'| - |v|, q' - q} with q' the
// heading of v' turned at most dq_max from q and |v'| - |v| clamped to
// ±du_max: the action the kinematics then executes unchanged.
__kernel void rl_rag(__global const float4* pos, __global const float4* vel, __global const float4* lpos,
                     __global const float4* lvel, uint agents, uint n, float r_sep, float r_ali, float r_coh,
                     float w_sep, float w_ali, float w_coh, float du_max, float dq_max, float dt,
                     __global float* actions) {
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
    o[0] = u;
    o[1] = q.x; o[2] = q.y; o[3] = q.z;
    o[4] = to_l.x; o[5] = to_l.y; o[6] = to_l.z;
    o[7] = dl;
    o[8] = lvel[w].w - u;

    float3 fr, fu;
    rl_frame(q, &fr, &fu);
    // Ray hits are found in the heading frame: each target's offset turned
    // into (forward, right, up) once, then one dot product per ray with the
    // constant table (no trigonometry per target).
    float ray[RL_RAYS];
    for (int k = 0; k < RL_RAYS; ++k) ray[k] = INFINITY;
    const float b2 = body * body;
    float sum_u = 0.0f, sum_q = 0.0f, sum_d = 0.0f, sum_du = 0.0f, sum_dist = 0.0f;
    uint nn = 0;
    const float d_target = prm[10];
    for (uint j = first; j <= first + agents; ++j) {  // j == first + agents: the leader
        if (j == s) continue;
        const bool leader = j == first + agents;
        const float3 d = leader ? to_l : pos[j].xyz - p;
        const float dd = dot(d, d);
        const float dist = sqrt(dd);
        if (!leader && dist <= r_nbr) {
            const float4 vj = vel[j];
            ++nn;
            sum_u += vj.w;
            sum_du += fabs(u - vj.w);
            sum_q += length(vj.xyz - q);
            sum_d += dist;
            const float e = dist - d_target;
            sum_dist += e * e;
        }
        if (dist > r_coh + body) continue;
        if (dd <= b2) {  // inside the target: every ray hits at 0
            for (int k = 0; k < RL_RAYS; ++k) ray[k] = 0.0f;
            continue;
        }
        const float lf = dot(d, q), lr = dot(d, fr), lu = dot(d, fu);
        for (int k = 0; k < RL_RAYS; ++k) {
            const float t = rl_ray_table[3 * k] * lf + rl_ray_table[3 * k + 1] * lr + rl_ray_table[3 * k + 2] * lu;
            const float perp2 = dd - t * t;
            if (t > 0.0f && perp2 < b2) ray[k] = fmin(ray[k], t - sqrt(b2 - perp2));
        }
    }
    // Obstacles: only boxes within r_coh can be hit within r_coh.
    float obst[RL_RAYS];
    for (int k = 0; k < RL_RAYS; ++k) obst[k] = INFINITY;
    for (uint b = 0; b < nbox; ++b) {
        const float4 c = box_c[b], h = box_h[b];
        const float3 e = fabs(p - c.xyz) - h.xyz;
        if (length(fmax(e, (float3)(0.0f))) > r_coh) continue;
        for (int k = 0; k < RL_RAYS; ++k) obst[k] = fmin(obst[k], rl_ray_box(p, rl_ray_dir(k, q, fr, fu), c, h));
    }
    for (int k = 0; k < RL_RAYS; ++k) {
        float val = r_coh;
        if (obst[k] <= r_coh && obst[k] <= ray[k]) val = -obst[k];
        else if (ray[k] <= r_coh) val = ray[k];
        o[RL_OBS_LOCAL + k] = val;
    }
    const float inv = nn ? 1.0f / (float)nn : 0.0f;
    if (efs) {
        o[RL_OBS_LOCAL + RL_RAYS] = sum_u * inv;
        o[RL_OBS_LOCAL + RL_RAYS + 1] = sum_q * inv;
        o[RL_OBS_LOCAL + RL_RAYS + 2] = sum_d * inv;
    }
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
