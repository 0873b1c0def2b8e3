#include "rl/leader_env.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "core/philox.hpp"
#include "rl/leader_follow_params.hpp"

namespace swarmcl {

namespace {

constexpr float kDegToRad = 0.017453292519943295f;

bool finite_all(const float* v, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

void validate(const RlEnvConfig& c) {
    require(c.worlds >= 1, "rl env: worlds must be >= 1");
    require(c.agents >= 1, "rl env: agents must be >= 1");
    require(uint64_t(c.worlds) * c.agents <= kRlMaxAgents,
            "rl env: worlds * agents = " + std::to_string(uint64_t(c.worlds) * c.agents) + " exceeds " +
                std::to_string(kRlMaxAgents));
    // The parameters shared with the policy model: one validation.
    LeaderFollowParams p;
    p.r_sep = c.r_sep, p.r_ali = c.r_ali, p.r_coh = c.r_coh;
    p.neighbor_radius = c.neighbor_radius, p.body_radius = c.body_radius;
    p.du_max = c.du_max, p.dq_max_deg = c.dq_max_deg, p.u_max = c.u_max;
    p.leader_du_max = c.leader_du_max, p.leader_dq_max_deg = c.leader_dq_max_deg, p.reach_radius = c.reach_radius;
    p.needs_waypoints = c.leader_mode == RlLeaderMode::Navigation;
    p.waypoints = &c.waypoints;
    p.obstacles = &c.obstacles;
    validate_leader_follow("rl env", p);
    // The environment's own: time step, RAG weights, rewards, spawn.
    const std::pair<const char*, float> own[] = {
        {"dt", c.dt}, {"rag_w_sep", c.rag_w_sep}, {"rag_w_ali", c.rag_w_ali}, {"rag_w_coh", c.rag_w_coh},
        {"rag_leader_kp", c.rag_leader_kp}, {"rag_leader_kd", c.rag_leader_kd},
        {"leader_u0_min", c.leader_u0_min}, {"leader_u0_max", c.leader_u0_max}, {"spawn_radius", c.spawn_radius},
        {"spawn_back", c.spawn_back}, {"reward.w_spd", c.reward.w_spd}, {"reward.w_dir", c.reward.w_dir},
        {"reward.w_leader", c.reward.w_leader}, {"reward.w_obs", c.reward.w_obs}, {"reward.w_dist", c.reward.w_dist},
        {"reward.l_spd", c.reward.l_spd}, {"reward.l_dir", c.reward.l_dir}, {"reward.l_leader", c.reward.l_leader},
        {"reward.l_obs", c.reward.l_obs}, {"reward.dist_target", c.reward.dist_target}};
    for (const auto& [name, v] : own)
        require(std::isfinite(v), std::string("rl env: ") + name + " = " + param_text(v) +
                                      ": every parameter must be finite");
    require(c.dt > 0, "rl env: dt = " + param_text(c.dt) + " must be > 0");
    require(c.rag_leader_kp >= 0 && c.rag_leader_kd >= 0,
            "rl env: rag_leader_kp = " + param_text(c.rag_leader_kp) + ", rag_leader_kd = " +
                param_text(c.rag_leader_kd) + ": the leader coupling's gains must be >= 0");
    require(c.spawn_radius >= 0, "rl env: spawn_radius = " + param_text(c.spawn_radius) + " must be >= 0");
    require(0 <= c.leader_u0_min && c.leader_u0_min <= c.leader_u0_max && c.leader_u0_max <= c.u_max,
            "rl env: the leader's start speeds need 0 <= leader_u0_min <= leader_u0_max <= u_max (" +
                param_text(c.leader_u0_min) + ", " + param_text(c.leader_u0_max) + ", " +
                param_text(c.u_max) + ")");
    require(c.max_steps >= 1, "rl env: max_steps must be >= 1");
}

cl_float4 f4(float x, float y, float z, float w) { return cl_float4{{x, y, z, w}}; }

}  // namespace

LeaderEnv::LeaderEnv(Context& ctx, RlEnvConfig config) : ctx_(ctx), c_(std::move(config)) {
    validate(c_);
    const size_t n = this->n(), W = c_.worlds;
    pos_.allocate(ctx_, n, "rl env positions");
    vel_.allocate(ctx_, n, "rl env velocities");
    actions_.allocate(ctx_, 4 * n, "rl env actions");
    obs_.allocate(ctx_, size_t(obs_dim()) * n, "rl env observations");
    rewards_.allocate(ctx_, n, "rl env rewards");
    lpos_.allocate(ctx_, W, "rl env leader positions");
    lvel_.allocate(ctx_, W, "rl env leader velocities");
    ctl_.allocate(ctx_, W, "rl env leader controls");
    ctl_.fill(ctx_, f4(0, 0, 0, 0), W);
    wp_.allocate(ctx_, W, "rl env waypoint index");
    done_.allocate(ctx_, W, "rl env done");
    std::vector<cl_float4> wps;
    for (auto& w : c_.waypoints) wps.push_back(f4(w[0], w[1], w[2], w[3]));
    waypoints_.allocate(ctx_, wps.size(), "rl env waypoints");
    waypoints_.upload(ctx_, wps.data(), wps.size());
    std::vector<cl_float4> bc, bh;
    for (auto& b : c_.obstacles) {
        bc.push_back(f4(b.center[0], b.center[1], b.center[2], 0));
        bh.push_back(f4(b.half[0], b.half[1], b.half[2], 0));
    }
    box_c_.allocate(ctx_, bc.size(), "rl env obstacles");
    box_h_.allocate(ctx_, bh.size(), "rl env obstacles");
    box_c_.upload(ctx_, bc.data(), bc.size());
    box_h_.upload(ctx_, bh.data(), bh.size());
    const RlRewardParams& r = c_.reward;
    const float d_target = r.dist_target > 0 ? r.dist_target : 0.5f * (c_.r_ali - c_.r_sep);
    const float prm[11] = {r.w_spd, r.w_dir, r.w_leader, r.w_obs, r.w_dist, r.l_spd,
                           r.l_dir, r.l_leader, r.l_obs, 0.0f, d_target};
    prm_.allocate(ctx_, 11, "rl env reward parameters");
    prm_.upload(ctx_, prm, 11);
    episode_.assign(W, 0);
    steps_.assign(W, 0);
    truncated_.assign(W, 0);
    done_host_.assign(W, 0);
    step_k_ = ctx_.kernel("rl_env.cl", "rl_agents_step");
    leader_k_ = ctx_.kernel("rl_env.cl", "rl_leader_step");
    rag_k_ = ctx_.kernel("rl_env.cl", "rl_rag");
    observe_k_ = ctx_.kernel("rl_env.cl", "rl_observe");
}

// World w's start of its episode episode_[w]: every number from
// philox(seed of w, agent, episode, world), so a seed gives the same bits.
void LeaderEnv::reset_world(uint32_t w, std::vector<cl_float4>& pos, std::vector<cl_float4>& vel) {
    const uint32_t N = c_.agents, e = episode_[w];
    float lp[3] = {0, 0, 0}, q[3] = {1, 0, 0}, u;
    if (c_.leader_mode == RlLeaderMode::Navigation) {
        const auto &a = c_.waypoints[0], &b = c_.waypoints[1];
        float d[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const float l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3; ++k) {
            lp[k] = a[k];
            if (l > 0) q[k] = d[k] / l;
        }
        u = a[3];
    } else {
        const auto r = philox_for(seeds_[w], N, e, w);
        const float th = 6.2831853f * uniform01(r[0]);
        q[0] = std::cos(th);
        q[1] = std::sin(th);
        u = c_.leader_u0_min + (c_.leader_u0_max - c_.leader_u0_min) * uniform01(r[1]);
    }
    lpos_h_[w] = f4(lp[0], lp[1], lp[2], 0);
    lvel_h_[w] = f4(q[0], q[1], q[2], u);
    const float c[3] = {lp[0] - c_.spawn_back * q[0], lp[1] - c_.spawn_back * q[1], lp[2] - c_.spawn_back * q[2]};
    for (uint32_t k = 0; k < N; ++k) {
        const auto r = philox_for(seeds_[w], k, e, w);
        const float z = 2 * uniform01(r[0]) - 1, ph = 6.2831853f * uniform01(r[1]);
        const float rad = c_.spawn_radius * std::cbrt(uniform01(r[2]));
        const float s = std::sqrt(std::max(0.0f, 1 - z * z));
        const size_t i = size_t(w) * N + k;
        pos[i] = f4(c[0] + rad * s * std::cos(ph), c[1] + rad * s * std::sin(ph), c[2] + rad * z, 0);
        vel[i] = f4(q[0], q[1], q[2], u);
    }
    steps_[w] = 0;
    truncated_[w] = 0;
    done_host_[w] = 0;
}

void LeaderEnv::reset(uint64_t seed) { reset(std::vector<uint64_t>(c_.worlds, seed)); }

void LeaderEnv::reset(const std::vector<uint64_t>& seeds) {
    require(seeds.size() == c_.worlds, "rl env: seeds need worlds = " + std::to_string(c_.worlds) + " entries (" +
                                           std::to_string(seeds.size()) + " given)");
    seeds_ = seeds;
    std::fill(episode_.begin(), episode_.end(), 0u);
    was_reset_ = true;
    lpos_h_.assign(c_.worlds, f4(0, 0, 0, 0));
    lvel_h_.assign(c_.worlds, f4(0, 0, 0, 0));
    std::vector<cl_float4> pos(n()), vel(n());
    for (uint32_t w = 0; w < c_.worlds; ++w) reset_world(w, pos, vel);
    pos_.upload(ctx_, pos.data(), n());
    vel_.upload(ctx_, vel.data(), n());
    lpos_.upload(ctx_, lpos_h_.data(), c_.worlds);
    lvel_.upload(ctx_, lvel_h_.data(), c_.worlds);
    const std::vector<cl_uint> one(c_.worlds, c_.leader_mode == RlLeaderMode::Navigation ? 1u : 0u);
    wp_.upload(ctx_, one.data(), c_.worlds);
    done_.fill(ctx_, cl_uint(0), c_.worlds);
    observe();
}

void LeaderEnv::reset_worlds(const uint8_t* mask, size_t count) {
    require(was_reset_, "rl env: reset(seed) must come first");
    require(mask != nullptr && count == c_.worlds,
            "rl env: reset mask needs worlds = " + std::to_string(c_.worlds) + " entries (" + std::to_string(count) +
                " given)");
    std::vector<cl_float4> pos(n()), vel(n());
    std::vector<cl_uint> wp(c_.worlds);
    pos_.download(ctx_, pos.data(), n());
    vel_.download(ctx_, vel.data(), n());
    lpos_.download(ctx_, lpos_h_.data(), c_.worlds);
    lvel_.download(ctx_, lvel_h_.data(), c_.worlds);
    wp_.download(ctx_, wp.data(), c_.worlds);
    done_.download(ctx_, done_host_.data(), c_.worlds);
    for (uint32_t w = 0; w < c_.worlds; ++w) {
        if (!mask[w]) continue;
        ++episode_[w];
        reset_world(w, pos, vel);
        wp[w] = c_.leader_mode == RlLeaderMode::Navigation ? 1u : 0u;
    }
    pos_.upload(ctx_, pos.data(), n());
    vel_.upload(ctx_, vel.data(), n());
    lpos_.upload(ctx_, lpos_h_.data(), c_.worlds);
    lvel_.upload(ctx_, lvel_h_.data(), c_.worlds);
    wp_.upload(ctx_, wp.data(), c_.worlds);
    done_.upload(ctx_, done_host_.data(), c_.worlds);
    observe();
}

void LeaderEnv::set_leader_controls(const float* ctl, size_t count) {
    require(ctl != nullptr && count == 4 * size_t(c_.worlds),
            "rl env: leader controls need worlds * 4 = " + std::to_string(4 * size_t(c_.worlds)) + " floats (" +
                std::to_string(count) + " given)");
    require(finite_all(ctl, count), "rl env: leader controls must be finite");
    std::vector<cl_float4> v(c_.worlds);
    for (uint32_t w = 0; w < c_.worlds; ++w) v[w] = f4(ctl[4 * w], ctl[4 * w + 1], ctl[4 * w + 2], ctl[4 * w + 3]);
    ctl_.upload(ctx_, v.data(), c_.worlds);
}

void LeaderEnv::step(const float* actions, size_t count) {
    require(was_reset_, "rl env: reset(seed) must come before step");
    require(actions != nullptr && count == 4 * n(), "rl env: actions need worlds * agents * 4 = " +
                                                        std::to_string(4 * n()) + " floats (" +
                                                        std::to_string(count) + " given)");
    for (size_t i = 0; i < count; ++i)
        if (!std::isfinite(actions[i]))
            fail(Status::InvalidArgument, "rl env: action " + std::to_string(i) + " (agent " +
                                              std::to_string(i / 4) + ") is not finite");
    actions_.upload(ctx_, actions, count);
    const float dq = c_.dq_max_deg * kDegToRad, ldq = c_.leader_dq_max_deg * kDegToRad;
    set_args(leader_k_, lpos_.get(), lvel_.get(), ctl_.get(), cl_uint(c_.worlds), cl_int(c_.leader_mode),
             waypoints_.get(), cl_uint(c_.waypoints.size()), wp_.get(), done_.get(), c_.reach_radius,
             c_.leader_du_max, ldq, c_.u_max, c_.dt);
    launch(ctx_, leader_k_, c_.worlds);
    set_args(step_k_, pos_.get(), vel_.get(), actions_.get(), cl_uint(n()), c_.du_max, dq, c_.u_max, c_.dt);
    launch(ctx_, step_k_, n());
    observe();
    done_.download(ctx_, done_host_.data(), c_.worlds);
    for (uint32_t w = 0; w < c_.worlds; ++w) {
        ++steps_[w];
        truncated_[w] = steps_[w] >= c_.max_steps && !done_host_[w] ? 1 : 0;
    }
}

void LeaderEnv::observe() {
    const float r_nbr = c_.neighbor_radius > 0 ? c_.neighbor_radius : c_.r_coh;
    set_args(observe_k_, pos_.get(), vel_.get(), lpos_.get(), lvel_.get(), cl_uint(c_.agents), cl_uint(n()),
             c_.r_sep, c_.r_ali, c_.r_coh, r_nbr, c_.body_radius, box_c_.get(), box_h_.get(),
             cl_uint(c_.obstacles.size()), cl_int(c_.efs ? 1 : 0), cl_uint(obs_dim()), prm_.get(), obs_.get(),
             rewards_.get());
    launch(ctx_, observe_k_, n());
}

void LeaderEnv::rag_actions(float* out, size_t count) {
    require(was_reset_, "rl env: reset(seed) must come before rag_actions");
    require(out != nullptr && count == 4 * n(), "rl env: RAG actions need worlds * agents * 4 = " +
                                                    std::to_string(4 * n()) + " floats (" +
                                                    std::to_string(count) + " given)");
    set_args(rag_k_, pos_.get(), vel_.get(), lpos_.get(), lvel_.get(), cl_uint(c_.agents), cl_uint(n()), c_.r_sep,
             c_.r_ali, c_.r_coh, c_.rag_w_sep, c_.rag_w_ali, c_.rag_w_coh, c_.du_max, c_.dq_max_deg * kDegToRad,
             c_.dt, cl_int(c_.rag_leader_pd ? 1 : 0), c_.rag_leader_kp, c_.rag_leader_kd, actions_.get());
    launch(ctx_, rag_k_, n());
    actions_.download(ctx_, out, count);
}

void LeaderEnv::read_observations(float* out, size_t count) {
    require(was_reset_, "rl env: reset(seed) must come first");
    require(out != nullptr && count == size_t(obs_dim()) * n(),
            "rl env: observations need worlds * agents * " + std::to_string(obs_dim()) + " = " +
                std::to_string(size_t(obs_dim()) * n()) + " floats (" + std::to_string(count) + " given)");
    obs_.download(ctx_, out, count);
}

void LeaderEnv::read_rewards(float* out, size_t count) {
    require(was_reset_, "rl env: reset(seed) must come first");
    require(out != nullptr && count == n(), "rl env: rewards need worlds * agents = " + std::to_string(n()) +
                                                " floats (" + std::to_string(count) + " given)");
    rewards_.download(ctx_, out, count);
}

void LeaderEnv::read_terminated(uint8_t* out, size_t count) const {
    require(out != nullptr && count == c_.worlds, "rl env: terminated flags need worlds = " +
                                                      std::to_string(c_.worlds) + " entries");
    for (uint32_t w = 0; w < c_.worlds; ++w) out[w] = done_host_[w] ? 1 : 0;
}

void LeaderEnv::read_truncated(uint8_t* out, size_t count) const {
    require(out != nullptr && count == c_.worlds, "rl env: truncated flags need worlds = " +
                                                      std::to_string(c_.worlds) + " entries");
    for (uint32_t w = 0; w < c_.worlds; ++w) out[w] = truncated_[w];
}

void LeaderEnv::read_state(float* pos, float* vel, float* leader_pos, float* leader_vel) {
    require(was_reset_, "rl env: reset(seed) must come first");
    static_assert(sizeof(cl_float4) == 4 * sizeof(float), "cl_float4 is 4 floats");
    if (pos) pos_.download(ctx_, reinterpret_cast<cl_float4*>(pos), n());
    if (vel) vel_.download(ctx_, reinterpret_cast<cl_float4*>(vel), n());
    if (leader_pos) lpos_.download(ctx_, reinterpret_cast<cl_float4*>(leader_pos), c_.worlds);
    if (leader_vel) lvel_.download(ctx_, reinterpret_cast<cl_float4*>(leader_vel), c_.worlds);
}

void LeaderEnv::write_state(const float* pos, const float* vel, const float* leader_pos, const float* leader_vel) {
    require(was_reset_, "rl env: reset(seed) must come first");
    require(pos && vel && leader_pos && leader_vel, "rl env: write_state needs all four arrays");
    const size_t W = c_.worlds;
    require(finite_all(pos, 4 * n()) && finite_all(vel, 4 * n()) && finite_all(leader_pos, 4 * W) &&
                finite_all(leader_vel, 4 * W),
            "rl env: write_state values must be finite");
    auto pack = [&](const float* p, const float* v, size_t count, std::vector<cl_float4>& po,
                    std::vector<cl_float4>& vo) {
        po.resize(count);
        vo.resize(count);
        for (size_t i = 0; i < count; ++i) {
            const float* q = v + 4 * i;
            const float l = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
            require(l > 1e-6f, "rl env: write_state heading " + std::to_string(i) + " is zero");
            require(q[3] >= 0 && q[3] <= c_.u_max, "rl env: write_state speed " + std::to_string(i) +
                                                       " outside [0, u_max]");
            po[i] = f4(p[4 * i], p[4 * i + 1], p[4 * i + 2], 0);
            vo[i] = f4(q[0] / l, q[1] / l, q[2] / l, q[3]);
        }
    };
    std::vector<cl_float4> po, vo;
    pack(leader_pos, leader_vel, W, lpos_h_, lvel_h_);
    pack(pos, vel, n(), po, vo);
    pos_.upload(ctx_, po.data(), n());
    vel_.upload(ctx_, vo.data(), n());
    lpos_.upload(ctx_, lpos_h_.data(), W);
    lvel_.upload(ctx_, lvel_h_.data(), W);
    observe();
}

}  // namespace swarmcl
