#include "rl/leader_follow_params.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include "core/error.hpp"

namespace swarmcl {
namespace {

bool finite_all(const float* v, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

std::string num(float v) { return param_text(v); }

}  // namespace

std::string param_text(float v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

void validate_leader_follow(const char* who, const LeaderFollowParams& p) {
    const std::string w = std::string(who) + ": ";
    auto check = [&](bool ok, const char* name, float value, const std::string& rule) {
        if (!ok) fail(Status::InvalidArgument, w + name + " = " + num(value) + ": " + rule);
    };
    const std::pair<const char*, float> scalars[] = {
        {"r_sep", p.r_sep}, {"r_ali", p.r_ali}, {"r_coh", p.r_coh}, {"neighbor_radius", p.neighbor_radius},
        {"body_radius", p.body_radius}, {"du_max", p.du_max}, {"dq_max_deg", p.dq_max_deg}, {"u_max", p.u_max},
        {"leader_du_max", p.leader_du_max}, {"leader_dq_max_deg", p.leader_dq_max_deg},
        {"reach_radius", p.reach_radius}};
    for (const auto& [name, v] : scalars) check(std::isfinite(v), name, v, "every parameter must be finite");
    const std::string radii = "the radii need 0 < r_sep < r_ali < r_coh (Table 1: 1, 9, 18)";
    check(p.r_sep > 0, "r_sep", p.r_sep, radii);
    if (!(p.r_sep < p.r_ali))
        fail(Status::InvalidArgument, w + "r_ali = " + num(p.r_ali) + " is not above r_sep = " + num(p.r_sep) + ": " + radii);
    if (!(p.r_ali < p.r_coh))
        fail(Status::InvalidArgument, w + "r_ali = " + num(p.r_ali) + " is not below r_coh = " + num(p.r_coh) + ": " + radii);
    check(p.neighbor_radius >= 0, "neighbor_radius", p.neighbor_radius, "must be >= 0 (0: r_coh)");
    check(p.body_radius > 0, "body_radius", p.body_radius, "must be > 0");
    check(p.du_max >= 0, "du_max", p.du_max, "must be >= 0 (Table 1: 0.1)");
    check(p.dq_max_deg >= 0, "dq_max_deg", p.dq_max_deg, "must be >= 0 (Table 1: 4 degrees)");
    check(p.u_max > 0, "u_max", p.u_max, "must be > 0");
    check(p.leader_du_max >= 0, "leader_du_max", p.leader_du_max, "must be >= 0");
    check(p.leader_dq_max_deg >= 0, "leader_dq_max_deg", p.leader_dq_max_deg, "must be >= 0");
    check(p.reach_radius > 0, "reach_radius", p.reach_radius, "must be > 0");
    const size_t nw = p.waypoints ? p.waypoints->size() : 0;
    if (p.needs_waypoints) {
        if (nw < 2)
            fail(Status::InvalidArgument,
                 w + "navigation needs at least 2 waypoints (" + std::to_string(nw) + " given)");
        for (size_t k = 0; k < nw; ++k) {
            const auto& q = (*p.waypoints)[k];
            if (!finite_all(q.data(), 4) || q[3] < 0 || q[3] > p.u_max)
                fail(Status::InvalidArgument, w + "waypoint " + std::to_string(k) + " (" + num(q[0]) + ", " +
                                                  num(q[1]) + ", " + num(q[2]) + ", speed " + num(q[3]) +
                                                  ") must be finite with 0 <= speed <= u_max = " + num(p.u_max));
        }
    }
    const size_t nb = p.obstacles ? p.obstacles->size() : 0;
    for (size_t b = 0; b < nb; ++b) {
        const RlObstacleBox& o = (*p.obstacles)[b];
        if (!finite_all(o.center.data(), 3) || !finite_all(o.half.data(), 3) || !(o.half[0] > 0) ||
            !(o.half[1] > 0) || !(o.half[2] > 0))
            fail(Status::InvalidArgument, w + "obstacle " + std::to_string(b) + " (half extents " + num(o.half[0]) +
                                              ", " + num(o.half[1]) + ", " + num(o.half[2]) +
                                              ") must be finite with half extents > 0");
    }
}

}  // namespace swarmcl
