// Plain C++ reference of the FASTSWARM energy (Eq. 4-14) for one agent and
// one candidate, in double, with brute-force neighbour sets: what
// kernels/energy_model.cl must reproduce.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "data/dataset.hpp"
#include "models/energy_model.hpp"

namespace swarmcl::test {

using V3 = std::array<double, 3>;

inline V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline V3 add(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline V3 mul(const V3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
inline double len(const V3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }
inline V3 unit(const V3& a) {
    const double l = len(a);
    return l > 0.0 ? mul(a, 1.0 / l) : V3{0, 0, 0};
}
inline V3 v3(const float* p) { return {p[0], p[1], p[2]}; }
inline V3 v3(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }

struct ReferenceState {
    std::vector<float> pos, vel;      // packed xyz by agent id
    std::vector<float> noise;         // noise velocity at each agent, packed xyz
    V3 centre{};
    std::vector<std::array<float, 3>> stimuli_pos;  // at the step's time
    std::vector<int> goal;            // per agent: goal keypoint index (-1: none)
    float dt = 0.01f;
    float accel_time = 0.01f;
};

// The candidate range of agent `a` (speed group +- span), as the kernel picks it.
inline std::array<uint32_t, 2> reference_candidates(const Dataset& d, uint32_t span, const float* v) {
    auto speed = [](const float* x) { return std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]); };
    const uint32_t G = d.groups();
    uint32_t g = 0;
    for (uint32_t k = 1; k < G; ++k)
        if (speed(d.v[d.group_start[k]].data()) <= speed(v)) g = k;
    return {d.group_start[g > span ? g - span : 0u], d.group_start[std::min(G, g + span + 1)]};
}

// Eq. 12 over the horizon: the closest approach within max(dt, horizon) of
// an agent at p moving at v and stimulus k moving on at its velocity.
inline double reference_closest(const EnergyModelConfig& cfg, const ReferenceState& s, size_t k, const V3& p,
                                const V3& v) {
    const double h = std::max<double>(s.dt, cfg.danger_horizon);
    const V3 r0 = sub(p, v3(s.stimuli_pos[k])), u = sub(v, v3(cfg.stimuli[k].velocity));
    const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    const double tau = uu > 0 ? std::clamp(-(r0[0] * u[0] + r0[1] * u[1] + r0[2] * u[2]) / uu, 0.0, h) : 0.0;
    return len(add(r0, mul(u, tau)));
}

// Keep-out (EnergyModelConfig::keep_out): how far candidate c of agent a
// would enter a startling stimulus' d_danger, relative to it (0: not at all).
inline double reference_violation(const EnergyModelConfig& cfg, const Dataset& d, const ReferenceState& s,
                                  uint32_t a, uint32_t c) {
    double viol = 0;
    if (!cfg.keep_out) return viol;
    for (size_t k = 0; k < cfg.stimuli.size(); ++k)
        if (cfg.stimuli[k].kind == Stimulus::Kind::Startle)
            viol = std::max(viol, 1.0 - reference_closest(cfg, s, k, v3(&s.pos[3 * a]), v3(d.v[c])) /
                                            cfg.stimuli[k].d_danger);
    return viol;
}

// Agent a is in danger (Table 1, escaping): a startling stimulus comes
// within its d_danger within the horizon at the agent's velocity.
inline bool reference_in_danger(const EnergyModelConfig& cfg, const ReferenceState& s, uint32_t a) {
    const V3 p = v3(&s.pos[3 * a]), vt = v3(&s.vel[3 * a]);
    for (size_t k = 0; k < cfg.stimuli.size(); ++k)
        if (cfg.stimuli[k].kind == Stimulus::Kind::Startle &&
            reference_closest(cfg, s, k, p, vt) < cfg.stimuli[k].d_danger)
            return true;
    return false;
}

// The eight terms of candidate c for agent a.
inline std::array<double, 8> reference_terms(const EnergyModelConfig& cfg, const Dataset& d,
                                             const ReferenceState& s, uint32_t a, uint32_t c) {
    const size_t n = s.pos.size() / 3;
    const V3 p = v3(&s.pos[3 * a]), vt = v3(&s.vel[3 * a]);
    const V3 v = v3(d.v[c]), acc = v3(d.a[c]);
    const double dt = s.dt, rho = cfg.rho;
    const EnergyWeights& w = reference_in_danger(cfg, s, a) ? cfg.danger_weights : cfg.weights;
    const V3 vh = unit(v);
    std::array<double, 8> e{};
    // Eq. 4 and 6 over brute-force neighbour sets (distances in float, as the
    // kernel classifies them).
    double rep = 0, oa = 0;
    int nrep = 0, natt = 0;
    const V3 pi1 = add(p, mul(v, dt));
    for (size_t j = 0; j < n; ++j) {
        if (j == a) continue;
        const float dx = s.pos[3 * a] - s.pos[3 * j], dy = s.pos[3 * a + 1] - s.pos[3 * j + 1],
                    dz = s.pos[3 * a + 2] - s.pos[3 * j + 2];
        const float df = std::sqrt(dx * dx + dy * dy + dz * dz);
        const V3 pj = v3(&s.pos[3 * j]);
        if (df < cfg.d_rep) {
            const V3 pj1 = add(pj, mul(v3(&s.vel[3 * j]), dt));
            rep += std::exp(rho * (1.0 - len(sub(pi1, pj1)) / cfg.d_rep));
            ++nrep;
        } else if (df >= cfg.d_att1 && df <= cfg.d_att2) {
            oa += std::exp(rho * (len(sub(pi1, pj)) / cfg.d_att1 - 1.0));
            ++natt;
        }
    }
    e[0] = nrep ? w.rep * rep / nrep : 0.0;
    e[1] = natt ? w.oa * oa / natt : 0.0;
    e[2] = w.cos * std::exp(rho * len(sub(vh, unit(sub(s.centre, p)))));  // Eq. 7
    e[3] = w.dir * std::exp(rho * len(sub(vh, unit(vt))));                // Eq. 9
    const V3 a1 = mul(sub(v, vt), 1.0 / dt);                              // Eq. 10
    e[4] = w.acc * (std::exp(rho * len(sub(unit(a1), unit(acc)))) + s.accel_time * std::fabs(len(a1) - len(acc)));
    double env = 0;                                                        // Eq. 11-12
    for (size_t k = 0; k < cfg.stimuli.size(); ++k) {
        const V3 sp = v3(s.stimuli_pos[k]);
        if (cfg.stimuli[k].kind == Stimulus::Kind::Attract) {
            env += std::exp(rho * len(sub(vh, unit(sub(sp, p)))));
        } else if (reference_closest(cfg, s, k, p, vt) < cfg.stimuli[k].d_danger) {
            env += std::exp(rho * (1.0 - reference_closest(cfg, s, k, p, v) / cfg.stimuli[k].d_danger));
        }
    }
    e[5] = w.env * env;
    e[6] = w.n * std::exp(rho * len(sub(vh, unit(v3(&s.noise[3 * a])))));  // Eq. 13
    V3 cd{0, 0, 0};
    if (s.goal[a] >= 0) cd = unit(sub(v3(cfg.keypoints[size_t(s.goal[a])]), p));
    e[7] = w.user * std::exp(rho * len(sub(vh, cd)));                      // Eq. 14
    return e;
}

}  // namespace swarmcl::test
