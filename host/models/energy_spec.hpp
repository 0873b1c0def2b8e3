// The "energy" model of scenario files (FASTSWARM, docs/scenarios.md): its
// parameters, where its reference dataset comes from, and building it for a
// swarm.
#pragma once
#include <memory>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "data/dataset.hpp"
#include "data/tracks.hpp"
#include "models/energy_model.hpp"

namespace swarmcl {

struct EnergyScenario {
    EnergyModelConfig config;
    enum class Source { Synthetic, File, Tracks } source = Source::Synthetic;
    std::string path;              // File: a dataset file; Tracks: a track CSV
    TrackLoadOptions tracks;       // Tracks
    DatasetOptions dataset;        // Synthetic and Tracks: k, groups, seed
    double synthetic_frame_time = 0.01;
    float synthetic_mean_speed = 0.5f;
};

// Parses the model object (all keys but "type" and "noise", which the caller
// reads); Error(Parse) naming the key path under `path`.
EnergyScenario read_energy_scenario(const nlohmann::json& model, const std::string& path);

// Loads or builds the dataset (Error(Io/Parse) for a file) and the model.
std::shared_ptr<EnergyModel> make_energy_model(Swarm& swarm, const EnergyScenario& scenario);
std::shared_ptr<const Dataset> energy_scenario_dataset(const EnergyScenario& scenario);

}  // namespace swarmcl
