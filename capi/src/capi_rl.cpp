// The deep-RL leader-following environment (issue 15): whole arrays in and
// out of host/rl/leader_env, never one agent at a time.
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>

#include "capi_common.hpp"
#include "rl/leader_env.hpp"
#include "rl/rl_scenarios.hpp"

using namespace swarmcl;
using namespace swarmcl::capi;

namespace {

struct RlEnvHandle {
    std::shared_ptr<Context> context;  // kept alive while the env lives
    std::unique_ptr<LeaderEnv> env;
    std::mutex mutex;
};

HandleRegistry<RlEnvHandle>& rl_envs() {
    static auto* registry = new HandleRegistry<RlEnvHandle>(0x7E, "rl env");
    return *registry;
}

template <typename F>
swcl_status with_env(const char* function, swcl_rl_env handle, F&& body) noexcept {
    return guarded(function, [&] {
        auto h = rl_envs().get(handle.id);
        std::lock_guard<std::mutex> lock(h->mutex);
        body(*h->env);
    });
}

// The first version ended at dist_target; the leader coupling came after.
constexpr size_t kRlDescV1 = offsetof(swcl_rl_env_desc, rag_leader_pd);

RlEnvConfig config_from(const swcl_rl_env_desc& d) {
    RlEnvConfig c;
    c.worlds = d.worlds;
    c.agents = d.agents;
    apply_rl_scenario(d.scenario ? d.scenario : "roaming", c);
    require(d.waypoints != nullptr || d.waypoint_count == 0,
            "waypoints is NULL but waypoint_count is " + std::to_string(d.waypoint_count));
    if (d.waypoint_count) {
        c.leader_mode = RlLeaderMode::Navigation;
        c.waypoints.clear();
        for (uint32_t k = 0; k < d.waypoint_count; ++k)
            c.waypoints.push_back({d.waypoints[4 * k], d.waypoints[4 * k + 1], d.waypoints[4 * k + 2],
                                   d.waypoints[4 * k + 3]});
    }
    require(d.obstacles != nullptr || d.obstacle_count == 0,
            "obstacles is NULL but obstacle_count is " + std::to_string(d.obstacle_count));
    for (uint32_t b = 0; b < d.obstacle_count; ++b) {
        const float* o = d.obstacles + 6 * size_t(b);
        c.obstacles.push_back({{o[0], o[1], o[2]}, {o[3], o[4], o[5]}});
    }
    c.max_steps = d.max_steps;
    c.efs = d.efs != 0;
    c.dt = d.dt;
    c.du_max = d.du_max;
    c.dq_max_deg = d.dq_max_deg;
    c.r_sep = d.r_sep;
    c.r_ali = d.r_ali;
    c.r_coh = d.r_coh;
    c.u_max = d.u_max;
    c.body_radius = d.body_radius;
    c.neighbor_radius = d.neighbor_radius;
    c.rag_w_sep = d.rag_w_sep;
    c.rag_w_ali = d.rag_w_ali;
    c.rag_w_coh = d.rag_w_coh;
    c.reward = {d.w_spd, d.w_dir, d.w_leader, d.w_obs, d.w_dist, d.l_spd, d.l_dir, d.l_leader, d.l_obs,
                d.dist_target};
    if (d.struct_size >= offsetof(swcl_rl_env_desc, rag_leader_kd) + sizeof(d.rag_leader_kd)) {
        c.rag_leader_pd = d.rag_leader_pd != 0;
        c.rag_leader_kp = d.rag_leader_kp;
        c.rag_leader_kd = d.rag_leader_kd;
    }
    return c;
}

void check_count(const void* p, size_t count, size_t want, const char* what) {
    if (!p) return;
    require(count == want, std::string(what) + " needs " + std::to_string(want) + " entries (" +
                               std::to_string(count) + " given)");
}

}  // namespace

extern "C" {

swcl_rl_env_desc swcl_rl_env_desc_default(void) {
    const RlEnvConfig c;
    swcl_rl_env_desc d{};
    d.struct_size = sizeof d;
    d.worlds = c.worlds;
    d.agents = c.agents;
    d.max_steps = c.max_steps;
    d.efs = 1;
    d.dt = c.dt;
    d.du_max = c.du_max;
    d.dq_max_deg = c.dq_max_deg;
    d.r_sep = c.r_sep;
    d.r_ali = c.r_ali;
    d.r_coh = c.r_coh;
    d.u_max = c.u_max;
    d.body_radius = c.body_radius;
    d.neighbor_radius = c.neighbor_radius;
    d.rag_w_sep = c.rag_w_sep;
    d.rag_w_ali = c.rag_w_ali;
    d.rag_w_coh = c.rag_w_coh;
    d.rag_leader_pd = c.rag_leader_pd ? 1 : 0;
    d.rag_leader_kp = c.rag_leader_kp;
    d.rag_leader_kd = c.rag_leader_kd;
    const RlRewardParams& r = c.reward;
    d.w_spd = r.w_spd;
    d.w_dir = r.w_dir;
    d.w_leader = r.w_leader;
    d.w_obs = r.w_obs;
    d.w_dist = r.w_dist;
    d.l_spd = r.l_spd;
    d.l_dir = r.l_dir;
    d.l_leader = r.l_leader;
    d.l_obs = r.l_obs;
    d.dist_target = r.dist_target;
    return d;
}

swcl_status swcl_rl_env_create(swcl_context context, const swcl_rl_env_desc* desc, swcl_rl_env* out) {
    return guarded(__func__, [&] {
        check_struct_size(desc, kRlDescV1, "desc");
        check_out(out, "out");
        auto h = std::make_shared<RlEnvHandle>();
        h->context = contexts().get(context.id);
        h->env = std::make_unique<LeaderEnv>(*h->context, config_from(*desc));
        out->id = rl_envs().add(std::move(h));
    });
}

swcl_status swcl_rl_env_destroy(swcl_rl_env env) {
    return guarded(__func__, [&] { rl_envs().remove(env.id); });
}

swcl_status swcl_rl_env_get_info(swcl_rl_env env, uint32_t* out_worlds, uint32_t* out_agents, uint32_t* out_obs_dim) {
    return with_env(__func__, env, [&](LeaderEnv& e) {
        if (out_worlds) *out_worlds = e.worlds();
        if (out_agents) *out_agents = e.agents();
        if (out_obs_dim) *out_obs_dim = e.obs_dim();
    });
}

swcl_status swcl_rl_env_get_layout(swcl_rl_env env, float* out_waypoints, size_t waypoint_capacity,
                                   uint32_t* out_waypoint_count, float* out_obstacles, size_t obstacle_capacity,
                                   uint32_t* out_obstacle_count) {
    return with_env(__func__, env, [&](LeaderEnv& e) {
        const RlEnvConfig& c = e.config();
        const size_t nw = c.leader_mode == RlLeaderMode::Navigation ? c.waypoints.size() : 0, nb = c.obstacles.size();
        require(!out_waypoints || waypoint_capacity >= nw,
                "out_waypoints needs " + std::to_string(nw) + " rows of 4 (capacity " +
                    std::to_string(waypoint_capacity) + ")");
        require(!out_obstacles || obstacle_capacity >= nb,
                "out_obstacles needs " + std::to_string(nb) + " rows of 6 (capacity " +
                    std::to_string(obstacle_capacity) + ")");
        for (size_t i = 0; out_waypoints && i < nw; ++i)
            for (int k = 0; k < 4; ++k) out_waypoints[4 * i + k] = c.waypoints[i][k];
        for (size_t i = 0; out_obstacles && i < nb; ++i)
            for (int k = 0; k < 3; ++k) {
                out_obstacles[6 * i + k] = c.obstacles[i].center[k];
                out_obstacles[6 * i + 3 + k] = c.obstacles[i].half[k];
            }
        if (out_waypoint_count) *out_waypoint_count = uint32_t(nw);
        if (out_obstacle_count) *out_obstacle_count = uint32_t(nb);
    });
}

swcl_status swcl_rl_env_reset(swcl_rl_env env, uint64_t seed, float* out_obs, size_t obs_count) {
    return with_env(__func__, env, [&](LeaderEnv& e) {
        const size_t n = size_t(e.worlds()) * e.agents();
        check_count(out_obs, obs_count, n * e.obs_dim(), "out_obs");
        e.reset(seed);
        if (out_obs) e.read_observations(out_obs, obs_count);
    });
}

swcl_status swcl_rl_env_reset_seeds(swcl_rl_env env, const uint64_t* seeds, size_t seed_count, float* out_obs,
                                    size_t obs_count) {
    return with_env(__func__, env, [&](LeaderEnv& e) {
        const size_t n = size_t(e.worlds()) * e.agents();
        check_count(out_obs, obs_count, n * e.obs_dim(), "out_obs");
        require(seeds != nullptr && seed_count == e.worlds(), "seeds needs worlds = " + std::to_string(e.worlds()) +
                                                                 " entries (" + std::to_string(seed_count) +
                                                                 " given)");
        e.reset(std::vector<uint64_t>(seeds, seeds + seed_count));
        if (out_obs) e.read_observations(out_obs, obs_count);
    });
}

swcl_status swcl_rl_env_reset_worlds(swcl_rl_env env, const uint8_t* mask, size_t mask_count, float* out_obs,
                                     size_t obs_count) {
    return with_env(__func__, env, [&](LeaderEnv& e) {
        const size_t n = size_t(e.worlds()) * e.agents();
        check_count(out_obs, obs_count, n * e.obs_dim(), "out_obs");
        e.reset_worlds(mask, mask_count);
        if (out_obs) e.read_observations(out_obs, obs_count);
    });
}

swcl_status swcl_rl_env_step(swcl_rl_env env, const float* actions, size_t action_count, float* out_obs,
                             size_t obs_count, float* out_rewards, size_t reward_count, uint8_t* out_terminated,
                             uint8_t* out_truncated, size_t world_count) {
    return with_env(__func__, env, [&](LeaderEnv& e) {
        // Every size checked before anything moves.
        const size_t n = size_t(e.worlds()) * e.agents();
        check_count(out_obs, obs_count, n * e.obs_dim(), "out_obs");
        check_count(out_rewards, reward_count, n, "out_rewards");
        if (out_terminated || out_truncated)
            require(world_count == e.worlds(), "out_terminated / out_truncated need worlds = " +
                                                   std::to_string(e.worlds()) + " entries (" +
                                                   std::to_string(world_count) + " given)");
        e.step(actions, action_count);
        if (out_obs) e.read_observations(out_obs, obs_count);
        if (out_rewards) e.read_rewards(out_rewards, reward_count);
        if (out_terminated) e.read_terminated(out_terminated, world_count);
        if (out_truncated) e.read_truncated(out_truncated, world_count);
    });
}

swcl_status swcl_rl_env_rag_actions(swcl_rl_env env, float* out_actions, size_t action_count) {
    return with_env(__func__, env, [&](LeaderEnv& e) { e.rag_actions(out_actions, action_count); });
}

swcl_status swcl_rl_env_set_leader_controls(swcl_rl_env env, const float* controls, size_t count) {
    return with_env(__func__, env, [&](LeaderEnv& e) { e.set_leader_controls(controls, count); });
}

swcl_status swcl_rl_env_read_state(swcl_rl_env env, float* out_pos, size_t pos_count, float* out_vel,
                                   size_t vel_count, float* out_leader_pos, float* out_leader_vel,
                                   size_t leader_count) {
    return with_env(__func__, env, [&](LeaderEnv& e) {
        const size_t n = size_t(e.worlds()) * e.agents();
        check_count(out_pos, pos_count, 4 * n, "out_pos");
        check_count(out_vel, vel_count, 4 * n, "out_vel");
        if (out_leader_pos || out_leader_vel)
            require(leader_count == 4 * size_t(e.worlds()),
                    "out_leader_pos / out_leader_vel need worlds * 4 = " + std::to_string(4 * size_t(e.worlds())) +
                        " entries (" + std::to_string(leader_count) + " given)");
        e.read_state(out_pos, out_vel, out_leader_pos, out_leader_vel);
    });
}

}  // extern "C"
