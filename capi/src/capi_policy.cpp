// The policy model (issue 15 item 7; docs/rl-swarm.md, "Policy model").
#include <cstring>

#include "capi_common.hpp"
#include "models/policy_model.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

PolicyModel& policy_of(Swarm& s, const char* what) {
    auto* p = dynamic_cast<PolicyModel*>(s.behavior());
    if (!p) fail(Status::InvalidArgument, std::string(what) + ": the swarm's model is not the policy model");
    return *p;
}

}  // namespace

extern "C" {

swcl_policy_model_desc swcl_policy_model_desc_default(void) {
    swcl_policy_model_desc d;
    std::memset(&d, 0, sizeof(d));
    const PolicyModelConfig c;
    d.struct_size = sizeof(d);
    d.leader_mode = SWCL_POLICY_LEADER_JOYSTICK;
    for (int a = 0; a < 3; ++a) {
        d.leader_position[a] = c.leader_position[a];
        d.leader_heading[a] = c.leader_heading[a];
    }
    d.leader_speed = c.leader_speed;
    d.leader_du_max = c.leader_du_max;
    d.leader_dq_max_deg = c.leader_dq_max_deg;
    d.reach_radius = c.reach_radius;
    d.r_sep = c.r_sep;
    d.r_ali = c.r_ali;
    d.r_coh = c.r_coh;
    d.neighbor_radius = c.neighbor_radius;
    d.body_radius = c.body_radius;
    d.du_max = c.du_max;
    d.dq_max_deg = c.dq_max_deg;
    d.u_max = c.u_max;
    return d;
}

swcl_status swcl_swarm_policy_set_model(swcl_swarm swarm, const swcl_policy_model_desc* desc) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        check_struct_size(desc, sizeof(swcl_policy_model_desc), "desc");
        PolicyModelConfig c;
        const uint32_t leader_mode = enum_bits(desc->leader_mode);  // a C caller's value may be any int
        require(leader_mode <= SWCL_POLICY_LEADER_TOUR, "desc->leader_mode: unknown mode " + c_enum_text(leader_mode));
        c.leader_mode = PolicyLeaderMode(leader_mode);
        require(desc->waypoints != nullptr || desc->waypoint_count == 0, "desc->waypoints is NULL");
        for (uint32_t k = 0; k < desc->waypoint_count; ++k)
            c.waypoints.push_back({desc->waypoints[4 * k], desc->waypoints[4 * k + 1], desc->waypoints[4 * k + 2],
                                   desc->waypoints[4 * k + 3]});
        for (int a = 0; a < 3; ++a) {
            c.leader_position[a] = desc->leader_position[a];
            c.leader_heading[a] = desc->leader_heading[a];
        }
        c.leader_speed = desc->leader_speed;
        c.leader_du_max = desc->leader_du_max;
        c.leader_dq_max_deg = desc->leader_dq_max_deg;
        c.reach_radius = desc->reach_radius;
        c.r_sep = desc->r_sep;
        c.r_ali = desc->r_ali;
        c.r_coh = desc->r_coh;
        c.neighbor_radius = desc->neighbor_radius;
        c.body_radius = desc->body_radius;
        c.du_max = desc->du_max;
        c.dq_max_deg = desc->dq_max_deg;
        c.u_max = desc->u_max;
        require(desc->obstacles != nullptr || desc->obstacle_count == 0, "desc->obstacles is NULL");
        for (uint32_t b = 0; b < desc->obstacle_count; ++b) {
            const float* o = desc->obstacles + 6 * size_t(b);
            c.obstacles.push_back({{o[0], o[1], o[2]}, {o[3], o[4], o[5]}});
        }
        std::shared_ptr<const std::string> bytes;
        if (desc->weights_path) {
            bytes = std::make_shared<const std::string>(read_policy_file(desc->weights_path));
        } else {
            require(desc->weights_data != nullptr, "desc: weights_path and weights_data are both NULL");
            bytes = std::make_shared<const std::string>(static_cast<const char*>(desc->weights_data),
                                                        desc->weights_size);
        }
        std::shared_ptr<PolicyModel> model;
        try {
            model = std::make_shared<PolicyModel>(s, std::move(c), std::move(bytes));
        } catch (const Error& e) {
            if (desc->weights_path && e.status() == Status::Parse)
                fail(Status::Parse, std::string(desc->weights_path) + ": " + e.what());
            throw;
        }
        s.set_behavior(std::move(model));
    });
}

swcl_status swcl_swarm_policy_set_leader_controls(swcl_swarm swarm, const float controls[4]) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        require(controls != nullptr, "controls is NULL");
        policy_of(s, __func__).set_leader_controls({controls[0], controls[1], controls[2], controls[3]});
    });
}

swcl_status swcl_swarm_policy_get_leader(swcl_swarm swarm, float out_position[3], float out_heading_speed[4]) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        cl_float4 p, v;
        policy_of(s, __func__).read_leader(&p, &v);
        if (out_position)
            for (int a = 0; a < 3; ++a) out_position[a] = p.s[a];
        if (out_heading_speed)
            for (int a = 0; a < 4; ++a) out_heading_speed[a] = v.s[a];
    });
}

swcl_status swcl_swarm_policy_get_info(swcl_swarm swarm, uint32_t* out_obs_dim, uint32_t* out_layers,
                                       uint32_t* out_widths) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        const PolicyWeights& w = policy_of(s, __func__).weights();
        if (out_obs_dim) *out_obs_dim = w.obs_dim;
        if (out_layers) *out_layers = uint32_t(w.layers.size());
        if (out_widths)
            for (size_t i = 0; i < w.layers.size(); ++i) out_widths[i] = w.layers[i].out;
    });
}

swcl_status swcl_swarm_policy_observe(swcl_swarm swarm, float* out_obs, float* out_actions, size_t count) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        PolicyModel& p = policy_of(s, __func__);
        require(count == s.total_agents(), std::string(__func__) + ": count is " + std::to_string(count) +
                                               " but the swarm has " + std::to_string(s.total_agents()) +
                                               " agents (all worlds)");
        std::vector<float> obs, act;
        p.observe(s, out_obs ? &obs : nullptr, out_actions ? &act : nullptr);
        if (out_obs) std::copy(obs.begin(), obs.end(), out_obs);
        if (out_actions) std::copy(act.begin(), act.end(), out_actions);
    });
}

swcl_status swcl_swarm_policy_infer(swcl_swarm swarm, const float* obs, size_t count, float* out_actions) {
    return with_swarm(__func__, swarm, [&](Swarm& s) {
        PolicyModel& p = policy_of(s, __func__);
        require(count <= 0xFFFFFFFFu, std::string(__func__) + ": count " + std::to_string(count) + " is too large");
        require(count == 0 || (obs && out_actions), std::string(__func__) + ": obs and out_actions must not be NULL");
        p.infer(obs, uint32_t(count), out_actions);
    });
}

}  // extern "C"
