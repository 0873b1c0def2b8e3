#include "scenario/synthesis.hpp"

#include <string>
#include <vector>

#include "core/error.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

void start_from_tracks(Swarm& swarm, const TrackSet& tracks) {
    // The last segment of each id (segments of one id are in time order).
    std::vector<const Track*> last;
    std::vector<std::string> ids;
    for (const Track& t : tracks.tracks) {
        size_t k = 0;
        while (k < ids.size() && ids[k] != t.id) ++k;
        if (k == ids.size()) {
            ids.push_back(t.id);
            last.push_back(&t);
        } else {
            last[k] = &t;
        }
    }
    require(last.size() <= swarm.config().capacity,
            "start_from_tracks: " + std::to_string(last.size()) + " tracks exceed the swarm's capacity " +
                std::to_string(swarm.config().capacity));
    std::vector<float> pos, vel;
    for (const Track* t : last) {
        const size_t n = t->t.size();  // >= 3 (TrackSet segments)
        const double dt = t->t[n - 1] - t->t[n - 2];
        for (int a = 0; a < 3; ++a) {
            pos.push_back(float(t->p[n - 1][a]));
            vel.push_back(float((t->p[n - 1][a] - t->p[n - 2][a]) / dt));
        }
    }
    swarm.write(Attribute::Position, pos.data(), last.size());
    swarm.write(Attribute::Velocity, vel.data(), last.size());
}

}  // namespace swarmcl
