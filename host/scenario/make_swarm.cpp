#include "scenario/make_swarm.hpp"

#include <vector>

#include "swarm/behavior.hpp"

namespace swarmcl {

std::shared_ptr<Swarm> make_swarm(std::shared_ptr<Context> ctx, const Scenario& s) {
    SwarmConfig config = s.swarm;
    config.agent_count = 0;  // placed from the scenario's distribution below
    auto swarm = std::make_shared<Swarm>(std::move(ctx), config);
    const auto pos = s.initial_positions();
    const uint32_t n = s.swarm.agent_count;
    swarm->write(Attribute::Position, pos.data(), n);
    std::vector<float> vel(size_t(n) * 3);
    for (size_t i = 0; i < vel.size(); ++i) vel[i] = s.initial.velocity[i % 3];
    swarm->write(Attribute::Velocity, vel.data(), n);
    if (auto behavior = make_behavior(*swarm, s.model)) swarm->set_behavior(std::move(behavior));
    return swarm;
}

}  // namespace swarmcl
