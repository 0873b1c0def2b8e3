#include "models/policy_model.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "fields/noise_field.hpp"
#include "models/model_descriptor.hpp"
#include "params/param_block.hpp"
#include "rl/leader_follow_params.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {
namespace {

constexpr float kDegToRad = 0.017453292519943295f;
// Tiles of the MLP per launch: its scratch is 2 * max_width * lanes floats
// per tile (at most 64 MiB for 512-wide layers and 16 lanes).  A multiple of
// every local size launch() gives this kernel (powers of two, at most its
// max_local of 64), so only the last chunk's launch is padded, past the last
// tile (those work-items return): work-item t uses scratch row t, and a
// padded work-item of an earlier chunk would take a row past the scratch.
constexpr uint32_t kMlpChunkTiles = 1024;
static_assert(kMlpChunkTiles % 64 == 0, "kMlpChunkTiles: a multiple of launch()'s local sizes");
// policy_mlp's lanes on CPU devices (weights read once per 16 agents).
constexpr uint32_t kPolicyMlpCpuLanes = 16;

// The tiled MLP (policy_mlp_tiled, the GPU profile): 64 outputs x 64 agents
// per 16 x 16 work-group.  Agents are chunked so its two hidden buffers stay
// bounded: at most 64k agents a chunk and 16M floats (64 MiB) a buffer; a
// chunk is a multiple of 64 agents, the buffers' agent stride.
constexpr uint32_t kTiledTile = 64, kTiledLocal = 16;
constexpr uint32_t kTiledChunkAgents = 65536;
constexpr size_t kTiledBufferFloats = size_t(16) << 20;

bool finite_all(const float* v, size_t n) {
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

cl_float4 f4(float x, float y, float z, float w) { return cl_float4{{x, y, z, w}}; }

float activate(float x, PolicyActivation a) {
    if (a == PolicyActivation::Relu) return std::max(x, 0.0f);
    if (a == PolicyActivation::Tanh) return std::tanh(x);
    return x;
}

// The fields shared with the RL environment (rl/leader_follow_params.hpp).
LeaderFollowParams leader_follow_params(const PolicyModelConfig& c) {
    LeaderFollowParams p;
    p.r_sep = c.r_sep, p.r_ali = c.r_ali, p.r_coh = c.r_coh;
    p.neighbor_radius = c.neighbor_radius, p.body_radius = c.body_radius;
    p.du_max = c.du_max, p.dq_max_deg = c.dq_max_deg, p.u_max = c.u_max;
    p.leader_du_max = c.leader_du_max, p.leader_dq_max_deg = c.leader_dq_max_deg, p.reach_radius = c.reach_radius;
    p.needs_waypoints = c.leader_mode != PolicyLeaderMode::Joystick;
    p.waypoints = &c.waypoints;
    p.obstacles = &c.obstacles;
    return p;
}

}  // namespace

void validate(const PolicyModelConfig& c) {
    require(uint32_t(c.leader_mode) <= 2, "policy model: unknown leader mode");
    validate_leader_follow("policy model", leader_follow_params(c));
    // The leader's start (the environment draws its own).
    const float start[] = {c.leader_speed, c.leader_position[0], c.leader_position[1], c.leader_position[2],
                           c.leader_heading[0], c.leader_heading[1], c.leader_heading[2]};
    require(finite_all(start, sizeof start / sizeof *start),
            "policy model: leader_speed, leader_position and leader_heading must be finite");
    require(c.leader_speed >= 0 && c.leader_speed <= c.u_max,
            "policy model: leader_speed = " + param_text(c.leader_speed) + " must lie in [0, u_max = " +
                param_text(c.u_max) + "]");
    const float h = std::sqrt(c.leader_heading[0] * c.leader_heading[0] + c.leader_heading[1] * c.leader_heading[1] +
                              c.leader_heading[2] * c.leader_heading[2]);
    require(h > 1e-6f, "policy model: leader_heading must not be zero");
}

std::array<float, 4> policy_forward(const PolicyWeights& w, const float* obs) {
    std::vector<float> x(obs, obs + w.obs_dim), y;
    if (!w.obs_mean.empty())
        for (uint32_t i = 0; i < w.obs_dim; ++i) x[i] = (x[i] - w.obs_mean[i]) / w.obs_std[i];
    for (const PolicyLayer& L : w.layers) {
        y.assign(L.out, 0.0f);
        for (uint32_t o = 0; o < L.out; ++o) {
            float acc = L.bias[o];
            for (uint32_t i = 0; i < L.in; ++i) acc = std::fma(L.weight[size_t(o) * L.in + i], x[i], acc);
            y[o] = activate(acc, L.activation);
        }
        x.swap(y);
    }
    return {x[0] * w.action_scale[0], x[1] * w.action_scale[1], x[2] * w.action_scale[2], x[3] * w.action_scale[3]};
}

PolicyModel::PolicyModel(Swarm& swarm, PolicyModelConfig config, std::shared_ptr<const std::string> bytes)
    : config_(std::move(config)), worlds_(policy_param_table(), config_, 1), bytes_(std::move(bytes)),
      ctx_(swarm.context()) {
    require(bytes_ != nullptr, "policy model: no weights");
    weights_ = parse_policy_weights(reinterpret_cast<const uint8_t*>(bytes_->data()), bytes_->size());
    validate(config_);
    Context& ctx = ctx_;
    // Parameters in one array: per layer weight then bias, then mean and std.
    std::vector<float> params;
    std::vector<cl_uint> table;
    for (const PolicyLayer& L : weights_.layers) {
        table.insert(table.end(), {L.in, L.out, cl_uint(L.activation), cl_uint(params.size()),
                                   cl_uint(params.size() + L.weight.size())});
        params.insert(params.end(), L.weight.begin(), L.weight.end());
        params.insert(params.end(), L.bias.begin(), L.bias.end());
        max_width_ = std::max({max_width_, L.in, L.out});
        if (&L != &weights_.layers.back()) hidden_width_ = std::max(hidden_width_, L.out);
    }
    layer_table_.assign(table.begin(), table.end());
    mean_off_ = uint32_t(params.size());
    params.insert(params.end(), weights_.obs_mean.begin(), weights_.obs_mean.end());
    std_off_ = uint32_t(params.size());
    params.insert(params.end(), weights_.obs_std.begin(), weights_.obs_std.end());
    params_.allocate(ctx, params.size(), "policy weights");
    params_.upload(ctx, params.data(), params.size());
    layers_.allocate(ctx, table.size(), "policy layer table");
    layers_.upload(ctx, table.data(), table.size());

    // The leader: at leader_position heading along leader_heading at
    // leader_speed; navigation and tours start at waypoint 0.
    const auto& c = config_;
    const float hl = std::sqrt(c.leader_heading[0] * c.leader_heading[0] + c.leader_heading[1] * c.leader_heading[1] +
                               c.leader_heading[2] * c.leader_heading[2]);
    const cl_float4 lp = f4(c.leader_position[0], c.leader_position[1], c.leader_position[2], 0.0f);
    const cl_float4 lv = f4(c.leader_heading[0] / hl, c.leader_heading[1] / hl, c.leader_heading[2] / hl, c.leader_speed);
    // Worlds: one leader each, every one starting alike (the leader's
    // parameters are one for every world).
    const uint32_t worlds = swarm.worlds();
    worlds_ = WorldConfigs<PolicyModelConfig>(policy_param_table(), config_, worlds);
    lpos_.allocate(ctx, worlds, "policy leader position");
    lvel_.allocate(ctx, worlds, "policy leader velocity");
    lst_.allocate(ctx, size_t(2) * worlds, "policy leader state");
    ctl_.allocate(ctx, worlds, "policy leader controls");
    lpos_.fill(ctx, lp, worlds);
    lvel_.fill(ctx, lv, worlds);
    ctl_.fill(ctx, f4(0, 0, 0, 0), worlds);
    wp_.allocate(ctx, worlds, "policy leader waypoint");
    done_.allocate(ctx, worlds, "policy leader done");
    wp_.fill(ctx, 0u, worlds);
    done_.fill(ctx, 0u, worlds);
    std::vector<cl_float4> wps;
    for (const auto& w : c.waypoints) wps.push_back(f4(w[0], w[1], w[2], w[3]));
    waypoints_.allocate(ctx, wps.size(), "policy waypoints");
    waypoints_.upload(ctx, wps.data(), wps.size());
    std::vector<cl_float4> bc, bh;
    for (const auto& b : c.obstacles) {
        bc.push_back(f4(b.center[0], b.center[1], b.center[2], 0));
        bh.push_back(f4(b.half[0], b.half[1], b.half[2], 0));
    }
    box_c_.allocate(ctx, bc.size(), "policy obstacles");
    box_h_.allocate(ctx, bh.size(), "policy obstacles");
    box_c_.upload(ctx, bc.data(), bc.size());
    box_h_.upload(ctx, bh.data(), bh.size());

    // CPU devices: the observations take the noise kernels' lane width (16,
    // or 8 where the device prefers 8-float vectors), the MLP 16 lanes
    // whatever the device (with AVX2 its 8-lane build was 12 % slower, the
    // observations' 16-lane build 10 %: docs/benchmarks.md, "Eight lanes
    // with AVX2"); a forced noise width sets both.  set_kernel_width_override,
    // then $SWARMCL_POLICY_LANES, override both.
    const char* env = std::getenv("SWARMCL_POLICY_LANES");
    const bool cpu = ctx.device().cpu_profile;
    lanes_ = cpu ? preferred_noise_width(ctx.device()) : 1;
    mlp_lanes_ = cpu && !kernel_width_forced() ? kPolicyMlpCpuLanes : lanes_;
    bool forced = false;
    if (env && (std::string(env) == "1" || std::string(env) == "8" || std::string(env) == "16")) {
        lanes_ = mlp_lanes_ = uint32_t(std::stoul(env));
        forced = true;
    }
    if (const uint32_t w = kernel_width_override()) {
        lanes_ = mlp_lanes_ = w;
        forced = true;
    }
    // Every build of policy.cl names the parameter block's slots (POLICY_*).
    const std::string slots = policy_param_table().device_defines("POLICY") + world_defines(worlds);
    const std::string lanes_define = "-DPM_W=" + std::to_string(lanes_) + slots;
    const std::string mlp_define = "-DPM_W=" + std::to_string(mlp_lanes_) + slots;
    // With lanes, the observations too come PM_W agents per work-item.
    observe_k_ = lanes_ > 1 ? ctx.kernel("policy.cl", "policy_observe_w", lanes_define)
                            : ctx.kernel("policy.cl", "policy_observe", slots);
    mlp_k_ = ctx.kernel("policy.cl", "policy_mlp", mlp_define);
    // Other devices (the GPU profile), lanes not forced: the tiled MLP
    // (kernels/policy.cl says why), if the device runs its 256-item groups
    // and has the local memory; policy_mlp otherwise.
    if (!ctx.device().cpu_profile && !forced) {
        cl::Kernel k = ctx.kernel("policy.cl", "policy_mlp_tiled", mlp_define);
        const cl::Device& dev = ctx.device().device;
        const size_t group = k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(dev);
        const cl_ulong local = k.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(dev);
        const std::vector<size_t> items = dev.getInfo<CL_DEVICE_MAX_WORK_ITEM_SIZES>();
        if (group >= size_t(kTiledLocal) * kTiledLocal && local <= dev.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>() &&
            items.size() >= 2 && items[0] >= kTiledLocal && items[1] >= kTiledLocal) {
            tiled_ = true;
            tiled_k_ = k;
            const size_t per_buffer = kTiledBufferFloats / std::max<uint32_t>(hidden_width_, 1) / kTiledTile * kTiledTile;
            tiled_chunk_ = uint32_t(std::clamp<size_t>(per_buffer, kTiledTile, kTiledChunkAgents));
        }
    }
    apply_k_ = ctx.kernel("policy.cl", "policy_apply", slots);
    copy_k_ = ctx.kernel("policy.cl", "policy_leader_copy", slots);
    headings_k_ = ctx.kernel("policy.cl", "policy_headings", slots);
    upload_world_blocks();
    leader_k_ = ctx.kernel("rl_env.cl", "rl_leader_step");
    enqueue_leader_copy(worlds);
}

void PolicyModel::upload_world_blocks() {
    const std::vector<float> blocks = worlds_.device_blocks();
    block_.reserve(ctx_, blocks.size(), "policy parameter blocks");
    block_.upload(ctx_, blocks.data(), blocks.size());
    blocks_current_ = true;
}

void PolicyModel::set_world_param(Swarm&, const std::string& key, const double* values, size_t count) {
    // The leader's parameters and u_max (one for every world in the table)
    // are refused even where every world has the same value: the leader
    // state is set once, at creation.
    const Param& row = world_param_row(policy_param_table(), key);
    if (!row.one_world.empty())
        fail(Status::InvalidArgument, "policy model " + row.key + " cannot differ between worlds: " + row.one_world);
    worlds_.set(key, values, count, [](const PolicyModelConfig& c, uint32_t) { validate(c); });
    config_ = worlds_[0];
    blocks_current_ = false;
}

std::vector<double> PolicyModel::world_param(const std::string& key) const { return worlds_.get(key); }

std::vector<std::string> PolicyModel::varied_world_params() const {
    return worlds_.worlds() > 1 ? worlds_.varied_keys() : std::vector<std::string>{};
}

void PolicyModel::set_leader_controls(const std::array<float, 4>& ctl) {
    require(finite_all(ctl.data(), 4), "policy model: leader controls must be finite");
    ctl_.fill(ctx_, f4(ctl[0], ctl[1], ctl[2], ctl[3]), worlds_.worlds());
}

void PolicyModel::read_leader(cl_float4* position, cl_float4* heading_speed, uint32_t world) {
    require(world < worlds_.worlds(), "policy model: world " + std::to_string(world) + " does not exist (" +
                                          std::to_string(worlds_.worlds()) + " worlds)");
    std::vector<cl_float4> all(worlds_.worlds());
    if (position) {
        lpos_.download(ctx_, all.data(), all.size());
        *position = all[world];
    }
    if (heading_speed) {
        lvel_.download(ctx_, all.data(), all.size());
        *heading_speed = all[world];
    }
}

void PolicyModel::enqueue_leader_copy(uint32_t worlds) {
    set_args(copy_k_, lpos_.get(), lvel_.get(), lst_.get(), cl_uint(worlds));
    launch(ctx_, copy_k_, worlds);
}

void PolicyModel::enqueue_observe(Swarm& swarm) {
    const uint32_t n = swarm.agent_count(), worlds = swarm.worlds();
    swarm.ensure_grid();
    if (!blocks_current_) upload_world_blocks();
    obs_.reserve(ctx_, size_t(n) * worlds * weights_.obs_dim, "policy observations");
    qu_.reserve(ctx_, size_t(n) * worlds, "policy headings");
    set_args(headings_k_, swarm.positions().get(), swarm.velocities().get(), n, lst_.get(), qu_.get());
    launch_worlds(ctx_, headings_k_, n, worlds);
    // The walk's reach: every world's (a wider one only adds candidates
    // that fail every test, policy_observe.inc.cl).
    float search = 0.0f;
    for (uint32_t k = 0; k < worlds; ++k) {
        const PolicyModelConfig& c = worlds_[k];
        const float r_nbr = c.neighbor_radius > 0 ? c.neighbor_radius : c.r_coh;
        search = std::max(search, std::max(c.r_coh + c.body_radius, r_nbr));
    }
    const auto& c = config_;
    cl_uint i = 0;
    observe_k_.setArg(i++, swarm.positions().get());
    observe_k_.setArg(i++, qu_.get());
    observe_k_.setArg(i++, n);
    i = swarm.grid().set_world_grid_args(observe_k_, i);  // the cells of a world (unread with one)
    observe_k_.setArg(i++, lst_.get());
    observe_k_.setArg(i++, search);
    observe_k_.setArg(i++, block_.get());
    observe_k_.setArg(i++, box_c_.get());
    observe_k_.setArg(i++, box_h_.get());
    observe_k_.setArg(i++, cl_uint(c.obstacles.size()));
    observe_k_.setArg(i++, cl_int(weights_.efs ? 1 : 0));
    observe_k_.setArg(i++, cl_uint(weights_.obs_dim));
    observe_k_.setArg(i++, obs_.get());
    check_arg_count(observe_k_, i);
    // Two 42-float arrays per work-item (42 vectors with lanes): small
    // work-groups (buffer.hpp).
    if (lanes_ > 1) launch_worlds(ctx_, observe_k_, (size_t(n) + lanes_ - 1) / lanes_, worlds, 16);
    else launch_worlds(ctx_, observe_k_, n, worlds, 256);
}

void PolicyModel::enqueue_mlp(DeviceBuffer<float>& obs, uint32_t n, DeviceBuffer<float>& actions) {
    if (n == 0) return;
    if (tiled_) {
        enqueue_mlp_tiled(obs, n, actions);
        return;
    }
    const uint32_t tiles = (n + mlp_lanes_ - 1) / mlp_lanes_;
    const uint32_t chunk = std::min(tiles, kMlpChunkTiles);
    scratch_.reserve(ctx_, size_t(chunk) * 2 * max_width_ * mlp_lanes_, "policy MLP scratch");
    const auto& s = weights_.action_scale;
    for (uint32_t first = 0; first < tiles; first += chunk) {
        set_args(mlp_k_, obs.get(), n, cl_uint(weights_.obs_dim), first, params_.get(), layers_.get(),
                 cl_uint(weights_.layers.size()), cl_int(weights_.obs_mean.empty() ? 0 : 1), mean_off_, std_off_,
                 cl_float4{{s[0], s[1], s[2], s[3]}}, max_width_, scratch_.get(), actions.get());
        launch(ctx_, mlp_k_, std::min(chunk, tiles - first), 64);
    }
}

// One launch a layer over each chunk of agents: obs (agent-major) -> hidden
// buffers ([feature][agent], agent stride `stride`) -> actions[4 a + o].
void PolicyModel::enqueue_mlp_tiled(DeviceBuffer<float>& obs, uint32_t n, DeviceBuffer<float>& actions) {
    const uint32_t stride = uint32_t(std::min<size_t>((size_t(n) + kTiledTile - 1) / kTiledTile * kTiledTile, tiled_chunk_));
    const size_t hidden = size_t(std::max<uint32_t>(hidden_width_, 1)) * stride;
    hidden_a_.reserve(ctx_, hidden, "policy MLP activations");
    if (weights_.layers.size() > 2) hidden_b_.reserve(ctx_, hidden, "policy MLP activations");
    const auto& s = weights_.action_scale;
    const cl_float4 scale{{s[0], s[1], s[2], s[3]}};
    const cl_int norm = weights_.obs_mean.empty() ? 0 : 1;
    const size_t nlayers = weights_.layers.size();
    for (size_t first = 0; first < n; first += stride) {
        const uint32_t m = uint32_t(std::min<size_t>(stride, n - first));
        for (size_t L = 0; L < nlayers; ++L) {
            const cl_uint* row = &layer_table_[5 * L];
            const bool in_obs = L == 0, to_actions = L + 1 == nlayers;
            // Layer L reads hidden buffer (L - 1) % 2 and writes L % 2.
            cl::Buffer& x = in_obs ? obs.get() : (L % 2 == 1 ? hidden_a_.get() : hidden_b_.get());
            cl::Buffer& y = to_actions ? actions.get() : (L % 2 == 0 ? hidden_a_.get() : hidden_b_.get());
            set_args(tiled_k_, x, cl_uint(in_obs ? first : 0), cl_uint(in_obs ? weights_.obs_dim : 1),
                     cl_uint(in_obs ? 1 : stride), m, params_.get(), row[0], row[1], row[2], row[3], row[4],
                     cl_int(in_obs ? norm : 0), mean_off_, std_off_, y, cl_uint(to_actions ? first : 0),
                     cl_uint(to_actions ? 4 : 1), cl_uint(to_actions ? 1 : stride), cl_int(to_actions ? 1 : 0), scale);
            launch_groups_2d(ctx_, tiled_k_, (m + kTiledTile - 1) / kTiledTile, (row[1] + kTiledTile - 1) / kTiledTile,
                             kTiledLocal, kTiledLocal);
        }
    }
}

void PolicyModel::advance(Swarm& swarm, uint64_t) {
    const uint32_t n = swarm.agent_count(), worlds = swarm.worlds();
    const auto& c = config_;
    enqueue_leader_copy(worlds);
    if (n > 0) {
        enqueue_observe(swarm);
        actions_.reserve(ctx_, size_t(n) * worlds * 4, "policy actions");
        // Every world's agents in one batch: the MLP is per agent.
        enqueue_mlp(obs_, n * worlds, actions_);
    }
    // The leaders move (rl_env.cl, one a world), then the followers by the
    // actions of the state they observed: the environment's order.
    set_args(leader_k_, lpos_.get(), lvel_.get(), ctl_.get(), cl_uint(worlds),
             cl_int(c.leader_mode == PolicyLeaderMode::Joystick ? 0 : c.leader_mode == PolicyLeaderMode::Navigation ? 1 : 2),
             waypoints_.get(), cl_uint(c.waypoints.size()), wp_.get(), done_.get(), c.reach_radius, c.leader_du_max,
             c.leader_dq_max_deg * kDegToRad, c.u_max, swarm.config().dt);
    launch(ctx_, leader_k_, worlds);
    if (n > 0) {
        set_args(apply_k_, swarm.positions().get(), swarm.velocities().get(), actions_.get(), n, lst_.get(),
                 block_.get(), swarm.config().dt);
        launch_worlds(ctx_, apply_k_, n, worlds);
        swarm.positions_changed();
    }
}

StepStages PolicyModel::stages() const { return {}; }

void PolicyModel::observe(Swarm& swarm, std::vector<float>* obs, std::vector<float>* actions) {
    const uint32_t per_world = swarm.agent_count(), worlds = swarm.worlds();
    const uint32_t n = per_world * worlds;
    enqueue_leader_copy(worlds);
    if (n == 0) {
        if (obs) obs->clear();
        if (actions) actions->clear();
        return;
    }
    enqueue_observe(swarm);
    actions_.reserve(ctx_, size_t(n) * 4, "policy actions");
    enqueue_mlp(obs_, n, actions_);
    // Slot s of world k holds agent k n + ids[s] (ids count from 0 in each world).
    std::vector<cl_uint> ids(n);
    swarm.ids().download(ctx_, ids.data(), n);
    for (uint32_t s = 0; s < n; ++s) ids[s] += (s / per_world) * per_world;
    const uint32_t d = weights_.obs_dim;
    if (obs) {
        std::vector<float> by_slot(size_t(n) * d);
        obs_.download(ctx_, by_slot.data(), by_slot.size());
        obs->assign(by_slot.size(), 0.0f);
        for (uint32_t s = 0; s < n; ++s)
            std::copy_n(&by_slot[size_t(s) * d], d, &(*obs)[size_t(ids[s]) * d]);
    }
    if (actions) {
        std::vector<float> by_slot(size_t(n) * 4);
        actions_.download(ctx_, by_slot.data(), by_slot.size());
        actions->assign(by_slot.size(), 0.0f);
        for (uint32_t s = 0; s < n; ++s) std::copy_n(&by_slot[size_t(s) * 4], 4, &(*actions)[size_t(ids[s]) * 4]);
    }
}

void PolicyModel::observe_on_device(Swarm& swarm) {
    enqueue_leader_copy(swarm.worlds());
    if (swarm.agent_count() > 0) enqueue_observe(swarm);
    ctx_.queue().finish();
}

void PolicyModel::mlp_on_device(Swarm& swarm) {
    const uint32_t agents = swarm.agent_count() * swarm.worlds();
    require(obs_.size() >= size_t(agents) * weights_.obs_dim,
            "policy model mlp_on_device: no observations of this swarm on the device (observe_on_device first)");
    actions_.reserve(ctx_, size_t(agents) * 4, "policy actions");
    enqueue_mlp(obs_, agents, actions_);
    ctx_.queue().finish();
}

std::vector<float> PolicyModel::infer(const std::vector<float>& obs, uint32_t count) {
    require(obs.size() == size_t(count) * weights_.obs_dim, "policy model infer: obs size != count * obs_dim");
    std::vector<float> out(size_t(count) * 4);
    infer(obs.data(), count, out.data());
    return out;
}

void PolicyModel::infer(const float* obs, uint32_t count, float* actions) {
    if (!count) return;
    const size_t floats = size_t(count) * weights_.obs_dim;
    require(finite_all(obs, floats), "policy model infer: the observations must be finite");
    // The inputs of the next infer reuse these (a benchmark's repeated calls
    // time the MLP and the copies, not allocations).
    infer_obs_.reserve(ctx_, floats, "policy infer input");
    infer_actions_.reserve(ctx_, size_t(count) * 4, "policy infer actions");
    infer_obs_.upload(ctx_, obs, floats);
    enqueue_mlp(infer_obs_, count, infer_actions_);
    infer_actions_.download(ctx_, actions, size_t(count) * 4);
}

// Checkpoints: the descriptor (config and the weights file's bytes; the
// other worlds' parameters beside it) and, as state, each world's leader
// (position, (q, u), controls, waypoint index, done), world by world.
void PolicyModel::save_checkpoint(Swarm&, ByteWriter& descriptor, ByteWriter& state) {
    write_model_descriptor(descriptor, config_, *bytes_);
    const uint32_t worlds = worlds_.worlds();
    std::vector<cl_float4> p(worlds), v(worlds), ctl(worlds);
    std::vector<cl_uint> wp(worlds), done(worlds);
    lpos_.download(ctx_, p.data(), worlds);
    lvel_.download(ctx_, v.data(), worlds);
    ctl_.download(ctx_, ctl.data(), worlds);
    wp_.download(ctx_, wp.data(), worlds);
    done_.download(ctx_, done.data(), worlds);
    for (uint32_t w = 0; w < worlds; ++w) {
        for (const cl_float4* x : {&p[w], &v[w], &ctl[w]})
            for (int k = 0; k < 4; ++k) state.f32(x->s[k]);
        state.u32(wp[w]);
        state.u32(done[w]);
    }
}

void PolicyModel::restore_checkpoint(Swarm&, ByteReader& state) {
    const uint32_t worlds = worlds_.worlds();
    std::vector<cl_float4> p(worlds), v(worlds), ctl(worlds);
    std::vector<cl_uint> wp(worlds), done(worlds);
    for (uint32_t w = 0; w < worlds; ++w) {
        for (cl_float4* x : {&p[w], &v[w], &ctl[w]})
            for (int k = 0; k < 4; ++k) x->s[k] = state.f32();
        wp[w] = state.u32();
        done[w] = state.u32();
    }
    state.expect_end();
    for (uint32_t w = 0; w < worlds; ++w) {
        for (const cl_float4* x : {&p[w], &v[w], &ctl[w]})
            if (!finite_all(x->s, 4)) state.bad("the policy model's leader state is not finite");
        if (done[w] > 1 || (!config_.waypoints.empty() && wp[w] > config_.waypoints.size()) ||
            (config_.waypoints.empty() && wp[w] != 0))
            state.bad("the policy model's waypoint index is out of range");
    }
    lpos_.upload(ctx_, p.data(), worlds);
    lvel_.upload(ctx_, v.data(), worlds);
    ctl_.upload(ctx_, ctl.data(), worlds);
    wp_.upload(ctx_, wp.data(), worlds);
    done_.upload(ctx_, done.data(), worlds);
}

}  // namespace swarmcl
