#include "models/energy_spec.hpp"

namespace swarmcl {

std::shared_ptr<const Dataset> energy_spec_dataset(const EnergySpec& e) {
    switch (e.source) {
        case EnergySpec::Source::File: return std::make_shared<const Dataset>(load_dataset(e.path));
        case EnergySpec::Source::Tracks: {
            const TrackSet set = load_tracks_csv(e.path, e.tracks);
            return std::make_shared<const Dataset>(build_dataset(track_kinematics(set), e.dataset, set.frame_time));
        }
        case EnergySpec::Source::Synthetic: break;
    }
    return std::make_shared<const Dataset>(
        synthetic_dataset(e.dataset, e.synthetic_frame_time, e.synthetic_mean_speed));
}

}  // namespace swarmcl
