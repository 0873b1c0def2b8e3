// A scenario's swarm: the one place a Scenario becomes a running Swarm, for
// the C API (swcl_scenario_create_swarm, and through it the CLI and Python)
// and the benchmarks.
#pragma once
#include <cstdint>
#include <memory>
#include <vector>

#include "scenario/scenario.hpp"

namespace swarmcl {

class Context;

// A swarm with the scenario's config, its agent_count agents placed from its
// initial distribution (Scenario::initial_positions) moving at its initial
// velocity, and the behavior of its model (make_behavior; none for
// Ballistic).  Error as Swarm and the model's constructor.
std::shared_ptr<Swarm> make_swarm(std::shared_ptr<Context> ctx, const Scenario& scenario);
// The same as `worlds` worlds (SwarmConfig::worlds): world k placed and
// seeded as the scenario alone with seed world_seeds[k] (empty: the
// scenario's seed + k), every world with the scenario's model.  With
// world_domains (empty: the scenario's for every world), world k is the
// scenario alone in domain world_domains[k] (SwarmConfig::world_domains):
// placed there, its grid and noise walls its own.
std::shared_ptr<Swarm> make_swarm(std::shared_ptr<Context> ctx, const Scenario& scenario, uint32_t worlds,
                                  const std::vector<uint64_t>& world_seeds,
                                  const std::vector<Domain>& world_domains = {});

}  // namespace swarmcl
