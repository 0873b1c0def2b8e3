// policy_bench's scene, shared with kernel_ab's policy stage: N agents placed
// uniformly at the density of a 200-agent swarm in a ball of radius 15
// (~0.014 per m^3: ~340 within r_coh + body = 18.5 m of each), headings
// random, speed 1, in a cube whose edge grows as N^(1/3); grid cells of
// `cell` m; the shipped policy drives them (the leader in the middle).
#pragma once
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "device/context.hpp"
#include "models/policy_model.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl::bench {

constexpr double kPolicyDensity = 200.0 / (4.0 / 3.0 * 3.14159265 * 15.0 * 15.0 * 15.0);
constexpr float kPolicyCell = 6.17f;  // (r_coh + body) / 3

inline std::shared_ptr<Swarm> policy_random_swarm(const std::shared_ptr<Context>& ctx, uint32_t n, float cell) {
    const float half = float(0.5 * std::cbrt(double(n) / kPolicyDensity));
    SwarmConfig sc;
    sc.capacity = n;
    sc.agent_count = 0;
    sc.domain_min = {-half, -half, -half};
    sc.domain_max = {half, half, half};
    sc.interaction_radius = cell;
    sc.dt = 0.1f;
    auto swarm = std::make_shared<Swarm>(ctx, sc);
    std::mt19937 rng(1);
    std::uniform_real_distribution<float> u(-half, half);
    std::normal_distribution<float> g(0.0f, 1.0f);
    std::vector<float> p(3 * size_t(n)), v(3 * size_t(n));
    for (uint32_t a = 0; a < n; ++a) {
        float d[3] = {g(rng), g(rng), g(rng)};
        const float l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3; ++k) {
            p[3 * size_t(a) + k] = u(rng);
            v[3 * size_t(a) + k] = d[k] / l;
        }
    }
    swarm->write(Attribute::Position, p.data(), n);
    swarm->write(Attribute::Velocity, v.data(), n);
    return swarm;
}

// The model with the leader at speed 1 (set as the swarm's behaviour).
inline std::shared_ptr<PolicyModel> policy_model_on(Swarm& swarm, const std::shared_ptr<const std::string>& bytes) {
    PolicyModelConfig pc;
    pc.leader_speed = 1.0f;
    auto model = std::make_shared<PolicyModel>(swarm, pc, bytes);
    swarm.set_behavior(model);
    return model;
}

}  // namespace swarmcl::bench
