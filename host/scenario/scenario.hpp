// Scenario files: one JSON description of a run (model and parameters, agents
// and their initial distribution, domain, obstacles, goal, steps, dt, seed,
// outputs), parsed and validated here so C, the CLI and Python share one
// parser.  The format is documented in docs/scenarios.md; each model's
// section is read by its own reader (scenario/model_section.hpp).
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "models/model_spec.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

struct InitialDistribution {
    enum class Kind { Uniform, Sphere, Points } kind = Kind::Uniform;
    std::array<float, 3> min{}, max{};  // uniform box (default: the domain)
    bool min_is_domain = true, max_is_domain = true;  // left out: the domain's (a world's own, make_swarm)
    std::array<float, 3> center{};      // sphere
    float radius = 0.0f;
    std::vector<float> points;          // packed xyz, one per agent
    std::array<float, 3> velocity{};    // every agent's initial velocity
};

struct Scenario {
    std::string name = "scenario";
    SwarmConfig swarm;                    // capacity, agent count, seed, domain, radius, dt
    InitialDistribution initial;
    ModelSpec model;                      // "model" ("type" picks the alternative); none: Ballistic
    uint32_t steps = 100;
    std::string output_dir = "out";
    uint32_t output_formats = 1;          // ExportFormat mask
    uint32_t output_every = 1;
    std::string source;                   // the JSON text as given (for run statistics)

    // Packed xyz initial positions of swarm.agent_count agents (deterministic
    // for the seed: Philox keyed by (seed, agent id)).
    std::vector<float> initial_positions() const;
};

// Parses and validates; Error(Parse) with "line L, column C" for malformed
// JSON and the key path ("model.noise.scale: expected a number > 0") for
// everything else.  Unknown keys are errors.
// OBJ obstacle files are read relative to `base_dir` (load_scenario: the
// scenario file's folder) unless absolute.
Scenario parse_scenario(const std::string& json_text, const std::string& base_dir = "");
Scenario load_scenario(const std::string& path);

}  // namespace swarmcl
