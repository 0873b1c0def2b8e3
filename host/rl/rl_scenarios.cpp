#include "rl/rl_scenarios.hpp"

#include <initializer_list>

#include "core/error.hpp"

namespace swarmcl {

namespace {

// Target speed of waypoint k: 0.5 at the start, +0.2 per waypoint (§IV-B).
float speed_at(size_t k) { return 0.5f + 0.2f * float(k); }

void set_path(RlEnvConfig& c, std::initializer_list<std::array<float, 3>> points) {
    c.leader_mode = RlLeaderMode::Navigation;
    c.waypoints.clear();
    for (const auto& p : points) c.waypoints.push_back({p[0], p[1], p[2], speed_at(c.waypoints.size())});
    c.obstacles.clear();
}

}  // namespace

void apply_rl_scenario(const std::string& name, RlEnvConfig& c) {
    if (name == "roaming") {
        c.leader_mode = RlLeaderMode::Joystick;
        c.waypoints.clear();
        c.obstacles.clear();
    } else if (name == "quadrilateral") {
        // A 60 x 40 quadrilateral in the z = 0 plane, closed.
        set_path(c, {{0, 0, 0}, {60, 0, 0}, {60, 40, 0}, {0, 40, 0}, {0, 0, 0}});
    } else if (name == "stairway") {
        // Four steps rising along +x (each 12 long, 4 high, 30 wide); the
        // path climbs 6 above each step's top.
        set_path(c, {{-20, 0, 6}, {0, 0, 6}, {12, 0, 10}, {24, 0, 14}, {36, 0, 18}, {56, 0, 18}});
        for (int s = 0; s < 4; ++s) {
            const float top = 4.0f * float(s);  // step s: x in [12 s, 12 s + 12], z in [-4, top]
            c.obstacles.push_back({{12.0f * float(s) + 6.0f, 0.0f, 0.5f * (top - 4.0f)},
                                   {6.0f, 15.0f, 0.5f * (top + 4.0f)}});
        }
    } else if (name == "maze") {
        // A corridor (side walls at y = +-23, x in [-10, 70]) crossed by three
        // walls at x = 20, 40, 60 with alternating 14-wide gaps (y in [8, 22],
        // [-22, -8], [8, 22]); the path passes each gap at y = +-15.
        set_path(c, {{-10, 0, 0}, {14, 15, 0}, {26, 15, 0}, {34, -15, 0}, {46, -15, 0}, {54, 15, 0},
                     {66, 15, 0}, {80, 0, 0}});
        c.obstacles.push_back({{20, -6, 0}, {1, 14, 10}});
        c.obstacles.push_back({{40, 6, 0}, {1, 14, 10}});
        c.obstacles.push_back({{60, -6, 0}, {1, 14, 10}});
        c.obstacles.push_back({{30, 23, 0}, {40, 1, 10}});
        c.obstacles.push_back({{30, -23, 0}, {40, 1, 10}});
    } else {
        fail(Status::InvalidArgument,
             "rl scenario '" + name + "' is unknown (roaming, quadrilateral, stairway, maze)");
    }
}

}  // namespace swarmcl
