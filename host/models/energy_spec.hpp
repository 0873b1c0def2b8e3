// The energy model (FASTSWARM) as a scenario describes it: its parameters and
// where its reference dataset comes from (docs/scenarios.md, docs/energy-model.md).
// The other models' configs are complete in themselves; this one names a
// dataset that is loaded or built when the behavior is (make_behavior).
#pragma once
#include <memory>
#include <string>

#include "data/dataset.hpp"
#include "data/tracks.hpp"
#include "models/energy_model.hpp"

namespace swarmcl {

struct EnergySpec {
    EnergyModelConfig config;
    enum class Source { Synthetic, File, Tracks } source = Source::Synthetic;
    std::string path;              // File: a dataset file; Tracks: a track CSV
    TrackLoadOptions tracks;       // Tracks
    DatasetOptions dataset;        // Synthetic and Tracks: k, groups, seed
    double synthetic_frame_time = 0.01;
    float synthetic_mean_speed = 0.5f;
};

// Loads or builds the dataset (Error(Io/Parse) for a file).
std::shared_ptr<const Dataset> energy_spec_dataset(const EnergySpec& spec);

}  // namespace swarmcl
