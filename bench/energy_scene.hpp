// energy_bench's scene, shared with kernel_ab's energy stage: N agents in a
// ball whose radius grows as N^(1/3) (the density of the paper's 300-agent
// scenario), grid cells of `cell` m, and the aggregation model
// (Table 1 weights, a fixed centre) on a synthetic dataset.
#pragma once
#include <cmath>
#include <memory>
#include <vector>

#include "core/philox.hpp"
#include "data/dataset.hpp"
#include "device/context.hpp"
#include "models/energy_model.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl::bench {

inline float energy_ball_radius(uint32_t n) { return 0.5f * std::cbrt(float(n) / 300.0f); }

inline std::shared_ptr<Swarm> energy_ball_swarm(const std::shared_ptr<Context>& ctx, uint32_t n, float cell) {
    const float r = energy_ball_radius(n);
    SwarmConfig c;
    c.capacity = n;
    c.seed = 4;
    c.dt = 0.01f;
    c.interaction_radius = cell;
    for (int a = 0; a < 3; ++a) c.domain_min[a] = -r - 0.5f, c.domain_max[a] = r + 0.5f;
    auto s = std::make_shared<Swarm>(ctx, c);
    std::vector<float> p(3 * size_t(n));
    for (uint32_t id = 0; id < n; ++id) {
        const auto u = philox_for(7, id, 0, 0);
        const float cz = 2 * uniform01(u[0]) - 1, phi = 6.2831853f * uniform01(u[1]);
        const float sz = std::sqrt(std::max(0.0f, 1 - cz * cz)), rad = r * std::cbrt(uniform01(u[2]));
        p[3 * id] = rad * sz * std::cos(phi);
        p[3 * id + 1] = rad * sz * std::sin(phi);
        p[3 * id + 2] = rad * cz;
    }
    s->write(Attribute::Position, p.data(), n);
    return s;
}

// Table 1's aggregation weights (rho = 2.5) about a fixed centre.
inline EnergyModelConfig energy_aggregation_config(bool exact_attraction) {
    EnergyModelConfig cfg;
    cfg.has_fixed_centre = true;
    cfg.exact_attraction = exact_attraction;
    return cfg;
}

}  // namespace swarmcl::bench
