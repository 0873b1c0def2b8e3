// Small runs of the example scenarios through the C API, one per model type,
// shared by the determinism and thread tests: the agent count lowered, the
// state read back as raw float bytes so runs compare bitwise.
#pragma once
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "swarmcl/swarmcl.h"

namespace swarmcl::test {

// model type -> example scenario (examples/scenarios/) and the agents used.
struct ModelCase {
    const char* model;
    const char* file;
    uint32_t agents;
};
// gtest prints a parameter in the test's listed name: the model, not its bytes.
inline void PrintTo(const ModelCase& c, std::ostream* os) { *os << c.model; }
inline const std::vector<ModelCase>& model_cases() {
    static const std::vector<ModelCase> cases{{"field", "aggregation.json", 48},
                                              {"path", "path_aggregation.json", 48},
                                              {"force", "force_moon_5k.json", 48},
                                              {"energy", "energy_aggregation_37.json", 37},
                                              {"policy", "policy_roaming.json", 48}};
    return cases;
}

// The scenario's JSON with `agents` agents and `steps` steps (output: npy every `every`).
inline std::string scenario_text(const ModelCase& c, uint32_t steps, uint32_t every = 1) {
    std::ifstream in(std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios/" + c.file);
    std::stringstream ss;
    ss << in.rdbuf();
    nlohmann::json j = nlohmann::json::parse(ss.str());
    j["agents"]["count"] = c.agents;
    j["steps"] = steps;
    // A weights file relative to the scenario file, for a text parsed elsewhere.
    if (j.contains("model") && j["model"].value("type", "") == "policy" && j["model"].contains("weights"))
        j["model"]["weights"] = std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios/" +
                                j["model"]["weights"].get<std::string>();
    j["output"]["formats"] = nlohmann::json::array({"npy"});
    j["output"]["every"] = every;
    return j.dump();
}

// Positions then velocities, agent-id order.
struct State {
    std::vector<float> p, v;
    bool operator==(const State& o) const {
        return p.size() == o.p.size() && v.size() == o.v.size() &&
               std::memcmp(p.data(), o.p.data(), p.size() * sizeof(float)) == 0 &&
               std::memcmp(v.data(), o.v.data(), v.size() * sizeof(float)) == 0;
    }
};

// A swarm made from a scenario on `ctx`; returns SWCL_OK or the failing status.
inline swcl_status scenario_swarm(const std::string& text, swcl_context ctx, swcl_swarm* out) {
    swcl_scenario sc;
    swcl_status st = swcl_scenario_parse(text.data(), text.size(), &sc);
    if (st != SWCL_OK) return st;
    st = swcl_scenario_create_swarm(sc, ctx, out);
    swcl_scenario_destroy(sc);
    return st;
}

inline swcl_status read_state(swcl_swarm s, State* out) {
    uint32_t n = 0;
    swcl_status st = swcl_swarm_agent_count(s, &n);
    if (st != SWCL_OK) return st;
    out->p.assign(3u * n, 0.0f);
    out->v.assign(3u * n, 0.0f);
    st = swcl_swarm_read(s, SWCL_ATTRIBUTE_POSITION, out->p.data(), n);
    if (st != SWCL_OK) return st;
    return swcl_swarm_read(s, SWCL_ATTRIBUTE_VELOCITY, out->v.data(), n);
}

// Runs `text` on `ctx` for `steps` steps as one call each of `batch` steps;
// returns the final state (empty on failure, with the status in *status).
inline State run_scenario(const std::string& text, swcl_context ctx, uint32_t steps, uint32_t batch,
                          swcl_status* status) {
    State st;
    swcl_swarm s;
    *status = scenario_swarm(text, ctx, &s);
    if (*status != SWCL_OK) return st;
    for (uint32_t done = 0; done < steps && *status == SWCL_OK; done += batch)
        *status = swcl_swarm_step(s, batch);
    if (*status == SWCL_OK) *status = read_state(s, &st);
    swcl_swarm_destroy(s);
    return st;
}

}  // namespace swarmcl::test
