#include "models/energy_model.hpp"

#include "models/model_descriptor.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <string>

#include "core/error.hpp"
#include "params/param_block.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {
namespace {

constexpr uint32_t kCentreChunks = 64;  // fixed: the reduction order depends only on n
constexpr uint32_t kGoalUnset = 0x7FFFFFFFu;
constexpr uint32_t kGoalBackward = 0x80000000u;
constexpr uint32_t kMaxCandidates = 4096;  // private arrays of the kernel

void check_stimuli(const std::vector<Stimulus>& stimuli) {
    require(stimuli.size() <= 1024, "energy model: more than 1024 stimuli");
    for (size_t s = 0; s < stimuli.size(); ++s) {
        const auto& st = stimuli[s];
        const std::string w = "energy model stimuli[" + std::to_string(s) + "]";
        for (int a = 0; a < 3; ++a)
            require(std::isfinite(st.position[a]) && std::isfinite(st.velocity[a]),
                    w + ": position and velocity must be finite");
        require(st.kind == Stimulus::Kind::Attract || (std::isfinite(st.d_danger) && st.d_danger > 0.0f),
                w + ": d_danger must be a finite number > 0");
    }
}

void check_keypoints(const std::vector<std::array<float, 3>>& kp) {
    require(kp.empty() || kp.size() >= 2,
            "energy model keypoints: " + std::to_string(kp.size()) + " given, a curve needs at least 2");
    require(kp.size() <= 65536, "energy model keypoints: more than 65536");
    for (size_t k = 0; k < kp.size(); ++k)
        for (int a = 0; a < 3; ++a)
            require(std::isfinite(kp[k][a]), "energy model keypoints[" + std::to_string(k) + "] is not finite");
}

// launch_chunks over (chunks, worlds): world get_global_id(1)'s chunks in
// the same order as alone (one world: launch_chunks exactly).
void launch_chunks_worlds(Context& ctx, cl::Kernel& kernel, size_t chunks, size_t worlds) {
    if (worlds == 1) return launch_chunks(ctx, kernel, chunks);
    if (!chunks) return;
    const bool cpu = ctx.device().cpu_profile;
    ctx.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(chunks, worlds),
                                     cpu ? cl::NDRange(1, 1) : cl::NullRange);
}

}  // namespace

bool EnergyModel::taylor_for(const EnergyModelConfig& c, float dt) const {
    return !c.exact_attraction && c.rho / c.d_att1 * vmax_ * dt <= 0.4f;
}

void EnergyModel::validate(const EnergyModelConfig& c) {
    // Each parameter's range from the table ("energy model weights.rep = -1
    // is outside [0, inf)"), then what the table cannot say alone.
    energy_param_table().validate(const_cast<EnergyModelConfig*>(&c));
    require(c.d_att1 >= c.d_rep, "energy model d_att1 must be a finite number >= d_rep");
    require(c.d_att2 >= c.d_att1, "energy model d_att2 must be a finite number >= d_att1");
    check_stimuli(c.stimuli);
    check_keypoints(c.keypoints);
    NoiseField::validate(c.noise);
}

EnergyModel::EnergyModel(Swarm& swarm, EnergyModelConfig config, std::shared_ptr<const Dataset> dataset)
    : ctx_(swarm.context()),
      config_(std::move(config)),
      worlds_(energy_param_table(), config_, swarm.worlds()),
      world_count_(swarm.worlds()),
      dataset_(std::move(dataset)) {
    require(dataset_ != nullptr, "energy model: no dataset");
    dataset_->validate("energy model dataset");
    validate(config_);
    Context& ctx = swarm.context();
    const Dataset& d = *dataset_;
    // The widest candidate range of any speed group.
    const uint32_t G = d.groups();
    for (uint32_t g = 0; g < G; ++g) {
        const uint32_t lo = g > config_.span ? g - config_.span : 0u;
        const uint32_t hi = std::min(G, g + config_.span + 1);
        max_cand_ = std::max(max_cand_, d.group_start[hi] - d.group_start[lo]);
    }
    if (max_cand_ > kMaxCandidates)
        fail(Status::InvalidArgument, "energy model: " + std::to_string(max_cand_) +
                                          " candidates per agent (speed groups x span too wide; at most " +
                                          std::to_string(kMaxCandidates) + "): use more groups or a smaller span");
    accel_time_ = config_.accel_time > 0.0f ? config_.accel_time
                                            : (d.frame_time > 0.0 ? float(d.frame_time) : 0.01f);
    check_noise_for_world_domains(config_.noise, swarm.world_domains(), "energy model noise");
    noise_ = std::make_unique<NoiseField>(ctx, config_.noise, &swarm.config().domain_min,
                                          &swarm.config().domain_max);
    for (const auto& v : d.v) vmax_ = std::max(vmax_, std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
    taylor_ = taylor_for(config_, swarm.config().dt);
    // f_N for all agents at once by the noise module's explicit-width kernel
    // (noise_sample_w, width() agents per work-item) where it covers this
    // field (CPU devices; noise_->width() > 1: curl, Perlin, baked, fields
    // of position and time only, so slot order is as good as agent id),
    // else per agent in energy_select (the random types are keyed by id).
    // The scalar curl noise was about 14% of energy_select on the 2-core
    // AVX2 PoCL CPU (docs/energy-model.md, section 6).
    noise_pre_ = noise_->width() > 1;
    const std::string defines = noise_->defines() + " -DEM_MAX_CAND=" + std::to_string(max_cand_) +
                                (noise_pre_ ? " -DEM_NOISE_PRE" : "") +
                                (taylor_ ? " -DEM_TAYLOR_OA" : "") + " -DEM_KEEP_OUT=" +
                                (config_.keep_out ? "1" : "0") + energy_param_table().device_defines("ENERGY") +
                                world_defines(world_count_);
    select_ = ctx.kernel("energy_model.cl", "energy_select", defines);
    terms_ = ctx.kernel("energy_model.cl", "energy_select", defines + " -DEM_TERMS");
    prepare_ = ctx.kernel("energy_model.cl", "energy_prepare", defines);
    if (noise_pre_) noise_sample_ = noise_->sample_kernel();
    centre_final_ = ctx.kernel("energy_model.cl", "energy_centre_final", defines);

    // Velocities (float4, read for the chosen sample), and the planes of
    // kernels/energy_model.cl (EM_P_*: v, v^, a^, |a|; unit vectors and
    // lengths that every agent would otherwise recompute for every
    // candidate), each padded by 16 zeros for the kernel's 16-wide chunks.
    constexpr uint32_t kPlanes = 10, kLanes = 16;
    std::vector<cl_float4> v(d.size());
    ds_stride_ = d.size() + kLanes;
    std::vector<cl_float> planes(size_t(kPlanes) * ds_stride_, 0.0f);
    auto unit_len = [](const std::array<float, 3>& x) {
        const double l = std::sqrt(double(x[0]) * x[0] + double(x[1]) * x[1] + double(x[2]) * x[2]);
        const double s = l > 0.0 ? 1.0 / l : 0.0;
        return std::array<float, 4>{float(x[0] * s), float(x[1] * s), float(x[2] * s), float(l)};
    };
    for (uint32_t i = 0; i < d.size(); ++i) {
        v[i] = {{d.v[i][0], d.v[i][1], d.v[i][2], 0.0f}};
        const auto vh = unit_len(d.v[i]), ah = unit_len(d.a[i]);
        const float row[kPlanes] = {d.v[i][0], d.v[i][1], d.v[i][2], vh[0], vh[1], vh[2], ah[0], ah[1], ah[2], ah[3]};
        for (uint32_t k = 0; k < kPlanes; ++k) planes[size_t(k) * ds_stride_ + i] = row[k];
    }
    std::vector<cl_float> gmin(G);
    for (uint32_t g = 0; g < G; ++g) {
        const auto& s = d.v[d.group_start[g]];
        gmin[g] = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);  // as the kernel's em_len
    }
    dv_.allocate(ctx, d.size(), "dataset velocities");
    dv_.upload(ctx, v.data(), v.size());
    ds_.allocate(ctx, planes.size(), "dataset planes");
    ds_.upload(ctx, planes.data(), planes.size());
    group_start_.allocate(ctx, G + 1, "dataset groups");
    group_start_.upload(ctx, d.group_start.data(), G + 1);
    group_min_speed_.allocate(ctx, G, "dataset group speeds");
    group_min_speed_.upload(ctx, gmin.data(), G);
    // Worlds: a centre and kCentreChunks partial sums per world.
    centre_.allocate(ctx, world_count_, "swarm centre");
    centre_.fill(ctx, cl_float4{{0, 0, 0, 0}}, world_count_);
    partial_.allocate(ctx, size_t(kCentreChunks) * world_count_, "swarm centre partial sums");
    capacity_ = swarm.config().capacity;
    const size_t slots = size_t(capacity_) * world_count_;  // every world's
    // x, y, z planes of the positions, each padded by 16 slots at both ends
    // (energy_select reads 16-slot windows that may start before slot 0 or
    // end past the last agent, lanes masked); zeros, never read as positions.
    // With worlds, world k's slots follow world k - 1's: the windows of
    // world k may read world k - 1's last slots, masked as the padding is.
    pxyz_stride_ = uint32_t(slots + 2 * kLanes);
    pxyz_.allocate(ctx, 3 * size_t(pxyz_stride_), "position planes");
    pxyz_.fill(ctx, 0.0f, 3 * size_t(pxyz_stride_));
    noise_buf_.allocate(ctx, noise_pre_ ? slots : 1, "noise velocities");
    vel_out_.allocate(ctx, slots, "energy model velocities");
    // Each world's goals by its agents' ids, world k's from k capacity_.
    goal_.allocate(ctx, size_t(capacity_) * world_count_, "keypoint goals");
    // A noise block per world (world k's at k NOISE_BLOCK_FLOATS), each
    // world's noise parameters as set_world_param leaves them.
    const std::vector<cl_float> block = noise_->block();
    for (uint32_t k = 0; k < world_count_; ++k) noise_host_.insert(noise_host_.end(), block.begin(), block.end());
    noise_prims_host_ = world_noise_prims(ctx, swarm.world_domains(), config_.noise, *noise_, "energy model noise", noise_host_);
    upload_noise_blocks();
    upload_params();
    set_keypoints(config_.keypoints, config_.keypoints_closed);
    set_stimuli(config_.stimuli);
}

void EnergyModel::reset_goals(uint32_t capacity) {
    std::vector<cl_uint> g(size_t(capacity) * world_count_);
    for (size_t slot = 0; slot < g.size(); ++slot) {
        const uint32_t id = uint32_t(slot % capacity);  // the id within its world
        g[slot] = kGoalUnset | ((config_.bidirectional && (id & 1u)) ? kGoalBackward : 0u);
    }
    goal_.upload(ctx_, g.data(), g.size());
}

void EnergyModel::upload_params() {
    if (world_count_ == 1) {
        params_ = upload_param_block(ctx_, energy_param_table(), &config_);
        return;
    }
    const std::vector<float> blocks = worlds_.device_blocks();  // world k's at k ENERGY_FLOATS
    params_.reserve(ctx_, blocks.size(), "model parameter blocks");
    params_.upload(ctx_, blocks.data(), blocks.size());
}

void EnergyModel::upload_noise_blocks() {
    noise_blocks_.reserve(ctx_, noise_host_.size(), "noise parameter blocks");
    noise_blocks_.upload(ctx_, noise_host_.data(), noise_host_.size());
    noise_prims_.reserve(ctx_, noise_prims_host_.size(), "noise boundaries of the worlds");
    noise_prims_.upload(ctx_, noise_prims_host_.data(), noise_prims_host_.size());
    if (world_count_ == 1 || !noise_pre_) return;
    // noise_sample_w reads one block: each world's apart (sample_noise).
    const size_t floats = noise_->block().size(), prims = noise_->prims().size();
    noise_world_blocks_.clear();
    noise_world_prims_.clear();
    for (uint32_t k = 0; k < world_count_; ++k) {
        DeviceBuffer<cl_float> b(ctx_, floats, "noise parameter block");
        b.upload(ctx_, noise_host_.data() + k * floats, floats);
        noise_world_blocks_.push_back(std::move(b));
        DeviceBuffer<cl_float4> p(ctx_, std::max<size_t>(prims, 2), "noise boundaries");
        p.upload(ctx_, noise_prims_host_.data() + k * prims, prims);
        noise_world_prims_.push_back(std::move(p));
    }
}

void EnergyModel::set_stimuli(std::vector<Stimulus> stimuli) {
    check_stimuli(stimuli);
    config_.stimuli = std::move(stimuli);
    // Positions at t = 0 and velocities: the kernel moves them on
    // (em_stimulus), so the step uploads nothing.  Kind in w (0 attract, 1 startle).
    std::vector<cl_float4> s(std::max<size_t>(1, 2 * config_.stimuli.size()), cl_float4{{0, 0, 0, 0}});
    for (size_t i = 0; i < config_.stimuli.size(); ++i) {
        const Stimulus& st = config_.stimuli[i];
        s[2 * i] = {{st.position[0], st.position[1], st.position[2],
                     st.kind == Stimulus::Kind::Attract ? 0.0f : 1.0f}};
        s[2 * i + 1] = {{st.d_danger, st.velocity[0], st.velocity[1], st.velocity[2]}};
    }
    stim_.reserve(ctx_, s.size(), "stimuli");
    stim_.upload(ctx_, s.data(), s.size());
}

void EnergyModel::set_keypoints(std::vector<std::array<float, 3>> keypoints, bool closed) {
    check_keypoints(keypoints);
    std::vector<cl_float4> k(std::max<size_t>(1, keypoints.size()), cl_float4{{0, 0, 0, 0}});
    for (size_t i = 0; i < keypoints.size(); ++i) k[i] = {{keypoints[i][0], keypoints[i][1], keypoints[i][2], 0.0f}};
    DeviceBuffer<cl_float4> buf(ctx_, k.size(), "keypoints");
    buf.upload(ctx_, k.data(), k.size());
    kp_ = std::move(buf);
    config_.keypoints = std::move(keypoints);
    const bool closed_changed = config_.keypoints_closed != closed;
    config_.keypoints_closed = closed;
    if (closed_changed) {  // keypoints_closed is in the block: every world's
        const std::vector<double> v(world_count_, closed ? 1.0 : 0.0);
        worlds_.set("keypoints_closed", v.data(), v.size());
        upload_params();
    }
    reset_goals(capacity_);
}

void EnergyModel::prepare(Swarm& swarm) {
    const uint32_t n = swarm.agent_count();
    const bool fixed = config_.has_fixed_centre;
    if (fixed && fixed_centre_n_ != n) {
        // Uploaded again only when the agent count (w) or a world's centre
        // changes: no host wait per step.  One per world.
        std::vector<cl_float4> v(world_count_);
        for (uint32_t k = 0; k < world_count_; ++k) {
            const auto& c = worlds_[k].fixed_centre;
            v[k] = cl_float4{{c[0], c[1], c[2], float(n)}};
        }
        centre_.upload(ctx_, v.data(), world_count_);
        fixed_centre_n_ = n;
    }
    // Position planes always; the centre's partial sums unless it is fixed
    // (has_fixed_centre is the same in every world).
    const uint32_t chunk = std::max<uint32_t>(1, (n + kCentreChunks - 1) / kCentreChunks);
    set_args(prepare_, swarm.positions().get(), n, chunk, cl_uint(fixed ? 0 : 1), kCentreChunks, partial_.get(),
             pxyz_.get(), cl_uint(pxyz_stride_));
    launch_chunks_worlds(ctx_, prepare_, kCentreChunks, world_count_);
    if (fixed) return;
    set_args(centre_final_, partial_.get(), kCentreChunks, centre_.get());
    if (world_count_ == 1)
        launch(ctx_, centre_final_, 1);
    else
        launch_chunks_worlds(ctx_, centre_final_, 1, world_count_);
}

void EnergyModel::sample_noise(Swarm& swarm, uint64_t step) {
    const uint32_t n = swarm.agent_count();
    if (!noise_pre_ || !n) return;
    // Time and step as Swarm::set_step_args passes them to energy_select.
    const float t = float(double(step) * swarm.config().dt);
    if (world_count_ == 1) {
        noise_->enqueue_sample(noise_sample_, swarm.positions(), n, t, uint32_t(step), noise_buf_);
        return;
    }
    // Worlds: each world's positions from point 0 with its own block, so
    // noise_sample_w groups its points as alone, then into its slots.
    const size_t bytes = size_t(n) * sizeof(cl_float4);
    noise_pts_.reserve(ctx_, n, "noise sample points");
    noise_one_.reserve(ctx_, n, "noise velocities");
    for (uint32_t k = 0; k < world_count_; ++k) {
        copy_buffer(ctx_, swarm.positions().get(), noise_pts_.get(), k * bytes, 0, bytes);
        cl_uint i = 0;
        noise_sample_.setArg(i++, noise_pts_.get());
        noise_sample_.setArg(i++, cl_uint(n));
        noise_sample_.setArg(i++, t);
        noise_sample_.setArg(i++, cl_uint(step));
        const cl_uint block_at = i;
        i = noise_->set_args(noise_sample_, i);
        noise_sample_.setArg(block_at, noise_world_blocks_[k].get());
        noise_sample_.setArg(block_at + 1, noise_world_prims_[k].get());
        noise_sample_.setArg(i++, noise_one_.get());
        check_arg_count(noise_sample_, i);
        launch(ctx_, noise_sample_, (size_t(n) + noise_->width() - 1) / noise_->width());
        copy_buffer(ctx_, noise_one_.get(), noise_buf_.get(), 0, k * bytes, bytes);
    }
}

cl_uint EnergyModel::set_common_args(cl::Kernel& k, Swarm& swarm, uint64_t step) {
    // energy_select's argument groups in order (kernels/energy_model.cl,
    // EM_SELECT_PARAMS): state and time, dataset, model parameters, scene,
    // prepared planes, grid, noise; the caller adds the outputs and checks
    // the count.
    const auto& c = config_;
    cl_uint i = swarm.set_step_args(k, step);
    k.setArg(i++, dv_.get());
    k.setArg(i++, ds_.get());
    k.setArg(i++, cl_uint(ds_stride_));
    k.setArg(i++, group_start_.get());
    k.setArg(i++, group_min_speed_.get());
    k.setArg(i++, cl_uint(dataset_->groups()));
    k.setArg(i++, centre_.get());
    // The weights, rho, radii, span, danger_horizon, keypoint_reach and
    // keypoints_closed: the parameter block; accel_time derived (0: the
    // dataset's frame time).
    k.setArg(i++, params_.get());
    k.setArg(i++, accel_time_);
    k.setArg(i++, stim_.get());
    k.setArg(i++, cl_uint(c.stimuli.size()));
    k.setArg(i++, kp_.get());
    k.setArg(i++, cl_uint(c.keypoints.size()));
    k.setArg(i++, goal_.get());
    k.setArg(i++, cl_uint(capacity_));  // world k's goals from k capacity_
    k.setArg(i++, pxyz_.get());
    k.setArg(i++, cl_uint(pxyz_stride_));
    k.setArg(i++, noise_buf_.get());
    i = swarm.grid().set_world_grid_args(k, i);  // the cells of a world (unread with one)
    const cl_uint noise_at = i;
    i = noise_->set_args(k, i);
    k.setArg(noise_at, noise_blocks_.get());      // the worlds' blocks (world 0's with one)
    k.setArg(noise_at + 1, noise_prims_.get());  // and their boundaries
    return i;
}

void EnergyModel::launch_per_agent(cl::Kernel& k, uint32_t n) {
    // CPU devices: work-groups of at most 64 agents (launch()'s policy
    // otherwise): energy_select's private candidate state for 4096 agents
    // per group overflowed PoCL's thread stack at 100k agents.
    launch_worlds(ctx_, k, n, world_count_, 64);
}

void EnergyModel::advance(Swarm& swarm, uint64_t step) {
    const uint32_t n = swarm.agent_count();
    swarm.ensure_grid();  // agents in cell order: neighbours via the grid
    prepare(swarm);
    sample_noise(swarm, step);
    cl_uint i = set_common_args(select_, swarm, step);
    select_.setArg(i++, swarm.scratch().get());
    select_.setArg(i++, vel_out_.get());
    check_arg_count(select_, i);
    launch_per_agent(select_, n);
    copy_buffer(ctx_, vel_out_.get(), swarm.velocities().get(), 0, 0, swarm.total_agents() * sizeof(cl_float4));
    swarm.swap_positions_with_scratch();
}

EnergyTerms EnergyModel::evaluate(Swarm& swarm, uint64_t step) {
    // The terms are written per agent id of one swarm.
    swarm.require_one_world("the energy model's evaluate (every term of every candidate)");
    const uint32_t n = swarm.agent_count();
    swarm.ensure_grid();
    prepare(swarm);
    sample_noise(swarm, step);
    DeviceBuffer<cl_float> terms(ctx_, size_t(std::max(n, 1u)) * max_cand_ * 8, "energy terms");
    DeviceBuffer<cl_uint> chosen(ctx_, std::max(n, 1u), "chosen samples");
    DeviceBuffer<cl_uint> range(ctx_, 2 * size_t(std::max(n, 1u)), "candidate ranges");
    terms.fill(ctx_, 0.0f, size_t(std::max(n, 1u)) * max_cand_ * 8);
    cl_uint i = set_common_args(terms_, swarm, step);
    terms_.setArg(i++, terms.get());
    terms_.setArg(i++, chosen.get());
    terms_.setArg(i++, range.get());
    check_arg_count(terms_, i);
    launch_per_agent(terms_, n);
    EnergyTerms out;
    out.terms.resize(size_t(n) * max_cand_ * 8);
    out.chosen.resize(n);
    std::vector<cl_uint> r(2 * size_t(n));
    terms.download(ctx_, out.terms.data(), out.terms.size());
    chosen.download(ctx_, out.chosen.data(), n);
    range.download(ctx_, r.data(), r.size());
    for (uint32_t a = 0; a < n; ++a) {
        out.first.push_back(r[2 * a]);
        out.last.push_back(r[2 * a + 1]);
    }
    return out;
}

void EnergyModel::goals(Swarm& swarm, std::vector<int32_t>& goal, std::vector<uint8_t>& backward) {
    const uint32_t n = swarm.agent_count();
    std::vector<cl_uint> all(std::max<size_t>(size_t(capacity_) * world_count_, 1));
    goal_.download(ctx_, all.data(), size_t(capacity_) * world_count_);
    goal.resize(size_t(n) * world_count_);
    backward.resize(goal.size());
    for (size_t a = 0; a < goal.size(); ++a) {  // world by world, each world's ids
        const cl_uint g = all[(a / std::max(n, 1u)) * capacity_ + a % std::max(n, 1u)];
        const uint32_t k = g & ~kGoalBackward;
        goal[a] = k == kGoalUnset ? -1 : int32_t(k);
        backward[a] = (g & kGoalBackward) ? 1 : 0;
    }
}

std::array<float, 4> EnergyModel::centre(Swarm&, uint32_t world) {
    require(world < world_count_, "energy model centre: world " + std::to_string(world) + " of " +
                                      std::to_string(world_count_));
    std::vector<cl_float4> c(world_count_);
    centre_.download(ctx_, c.data(), world_count_);
    return {c[world].s[0], c[world].s[1], c[world].s[2], c[world].s[3]};
}

void EnergyModel::set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) {
    // What selects a kernel (EM_KEEP_OUT, EM_MAX_CAND from span, the noise's
    // defines) or what the host uses once for every world (accel_time is one
    // kernel argument, bidirectional sets the goals, has_fixed_centre whether
    // the centre is reduced at all) is one for every world in the table,
    // checked by worlds_.set before anything changes.
    const bool noise = key.compare(0, 6, "noise.") == 0;
    std::vector<cl_float> noise_next = noise_host_;
    std::vector<cl_float4> prims_next = noise_prims_host_;
    const float dt = swarm.config().dt;
    worlds_.set(key, values, count, [&](const EnergyModelConfig& changed, uint32_t k) {
        validate(changed);  // what the table cannot say (d_rep <= d_att1 <= d_att2)
        // rho, d_att1 (and exact_attraction) choose Eq. 6's expansion
        // (EM_TAYLOR_OA) for the kernel of every world.
        if (taylor_for(changed, dt) != taylor_)
            fail(Status::InvalidArgument, "energy model " + key + ": this value " +
                                              (taylor_ ? "turns off" : "turns on") +
                                              " the attraction's expansion (rho / d_att1 x the fastest sample x "
                                              "dt <= 0.4), which is the same kernel in every world");
        if (!noise) return;
        write_world_noise_block(swarm.context(), changed.noise, &swarm.world_domain(k).min,
                                &swarm.world_domain(k).max, *noise_, "energy model " + key, noise_next, k,
                                &prims_next);
    });
    noise_host_ = std::move(noise_next);
    noise_prims_host_ = std::move(prims_next);
    // config_ is world 0's; the stimuli and keypoints are not table rows.
    EnergyModelConfig first = worlds_[0];
    first.stimuli = std::move(config_.stimuli);
    first.keypoints = std::move(config_.keypoints);
    config_ = std::move(first);
    upload_params();
    upload_noise_blocks();
    fixed_centre_n_ = 0xFFFFFFFFu;  // the fixed centres again at the next step
}

std::vector<double> EnergyModel::world_param(const std::string& key) const { return worlds_.get(key); }

// The dataset goes into the descriptor itself; stimuli and keypoints as
// they are now are in config_.  The state: each agent's keypoint goal (by
// agent id, the capacity's entries).  The swarm centre is recomputed (or
// uploaded, when fixed) at every step before it is used.
void EnergyModel::save_checkpoint(Swarm&, ByteWriter& descriptor, ByteWriter& state) {
    write_model_descriptor(descriptor, config_, *dataset_);
    std::vector<cl_uint> g(size_t(capacity_) * world_count_);
    goal_.download(ctx_, g.data(), g.size());
    state.u64(g.size());
    for (cl_uint v : g) state.u32(v);
}
void EnergyModel::restore_checkpoint(Swarm&, ByteReader& state) {
    const uint64_t count = state.count(4);
    const size_t want = size_t(capacity_) * world_count_;
    if (count != want)
        state.bad(std::to_string(count) + " keypoint goals for a capacity of " + std::to_string(capacity_) + " x " +
                  std::to_string(world_count_) + " worlds");
    std::vector<cl_uint> g(want);
    for (cl_uint& v : g) {
        v = state.u32();
        // The kernel indexes the keypoints with it.
        const uint32_t k = v & ~kGoalBackward;
        if (k != kGoalUnset && k >= config_.keypoints.size())
            state.bad("keypoint goal " + std::to_string(k) + " of " + std::to_string(config_.keypoints.size()));
    }
    state.expect_end();
    goal_.upload(ctx_, g.data(), g.size());
}

}  // namespace swarmcl
