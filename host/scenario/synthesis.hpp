// Trajectory synthesis (FASTSWARM §5.2.3): simulated agents continue real
// track segments.  The mixing of real and simulated trajectories into one
// file is in bindings/python/swarmcl/energy.py (write_mixed_csv).
#pragma once
#include "data/tracks.hpp"

namespace swarmcl {

class Swarm;

// Places one agent per source track (agent k: the k-th track id in order of
// first appearance) at the last sample of its last gap-free segment, moving
// with that segment's last forward-difference velocity.  Sets the agent
// count; Error(InvalidArgument) when there are more tracks than the swarm's
// capacity.
void start_from_tracks(Swarm& swarm, const TrackSet& tracks);

}  // namespace swarmcl
