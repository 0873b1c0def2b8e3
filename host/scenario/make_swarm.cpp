#include "scenario/make_swarm.hpp"

#include <string>
#include <vector>

#include "core/error.hpp"
#include "swarm/behavior.hpp"

namespace swarmcl {

std::shared_ptr<Swarm> make_swarm(std::shared_ptr<Context> ctx, const Scenario& s) {
    return make_swarm(std::move(ctx), s, 1, {});
}

std::shared_ptr<Swarm> make_swarm(std::shared_ptr<Context> ctx, const Scenario& s, uint32_t worlds,
                                  const std::vector<uint64_t>& world_seeds, const std::vector<Domain>& world_domains) {
    SwarmConfig config = s.swarm;
    config.agent_count = 0;  // placed from the scenario's distribution below
    config.worlds = worlds;
    config.world_seeds = world_seeds;
    config.world_domains = world_domains;
    auto swarm = std::make_shared<Swarm>(std::move(ctx), config);
    // World k placed as the scenario alone with its seed (and domain).
    std::vector<float> pos;
    for (uint32_t k = 0; k < worlds; ++k) {
        Scenario world = s;
        world.swarm.seed = swarm->world_seed(k);
        world.swarm.domain_min = swarm->world_domain(k).min;
        world.swarm.domain_max = swarm->world_domain(k).max;
        if (world.initial.min_is_domain) world.initial.min = world.swarm.domain_min;
        if (world.initial.max_is_domain) world.initial.max = world.swarm.domain_max;
        for (int a = 0; a < 3; ++a)
            if (!(world.initial.min[a] <= world.initial.max[a]))
                fail(Status::InvalidArgument, "world " + std::to_string(k) + ": agents.initial.min[" +
                                                  std::to_string(a) + "] (" + std::to_string(world.initial.min[a]) +
                                                  ") exceeds agents.initial.max (" +
                                                  std::to_string(world.initial.max[a]) +
                                                  ") in the world's domain; nothing was created");
        const auto p = world.initial_positions();
        pos.insert(pos.end(), p.begin(), p.end());
    }
    const size_t n = size_t(s.swarm.agent_count) * worlds;
    swarm->write(Attribute::Position, pos.data(), n);
    std::vector<float> vel(n * 3);
    for (size_t i = 0; i < vel.size(); ++i) vel[i] = s.initial.velocity[i % 3];
    swarm->write(Attribute::Velocity, vel.data(), n);
    if (auto behavior = make_behavior(*swarm, s.model)) swarm->set_behavior(std::move(behavior));
    return swarm;
}

}  // namespace swarmcl
