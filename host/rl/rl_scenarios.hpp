// The paper's navigation scenarios (§IV-A3, Fig. 7) as data: the leader's
// waypoints (x, y, z, target speed) and box obstacles.  Speeds start at
// 0.5 and rise by 0.2 at each waypoint (§IV-B).  Shapes are ours (the paper
// shows them only in pictures): docs/rl-swarm.md.
#pragma once
#include <string>

#include "rl/leader_env.hpp"

namespace swarmcl {

// "quadrilateral", "stairway", "maze": sets leader_mode = Navigation,
// waypoints and obstacles of `config`; "roaming": joystick, no obstacles.
// Unknown names: Error(InvalidArgument) listing the known ones.
void apply_rl_scenario(const std::string& name, RlEnvConfig& config);

}  // namespace swarmcl
