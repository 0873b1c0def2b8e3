// The leader-following environment's per-agent geometry (paper
// drl-swarm-animation-rule-based-action-generator, §III; docs/rl-swarm.md),
// shared by the batched environment (kernels/rl_env.cl: per-world all-pairs
// loops) and the policy model (kernels/policy.cl: the swarm's neighbour
// grid): Eq. 2's turn, the heading frame, the 42 rays, the box obstacles,
// Eq. 9's zones, and the observation of Eq. 11-13 accumulated one target at
// a time, so both loops compute the same values with the same code.
#ifndef SWCL_RL_COMMON_CL
#define SWCL_RL_COMMON_CL
#pragma OPENCL FP_CONTRACT OFF
#include "lib/inline.cl"

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

// ---- observations (Eq. 11-13), one target at a time ------------------------------
// What the neighbour loop gathers for one agent: the nearest agent hit per
// ray (INFINITY: none), and the neighbour sums of Eq. 12 and of the rewards.
typedef struct {
    float ray[RL_RAYS];
    float sum_u, sum_q, sum_d, sum_du, sum_dist;
    uint nn;
} RlObsAcc;

SWCL_INLINE void rl_obs_begin(RlObsAcc* a) {
    for (int k = 0; k < RL_RAYS; ++k) a->ray[k] = INFINITY;
    a->sum_u = a->sum_q = a->sum_d = a->sum_du = a->sum_dist = 0.0f;
    a->nn = 0;
}

// cos and sin of the rays' six elevations (-75, -45, ..., 75 degrees).
__constant float rl_row_cos[6] = {2.588190451e-01f, 7.071067812e-01f, 9.659258263e-01f,
                                  9.659258263e-01f, 7.071067812e-01f, 2.588190451e-01f};
__constant float rl_row_sin[6] = {-9.659258263e-01f, -7.071067812e-01f, -2.588190451e-01f,
                                  2.588190451e-01f, 7.071067812e-01f, 9.659258263e-01f};

// One target at offset d from the agent (heading q, frame fr/fu, speed u):
// a follower (vj = its (q, u)) within r_nbr is a neighbour (Eq. 12 and the
// rewards' sums); any target (followers and the leader, spheres of radius
// body) within r_coh + body may be hit by the rays.
SWCL_INLINE void rl_obs_target(RlObsAcc* a, float3 d, int follower, float4 vj, float3 q, float u, float3 fr,
                               float3 fu, float r_nbr, float r_coh, float body, float d_target, int cull) {
    const float dd = dot(d, d);
    const float dist = sqrt(dd);
    if (follower && dist <= r_nbr) {
        ++a->nn;
        a->sum_u += vj.w;
        a->sum_du += fabs(u - vj.w);
        a->sum_q += length(vj.xyz - q);
        a->sum_d += dist;
        const float e = dist - d_target;
        a->sum_dist += e * e;
    }
    if (dist > r_coh + body) return;
    const float b2 = body * body;
    if (dd <= b2) {  // inside the target: every ray hits at 0
        for (int k = 0; k < RL_RAYS; ++k) a->ray[k] = 0.0f;
        return;
    }
    // Ray hits are found in the heading frame: the target's offset turned
    // into (forward, right, up) once, then one dot product per ray with the
    // constant table (no trigonometry per target).
    const float lf = dot(d, q), lr = dot(d, fr), lu = dot(d, fu);
    if (!cull) {
        for (int k = 0; k < RL_RAYS; ++k) {
            const float t = rl_ray_table[3 * k] * lf + rl_ray_table[3 * k + 1] * lr + rl_ray_table[3 * k + 2] * lu;
            const float perp2 = dd - t * t;
            if (t > 0.0f && perp2 < b2) a->ray[k] = fmin(a->ray[k], t - sqrt(b2 - perp2));
        }
        return;
    }
    // cull: a ray of elevation row e (up component sin e) has t <= cos(e) h
    // + sin(e) lu with h = |(lf, lr)|; a row whose bound is below
    // sqrt(dd - b2) (with a margin far above float rounding) holds no hit
    // and is skipped.  Every ray visited is decided by the same test, so the
    // hits are the same; most targets reach one row or none.  (Worth it where
    // the loop is scalar, as over the grid; the environment's per-world loop
    // is vectorised across work-items and runs it without.)
    const float h = sqrt(lf * lf + lr * lr);
    const float need = (dd - b2) - 1e-5f * dd;
    for (int e = 0; e < RL_RAYS / 7; ++e) {
        const float bound = rl_row_cos[e] * h + rl_row_sin[e] * lu;
        if (bound <= 0.0f || bound * bound < need) continue;
        for (int k = 7 * e; k < 7 * e + 7; ++k) {
            const float t = rl_ray_table[3 * k] * lf + rl_ray_table[3 * k + 1] * lr + rl_ray_table[3 * k + 2] * lu;
            const float perp2 = dd - t * t;
            if (t > 0.0f && perp2 < b2) a->ray[k] = fmin(a->ray[k], t - sqrt(b2 - perp2));
        }
    }
}

// Writes observation entries 0-8 (the agent and the leader).
SWCL_INLINE void rl_obs_local(__global float* o, float3 p, float3 q, float u, float3 lp, float lu) {
    const float3 to_l = lp - p;
    o[0] = u;
    o[1] = q.x; o[2] = q.y; o[3] = q.z;
    o[4] = to_l.x; o[5] = to_l.y; o[6] = to_l.z;
    o[7] = length(to_l);
    o[8] = lu - u;
}

// Writes the rays (9-50: the obstacles' hits, negated, win over farther
// agents; r_coh when nothing is hit within it) and, with efs, Eq. 12's means
// (51-53; 0 without neighbours).
SWCL_INLINE void rl_obs_finish(const RlObsAcc* a, __global float* o, float3 p, float3 q, float3 fr, float3 fu,
                               float r_coh, __global const float4* box_c, __global const float4* box_h, uint nbox,
                               int efs) {
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
        if (obst[k] <= r_coh && obst[k] <= a->ray[k]) val = -obst[k];
        else if (a->ray[k] <= r_coh) val = a->ray[k];
        o[RL_OBS_LOCAL + k] = val;
    }
    if (efs) {
        const float inv = a->nn ? 1.0f / (float)a->nn : 0.0f;
        o[RL_OBS_LOCAL + RL_RAYS] = a->sum_u * inv;
        o[RL_OBS_LOCAL + RL_RAYS + 1] = a->sum_q * inv;
        o[RL_OBS_LOCAL + RL_RAYS + 2] = a->sum_d * inv;
    }
}

#endif
