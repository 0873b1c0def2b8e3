// The policy model's parameters (PolicyModelConfig), declared once
// (params/param_table.hpp).  Their checks are the ones the policy model
// shares with the RL environment (rl/leader_follow_params.hpp: ranges and the
// rules between parameters, in one place for both); the table's ranges are
// held to them by tests/test_params.cpp.  The weights file, the waypoints and
// the obstacle boxes are structured (scenario/policy_section.cpp).
#include "models/policy_model.hpp"
#include "params/param_table.hpp"

namespace swarmcl {

namespace {
// Read by the leader's kernel (rl_leader_step) once for every world.
constexpr const char* kLeaderOnce = "the leader's kernel reads it once for every world (every world has the same leader)";
}  // namespace

const ParamTable& policy_param_table() {
    static const ParamTable table = [] {
        using C = PolicyModelConfig;
        using T = ParamType;
        ParamTable t("policy", "PolicyModelConfig");
        t.add("r_sep", T::Float, &C::r_sep).positive().in("m")
            .says("R_sep: separation radius (r_sep < r_ali)").cites("DRL paper §III-B, Table 1");
        t.add("r_ali", T::Float, &C::r_ali).positive().in("m")
            .says("R_ali: alignment radius (r_ali < r_coh)").cites("DRL paper §III-B, Table 1");
        t.add("r_coh", T::Float, &C::r_coh).positive().in("m")
            .says("R_coh: cohesion radius, the observation's reach").cites("DRL paper §III-B, Table 1").on_device();
        t.add("neighbor_radius", T::Float, &C::neighbor_radius).non_negative().in("m")
            .says("neighbours of the embedded swarm features (EFS); 0: r_coh").cites("DRL paper §III-B, Eq. 12 (ours: the radius)")
            .on_device();
        t.add("body_radius", T::Float, &C::body_radius).positive().in("m")
            .says("the agents' sphere the observation's rays hit").cites("ours (DRL paper §III-B's rays)").on_device();
        t.add("du_max", T::Float, &C::du_max).non_negative().in("m/s")
            .says("clamp of an action's speed change per step").cites("DRL paper §III-A, Eq. 2, Table 1").on_device();
        t.add("dq_max_deg", T::Float, &C::dq_max_deg).non_negative().in("deg")
            .says("clamp of an action's turn per step").cites("DRL paper §III-A, Eq. 2, Table 1").on_device();
        t.add("u_max", T::Float, &C::u_max).positive().in("m/s")
            .says("the followers' top speed").cites("ours (Eq. 2's speed bound)").on_device()
            .same_in_every_world(kLeaderOnce);
        t.add("leader.mode", T::Enum, &C::leader_mode).c("leader_mode").names({"joystick", "navigation", "tour"})
            .says("controls set through the API; waypoints, stopping after the last; waypoints round and round")
            .cites("DRL paper §IV (scenarios); tour ours")
            .same_in_every_world(kLeaderOnce);
        t.add("leader.position", T::Vec3, &C::leader_position).c("leader_position").in("m")
            .says("the leader's start").cites("ours")
            .same_in_every_world(kLeaderOnce);
        t.add("leader.heading", T::Vec3, &C::leader_heading).c("leader_heading")
            .says("the leader's start direction (normalised; not zero)").cites("ours")
            .same_in_every_world(kLeaderOnce);
        t.add("leader.speed", T::Float, &C::leader_speed).c("leader_speed").non_negative().in("m/s")
            .says("the leader's start speed").cites("ours")
            .same_in_every_world(kLeaderOnce);
        t.add("leader.du_max", T::Float, &C::leader_du_max).c("leader_du_max").non_negative().in("m/s")
            .says("clamp of the leader's speed change per step").cites("DRL paper §III-A, Eq. 1-2 (the leader's)")
            .same_in_every_world(kLeaderOnce);
        t.add("leader.dq_max_deg", T::Float, &C::leader_dq_max_deg).c("leader_dq_max_deg").non_negative().in("deg")
            .says("clamp of the leader's turn per step").cites("DRL paper §III-A, Eq. 1-2 (the leader's)")
            .same_in_every_world(kLeaderOnce);
        t.add("leader.reach_radius", T::Float, &C::reach_radius).c("reach_radius").positive().in("m")
            .says("a waypoint counts as reached within this distance").cites("ours")
            .same_in_every_world(kLeaderOnce);
        t.finish<C>();
        return t;
    }();
    return table;
}

}  // namespace swarmcl
