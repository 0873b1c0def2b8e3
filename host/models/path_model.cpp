#include "models/path_model.hpp"

#include "models/model_checkpoint.hpp"

#include <chrono>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

PathModel::PathModel(Swarm& swarm, PathModelConfig config)
    : config_(std::move(config)), ctx_(swarm.context()) {
    const auto t0 = std::chrono::steady_clock::now();
    auto& c = config_;
    require(std::isfinite(c.speed) && c.speed >= 0.0f, "path model speed (s0) must be a finite number >= 0");
    require(std::isfinite(c.goal_falloff) && c.goal_falloff >= 0.0f, "path model goal_falloff must be a finite number >= 0");
    require(std::isfinite(c.min_distance) && c.min_distance >= 0.0f,
            "path model min_distance must be a finite number >= 0 (0: off)");
    require(!c.groups.empty() && c.groups.size() <= 64, "path model needs 1 to 64 groups, each with its goals");
    require(c.waypoints.empty() || c.waypoint_every > 0, "path model waypoint_every must be >= 1");
    for (const auto& w : c.waypoints)
        require(std::isfinite(w[0]) && std::isfinite(w[1]) && std::isfinite(w[2]), "path model waypoints must be finite");
    if (!c.has_grid_box) {
        c.grid_min = swarm.config().domain_min;
        c.grid_max = swarm.config().domain_max;
    }
    grid_ = make_grid(c.grid_min, c.grid_max, c.resolution, "path model grid", uint64_t(1) << 26);
    // §5.1: obstacles -> signed distance -> repulsion; Eq. 4/7 slowness.
    if (!c.obstacles.empty()) {
        const SdfGrid sdf = compute_sdf(ctx_, merged(c.obstacles), grid_);
        phi_ = sdf.phi;
    }
    slowness_ = cost_slowness(grid_, phi_, c.weights);
    for (size_t g = 0; g < c.groups.size(); ++g) {
        try {
            check_goals(grid_, c.groups[g].goals, slowness_);
        } catch (const Error& e) {
            throw Error(e.status(), "path model group " + std::to_string(g) + ": " + e.what());
        }
    }
    // The mesh shapes the curl noise when the kernel can assemble it (curl
    // with analytic derivatives); other noise types are used as they are.
    std::vector<float> phi_upload(phi_);
    bool any_mesh = false;
    for (float& v : phi_upload)
        if (std::isfinite(v)) any_mesh = true;
        else v = 1e20f;  // no mesh in reach: "far"
    const bool mesh_noise = any_mesh && c.noise.type == NoiseType::Curl && !c.noise.finite_difference;
    NoiseConfig nc = c.noise;
    if (!nc.has_region()) nc.region_min = swarm.config().domain_min, nc.region_max = swarm.config().domain_max;
    NoiseField::validate(nc);  // as given (what can be baked), before the mesh-aware bake takes over
    if (mesh_noise) nc.baked = false;  // baked below, with the mesh
    noise_ = std::make_unique<NoiseField>(ctx_, nc, &swarm.config().domain_min, &swarm.config().domain_max);
    std::string defines = noise_->defines();
    if (mesh_noise) {
        // The procedural curl path of noise_field.cl with every boundary, no wide kernels.
        defines = "-DNOISE_KIND=0 -DNOISE_TIMED=" + std::string(nc.time_scale > 0 ? "1" : "0") + " -DPATH_MESH=1";
    }
    phi_dev_.allocate(ctx_, phi_upload.empty() ? 1 : phi_upload.size(), "path model signed distance");
    if (!phi_upload.empty()) phi_dev_.upload(ctx_, phi_upload.data(), phi_upload.size());
    dirs_.allocate(ctx_, grid_.count() * c.groups.size(), "path model directions");
    std::vector<cl_uint> ends(c.groups.size());
    uint64_t end = 0;
    for (size_t g = 0; g < c.groups.size(); ++g) {
        end += c.groups[g].agents;
        ends[g] = cl_uint(std::min<uint64_t>(end, 0xFFFFFFFFu));
    }
    group_end_.allocate(ctx_, ends.size(), "path model groups");
    group_end_.upload(ctx_, ends.data(), ends.size());
    costs_.resize(c.groups.size());
    for (uint32_t g = 0; g < c.groups.size(); ++g) {
        costs_[g] = solve_cost(grid_, slowness_, c.groups[g].goals, c.second_order);
        upload_directions(g);
    }
    vl_.allocate(ctx_, 1, "baked local field");
    if (mesh_noise && c.noise.baked) {
        bake_local_field(defines);
        defines += " -DPATH_BAKED=1";
        // CPU devices: SWCL_W agents per work-item (path_model_advance_w).
        width_ = noise_->preferred_width();
        if (width_ > 1) defines += " -DNOISE_WIDTH=" + std::to_string(width_);
    }
    advance_ = ctx_.kernel("path_model.cl", width_ > 1 ? "path_model_advance_w" : "path_model_advance", defines);
    ctx_.queue().finish();
    preprocess_seconds_ = seconds_since(t0);
}

void PathModel::bake_local_field(const std::string& defines) {
    // The noise's bake grid over its region (NoiseField's bake), with the mesh.
    const BakeGrid g = bake_grid(noise_->config());
    vl_min_ = g.min;
    vl_cell_ = g.cell;
    vl_dims_ = g.dims;
    cl::Kernel k = ctx_.kernel("path_model.cl", "path_noise_bake", defines);
    cl_uint i = noise_->set_args(k, 0);
    k.setArg(i++, phi_dev_.get());
    k.setArg(i++, grid_dims_arg());
    k.setArg(i++, grid_origin_arg());
    k.setArg(i++, vl_min_);
    k.setArg(i++, vl_cell_);
    k.setArg(i++, vl_dims_);
    vl_ = bake_nodes(ctx_, k, i, g, "baked local field");
}

void PathModel::upload_directions(uint32_t group) {
    std::vector<cl_float4> d(grid_.count());
    direction_field(grid_, costs_[group], phi_, reinterpret_cast<float*>(d.data()));
    ctx_.queue().enqueueWriteBuffer(dirs_.get(), CL_TRUE, size_t(group) * grid_.count() * sizeof(cl_float4),
                                    d.size() * sizeof(cl_float4), d.data());
}

double PathModel::set_goals(uint32_t group, std::vector<Goal> goals) {
    const auto t0 = std::chrono::steady_clock::now();
    require(group < config_.groups.size(), "path model: group " + std::to_string(group) + " does not exist");
    std::vector<double> cost = solve_cost(grid_, slowness_, goals, config_.second_order);  // validates
    costs_[group] = std::move(cost);
    config_.groups[group].goals = std::move(goals);
    upload_directions(group);
    const double t = seconds_since(t0);
    ++recomputes_;
    recompute_seconds_ += t;
    return t;
}

void PathModel::advance(Swarm& swarm, uint64_t step) {
    if (!config_.waypoints.empty() && step > 0 && step % config_.waypoint_every == 0) {
        const auto& w = config_.waypoints[(step / config_.waypoint_every - 1) % config_.waypoints.size()];
        std::vector<Goal> goals = config_.groups[0].goals;
        // The first goal moves to the waypoint, the others keep their offsets to it.
        const std::array<float, 3> shift{w[0] - goals[0].center[0], w[1] - goals[0].center[1], w[2] - goals[0].center[2]};
        for (Goal& g : goals)
            for (int a = 0; a < 3; ++a) g.center[a] += shift[a];
        set_goals(0, std::move(goals));
    }
    const uint32_t n = swarm.agent_count();
    cl_uint i = swarm.set_step_args(advance_, step);
    i = noise_->set_args(advance_, i);
    advance_.setArg(i++, dirs_.get());
    advance_.setArg(i++, grid_dims_arg());
    advance_.setArg(i++, grid_origin_arg());
    advance_.setArg(i++, group_end_.get());
    advance_.setArg(i++, cl_uint(config_.groups.size()));
    advance_.setArg(i++, config_.speed);
    advance_.setArg(i++, phi_dev_.get());
    // The ramp compares the cost with A * falloff (cost per metre of free path: A).
    advance_.setArg(i++, config_.goal_falloff > 0.0f ? float(1.0 / (config_.weights.A * config_.goal_falloff)) : 0.0f);
    advance_.setArg(i++, vl_.get());
    advance_.setArg(i++, vl_min_);
    advance_.setArg(i++, vl_cell_);
    advance_.setArg(i++, vl_dims_);
    check_arg_count(advance_, i);
    launch(ctx_, advance_, (size_t(n) + width_ - 1) / width_);
    swarm.positions_changed();
}

StepStages PathModel::stages() const {
    StepStages s;
    s.min_distance = config_.min_distance;
    s.seed = config_.noise.seed;
    s.stats = true;
    return s;
}

// The goals as they are now are in the descriptor (config_.groups: moved by
// set_goals and the waypoints); the constructor solves their cost fields
// with the same code as set_goals.  The state: the recomputation counters.
void PathModel::save_checkpoint(Swarm&, ByteWriter& descriptor, ByteWriter& state) {
    write_model_descriptor(descriptor, config_);
    state.u32(recomputes_);
    state.f64(recompute_seconds_);
}
void PathModel::restore_checkpoint(Swarm&, ByteReader& state) {
    recomputes_ = state.u32();
    recompute_seconds_ = state.f64();
    state.expect_end();
}

}  // namespace swarmcl
