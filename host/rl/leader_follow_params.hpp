// The parameters the policy model (models/policy_model.hpp) and the RL
// environment (rl/leader_env.hpp) have in common — the followers' zones and
// clamps, the leader's clamps and waypoints, the box obstacles (paper
// drl-swarm-animation-rule-based-action-generator, Table 1 and Eq. 2; the
// rest ours, docs/rl-swarm.md) — and their one validation, so a trained
// policy and the swarm it drives accept the same worlds with the same
// messages.  Each caller checks its own parameters besides (the policy
// model's leader start, the environment's rewards, spawn and counts).
#pragma once
#include <array>
#include <string>
#include <vector>

#include "rl/leader_env.hpp"

namespace swarmcl {

// A view of a configuration's shared fields (copied floats, borrowed lists).
struct LeaderFollowParams {
    float r_sep = 0, r_ali = 0, r_coh = 0;    // Eq. 9's zones (Table 1: 1, 9, 18)
    float neighbor_radius = 0;                 // EFS neighbours; 0: r_coh
    float body_radius = 0;                     // agents' sphere for the rays
    float du_max = 0, dq_max_deg = 0, u_max = 0;  // Eq. 2's clamps, the speed ceiling
    float leader_du_max = 0, leader_dq_max_deg = 0, reach_radius = 0;
    bool needs_waypoints = false;              // the leader navigates or tours
    const std::vector<std::array<float, 4>>* waypoints = nullptr;  // (x, y, z, speed)
    const std::vector<RlObstacleBox>* obstacles = nullptr;
};

// Error(InvalidArgument) "<who>: <parameter> ...", naming the first
// parameter out of its range, its value and the range: every value finite;
// 0 < r_sep < r_ali < r_coh; neighbor_radius >= 0, body_radius > 0;
// du_max, dq_max_deg >= 0, u_max > 0; leader_du_max, leader_dq_max_deg >= 0,
// reach_radius > 0; at least 2 waypoints where the leader needs them, each
// finite with 0 <= speed <= u_max; obstacles finite with half extents > 0.
void validate_leader_follow(const char* who, const LeaderFollowParams& p);

// A value as these messages print it ("0.1", "-4", "nan", "inf"), for the
// callers' own checks.
std::string param_text(float v);

}  // namespace swarmcl
