// Plain C++ references of kernels/rl_env.cl (issue 15): the same formulas,
// one agent at a time, in the same float arithmetic, for the tests.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "rl/leader_env.hpp"

namespace swarmcl::test::rl {

using V3 = std::array<float, 3>;
inline V3 add(V3 a, V3 b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline V3 sub(V3 a, V3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline V3 mul(float s, V3 a) { return {s * a[0], s * a[1], s * a[2]}; }
inline float dot(V3 a, V3 b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline float len(V3 a) { return std::sqrt(dot(a, a)); }
inline V3 cross(V3 a, V3 b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
inline V3 norm(V3 a) { return mul(1.0f / len(a), a); }
constexpr float kInf = std::numeric_limits<float>::infinity();

inline V3 turn(V3 q, V3 dq, float max_angle) {
    const V3 t0 = add(q, dq);
    const float l = len(t0);
    if (!(l > 1e-6f)) return q;
    const V3 t = mul(1.0f / l, t0);
    const float c = std::clamp(dot(q, t), -1.0f, 1.0f);
    if (std::acos(c) <= max_angle) return t;
    V3 w = sub(t, mul(c, q));
    if (!(len(w) > 1e-6f)) w = std::fabs(q[0]) < 0.9f ? cross(q, {1, 0, 0}) : cross(q, {0, 1, 0});
    w = norm(w);
    return norm(add(mul(std::cos(max_angle), q), mul(std::sin(max_angle), w)));
}

inline V3 ray_dir(int k, V3 f) {
    V3 up{0, 0, 1};
    if (std::fabs(f[2]) > 0.999f) up = {1, 0, 0};
    const V3 r = norm(cross(f, up)), u = cross(r, f);
    const float d2r = 0.017453292519943295f;
    const float az = float(k % 7 * 30 - 90) * d2r, el = float(k / 7 * 30 - 75) * d2r;
    return add(add(mul(std::cos(el) * std::cos(az), f), mul(std::cos(el) * std::sin(az), r)), mul(std::sin(el), u));
}

inline float sdf(V3 p, const std::vector<RlObstacleBox>& boxes) {
    float best = kInf;
    for (const auto& b : boxes) {
        V3 d;
        for (int a = 0; a < 3; ++a) d[a] = std::fabs(p[a] - b.center[a]) - b.half[a];
        const V3 o{std::max(d[0], 0.0f), std::max(d[1], 0.0f), std::max(d[2], 0.0f)};
        best = std::min(best, len(o) + std::min(std::max(d[0], std::max(d[1], d[2])), 0.0f));
    }
    return best;
}

// Exact ray / box distance (slab method), 0 inside.
inline float ray_box(V3 p, V3 dir, const RlObstacleBox& b) {
    float t0 = 0, t1 = kInf;
    for (int a = 0; a < 3; ++a) {
        const float lo = b.center[a] - b.half[a], hi = b.center[a] + b.half[a];
        if (std::fabs(dir[a]) < 1e-12f) {
            if (p[a] < lo || p[a] > hi) return kInf;
            continue;
        }
        const float ta = (lo - p[a]) / dir[a], tb = (hi - p[a]) / dir[a];
        t0 = std::max(t0, std::min(ta, tb));
        t1 = std::min(t1, std::max(ta, tb));
    }
    return t0 <= t1 ? t0 : kInf;
}

inline float ray_sphere(V3 d, V3 dir, float rad) {
    const float dd = dot(d, d);
    if (dd <= rad * rad) return 0.0f;
    const float t = dot(d, dir);
    if (t <= 0.0f) return kInf;
    const float perp2 = dd - t * t;
    if (perp2 >= rad * rad) return kInf;
    return t - std::sqrt(rad * rad - perp2);
}

struct State {
    std::vector<std::array<float, 4>> pos, vel, lpos, lvel;  // as LeaderEnv::read_state
};

inline State read_state(LeaderEnv& env) {
    State s;
    const size_t n = size_t(env.worlds()) * env.agents();
    s.pos.resize(n);
    s.vel.resize(n);
    s.lpos.resize(env.worlds());
    s.lvel.resize(env.worlds());
    env.read_state(s.pos[0].data(), s.vel[0].data(), s.lpos[0].data(), s.lvel[0].data());
    return s;
}

inline V3 xyz(const std::array<float, 4>& a) { return {a[0], a[1], a[2]}; }

// Eq. 8-10 for slot s (kernels/rl_env.cl rl_rag), with the leader coupling
// of c.rag_leader_pd: a PD pull of its own (the leader in Eq. 8 only within
// r_sep), or one more Eq. 8 term at any distance.
inline std::array<float, 4> rag(const State& st, const RlEnvConfig& c, size_t s) {
    const size_t N = c.agents, w = s / N, first = w * N;
    const V3 p = xyz(st.pos[s]), q = xyz(st.vel[s]);
    const V3 v = mul(st.vel[s][3], q);
    V3 f[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    int cnt[3] = {0, 0, 0};
    for (size_t j = first; j <= first + N; ++j) {
        const bool leader = j == first + N;
        if (j == s) continue;
        const V3 pj = leader ? xyz(st.lpos[w]) : xyz(st.pos[j]);
        const auto& vj = leader ? st.lvel[w] : st.vel[j];
        const V3 pij = sub(pj, p);
        const float d = len(pij);
        if (!leader && d > c.r_coh) continue;
        if (leader && c.rag_leader_pd && d > c.r_sep) continue;
        if (!(d > 0)) continue;
        const float T = d <= c.r_sep ? -1.0f : (d <= c.r_ali ? 0.0f : 1.0f);
        const V3 vij = sub(mul(vj[3], xyz(vj)), v);
        V3 term = mul(T / d, pij);
        if (len(vij) > 1e-6f) term = add(term, mul((1 - T * T) / len(vij), vij));
        const int z = T < 0 ? 0 : (T == 0 ? 1 : 2);
        f[z] = add(f[z], term);
        ++cnt[z];
    }
    const float wz[3] = {c.rag_w_sep, c.rag_w_ali, c.rag_w_coh};
    V3 F{0, 0, 0};
    for (int z = 0; z < 3; ++z)
        if (cnt[z]) F = add(F, mul(wz[z] / float(cnt[z]), f[z]));
    if (c.rag_leader_pd) {
        const V3 to_l = sub(xyz(st.lpos[w]), p);
        const float dl = len(to_l);
        if (dl > c.r_ali) F = add(F, mul(c.rag_leader_kp * (dl - c.r_ali) / dl, to_l));
        F = add(F, mul(c.rag_leader_kd, sub(mul(st.lvel[w][3], xyz(st.lvel[w])), v)));
    }
    const V3 v1 = add(v, mul(c.dt, F));
    const float u1 = len(v1);
    const float du = std::clamp(u1 - st.vel[s][3], -c.du_max, c.du_max);
    const float dqm = c.dq_max_deg * 0.017453292519943295f;
    const V3 q1 = u1 > 1e-6f ? turn(q, sub(mul(1.0f / u1, v1), q), dqm) : q;
    const V3 dq = sub(q1, q);
    return {du, dq[0], dq[1], dq[2]};
}

// Eq. 11-19 for slot s: the observation row and the reward
// (kernels/rl_env.cl rl_observe), with obstacle rays by the exact slab test.
inline std::vector<float> observe(const State& st, const RlEnvConfig& c, size_t s, float* reward) {
    const size_t N = c.agents, w = s / N, first = w * N;
    const V3 p = xyz(st.pos[s]), q = xyz(st.vel[s]);
    const float u = st.vel[s][3];
    const V3 to_l = sub(xyz(st.lpos[w]), p);
    const float dl = len(to_l);
    std::vector<float> o = {u, q[0], q[1], q[2], to_l[0], to_l[1], to_l[2], dl, st.lvel[w][3] - u};
    const float r_nbr = c.neighbor_radius > 0 ? c.neighbor_radius : c.r_coh;
    const float d_target = c.reward.dist_target > 0 ? c.reward.dist_target : 0.5f * (c.r_ali - c.r_sep);
    double su = 0, sq = 0, sd = 0, sdu = 0, sdist = 0;
    int nn = 0;
    for (int k = 0; k < 42; ++k) {
        const V3 dir = ray_dir(k, q);
        float agent = ray_sphere(to_l, dir, c.body_radius);
        for (size_t j = first; j < first + N; ++j)
            if (j != s) agent = std::min(agent, ray_sphere(sub(xyz(st.pos[j]), p), dir, c.body_radius));
        float obst = kInf;
        for (const auto& b : c.obstacles) obst = std::min(obst, ray_box(p, dir, b));
        float val = c.r_coh;
        if (obst <= c.r_coh && obst <= agent) val = -obst;
        else if (agent <= c.r_coh) val = agent;
        o.push_back(val);
    }
    for (size_t j = first; j < first + N; ++j) {
        if (j == s) continue;
        const float dist = len(sub(xyz(st.pos[j]), p));
        if (dist > r_nbr) continue;
        ++nn;
        su += st.vel[j][3];
        sdu += std::fabs(u - st.vel[j][3]);
        sq += len(sub(xyz(st.vel[j]), q));
        sd += dist;
        sdist += double(dist - d_target) * double(dist - d_target);
    }
    const double inv = nn ? 1.0 / nn : 0.0;
    if (c.efs) {
        o.push_back(float(su * inv));
        o.push_back(float(sq * inv));
        o.push_back(float(sd * inv));
    }
    const RlRewardParams& R = c.reward;
    double r = 0;
    if (nn) {
        r += R.w_spd * std::exp(-R.l_spd * sdu * inv);
        r += R.w_dir * std::exp(-R.l_dir * sq * inv);
        r += R.w_dist - sdist * inv;
    }
    r += R.w_leader * std::exp(-R.l_leader * (dl + c.r_sep));
    if (!c.obstacles.empty()) {
        const float dobs = sdf(p, c.obstacles);
        if (dobs < c.r_coh) r -= R.w_obs * std::exp(-R.l_obs * std::max(dobs - c.r_sep, 0.0f));
    }
    *reward = float(r);
    return o;
}

}  // namespace swarmcl::test::rl
