#include "models/path_model.hpp"

#include "models/model_descriptor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "params/param_block.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

PathModel::PathModel(Swarm& swarm, PathModelConfig config)
    : config_(std::move(config)), ctx_(swarm.context()),
      domain_min_(swarm.config().domain_min), domain_max_(swarm.config().domain_max),
      worlds_(path_param_table(), PathModelConfig{}, 1) {
    const auto t0 = std::chrono::steady_clock::now();
    auto& c = config_;
    // Each parameter's range: path_param_table() ("path model speed = -1 is
    // outside [0, inf) (m/s)"); what one row cannot say follows.
    path_param_table().validate(&c);
    // The path field's grid and the noise cover one domain for every world.
    swarm.require_one_domain("the path model");
    require(!c.groups.empty() && c.groups.size() <= 64, "path model needs 1 to 64 groups, each with its goals");
    // Targets move goals and rebake the noise while it runs: on worlds they
    // are one for every world (retarget_worlds), and a noise baked with them
    // would be rebaked per world: refused.
    require(swarm.worlds() == 1 || c.targets.empty() || !c.noise.baked,
            "path model chasing targets with a baked noise do not run on a swarm of several worlds (" +
                std::to_string(swarm.worlds()) + "); bake the noise off");
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
    for (size_t i = 0; i < c.targets.size(); ++i) check_target(c.targets[i], "path model target " + std::to_string(i));
    if (!c.targets.empty())  // the waypoints move target 0: each must be a place it may be
        for (size_t i = 0; i < c.waypoints.size(); ++i) {
            PathTarget t = c.targets[0];
            t.center = c.waypoints[i];
            check_target(t, "path model waypoint " + std::to_string(i) + " (target 0)");
        }
    for (uint32_t g = 0; g < c.groups.size(); ++g) {
        try {
            check_goals(grid_, goals_with_targets(c.groups[g].goals, c.targets, g), slowness_);
        } catch (const Error& e) {
            throw Error(e.status(), "path model group " + std::to_string(g) + ": " + e.what());
        }
    }
    if (c.lamp.enabled) check_lamp(c.lamp);
    // The mesh shapes the curl noise when the kernel can assemble it (curl
    // with analytic derivatives); other noise types are used as they are.
    std::vector<float> phi_upload(phi_);
    bool any_mesh = false;
    for (float& v : phi_upload)
        if (std::isfinite(v)) any_mesh = true;
        else v = 1e20f;  // no mesh in reach: "far"
    mesh_noise_ = any_mesh && c.noise.type == NoiseType::Curl && !c.noise.finite_difference;
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
        costs_[g] = solve_cost(grid_, slowness_, goals_with_targets(c.groups[g].goals, c.targets, g), c.second_order);
        upload_directions(g);
    }
    worlds_ = WorldConfigs<PathModelConfig>(path_param_table(), c, swarm.worlds());
    local_ = build_local(c.noise, c.targets);
    const std::vector<cl_float> block = local_.noise->block();
    for (uint32_t k = 0; k < swarm.worlds(); ++k) noise_host_.insert(noise_host_.end(), block.begin(), block.end());
    // Every world's boundaries (one domain for all: world 0's, replicated).
    noise_prims_host_ = world_noise_prims(ctx_, swarm.world_domains(), local_.noise->config(), *local_.noise,
                                          "path model noise", noise_host_);
    upload_world_blocks();
    ctx_.queue().finish();
    preprocess_seconds_ = seconds_since(t0);
}

NoiseConfig noise_with_targets(NoiseConfig noise, const std::vector<PathTarget>& targets) {
    // §7 chasing: the target ball is a boundary of Eq. 2, after the others.
    for (const PathTarget& t : targets) {
        Boundary b;
        b.kind = Boundary::Kind::Sphere;
        b.center = t.center;
        b.radius = t.radius;
        noise.boundaries.push_back(b);
    }
    return noise;
}

std::vector<Goal> goals_moved_to(std::vector<Goal> goals, const std::array<float, 3>& to) {
    if (goals.empty()) return goals;
    const std::array<float, 3> shift{to[0] - goals[0].center[0], to[1] - goals[0].center[1], to[2] - goals[0].center[2]};
    for (Goal& g : goals)
        for (int a = 0; a < 3; ++a) g.center[a] += shift[a];
    return goals;
}

std::vector<Goal> goals_with_targets(std::vector<Goal> goals, const std::vector<PathTarget>& targets,
                                     uint32_t group) {
    for (const PathTarget& t : targets)
        if (t.group == group) {
            Goal g;
            g.kind = Goal::Kind::Sphere;
            g.center = t.center;
            g.radius = t.radius;
            goals.push_back(g);
        }
    return goals;
}

void PathModel::check_target(const PathTarget& t, const std::string& what) const {
    require(t.group < config_.groups.size(), what + ": group " + std::to_string(t.group) + " does not exist");
    require(std::isfinite(t.radius) && t.radius > 0.0f, what + ": radius must be a finite number > 0");
    require(std::isfinite(t.center[0]) && std::isfinite(t.center[1]) && std::isfinite(t.center[2]),
            what + ": center must be finite");
    const auto top = grid_.max_corner();
    int cell[3];
    for (int a = 0; a < 3; ++a) {
        require(t.center[a] > grid_.origin[a] && t.center[a] < top[a],
                what + ": center (" + std::to_string(t.center[0]) + ", " + std::to_string(t.center[1]) + ", " +
                    std::to_string(t.center[2]) + ") is outside the path grid [" + std::to_string(grid_.origin[0]) +
                    ", " + std::to_string(top[0]) + "] x [" + std::to_string(grid_.origin[1]) + ", " +
                    std::to_string(top[1]) + "] x [" + std::to_string(grid_.origin[2]) + ", " +
                    std::to_string(top[2]) + "]");
        cell[a] = std::min(int(grid_.dims[a]) - 1, int((t.center[a] - grid_.origin[a]) / grid_.h));
    }
    require(std::isfinite(slowness_[grid_.index(cell[0], cell[1], cell[2])]),
            what + ": center lies inside an obstacle");
}

PathModel::LocalField PathModel::build_local(const NoiseConfig& noise, const std::vector<PathTarget>& targets,
                                             const LocalField* previous,
                                             const std::vector<PathTarget>& changed) const {
    LocalField out;
    NoiseConfig nc = noise_with_targets(noise, targets);
    if (!nc.has_region()) nc.region_min = domain_min_, nc.region_max = domain_max_;
    NoiseField::validate(nc);  // as given (what can be baked), before the mesh-aware bake takes over
    if (mesh_noise_) nc.baked = false;  // baked below, with the mesh
    out.noise = std::make_unique<NoiseField>(ctx_, nc, &domain_min_, &domain_max_);
    std::string defines = out.noise->defines();
    if (mesh_noise_) {
        // The procedural curl path of noise_field.cl with every boundary, no wide kernels.
        defines = "-DNOISE_KIND=0 -DNOISE_TIMED=" + std::string(nc.time_scale > 0 ? "1" : "0") + " -DPATH_MESH=1" +
                  NoiseField::block_defines();
    }
    // The parameter block's slots (PATH_SPEED, ...), for every kernel of path_model.cl.
    defines += path_param_table().device_defines("PATH");
    if (mesh_noise_ && noise.baked) {
        // The noise's bake grid over its region (NoiseField's bake), with the mesh.
        const BakeGrid g = bake_grid(out.noise->config());
        out.vl_min = g.min;
        out.vl_cell = g.cell;
        out.vl_dims = g.dims;
        const bool partial = previous && previous->vl.size() == g.nodes();
        cl::Kernel k = ctx_.kernel("path_model.cl", partial ? "path_noise_rebake_box" : "path_noise_bake", defines);
        cl_uint i = out.noise->set_args(k, 0);
        k.setArg(i++, phi_dev_.get());
        k.setArg(i++, grid_dims_arg());
        k.setArg(i++, grid_origin_arg());
        k.setArg(i++, out.vl_min);
        k.setArg(i++, out.vl_cell);
        k.setArg(i++, out.vl_dims);
        if (!partial) {
            out.vl = bake_nodes(ctx_, k, i, g, "baked local field");
        } else {
            // Copy the nodes, then rebake the boxes of nodes within d0 (+ one
            // node) of each changed ball: beyond d0 Eq. 2 leaves N unchanged.
            out.vl.allocate(ctx_, g.nodes(), "baked local field");
            copy_buffer(ctx_, previous->vl.get(), out.vl.get(), 0, 0, g.nodes() * sizeof(cl_float4));
            const float d0 = nc.boundary_distance;
            for (const PathTarget& t : changed) {
                cl_int4 lo{}, n{};
                bool empty = false;
                for (int a = 0; a < 3; ++a) {
                    const float reach = t.radius + d0;
                    const int l = std::max(0, int(std::floor((t.center[a] - reach - g.min.s[a]) / g.cell.s[a])) - 1);
                    const int h = std::min(g.dims.s[a] - 1, int(std::ceil((t.center[a] + reach - g.min.s[a]) / g.cell.s[a])) + 1);
                    lo.s[a] = l;
                    n.s[a] = h - l + 1;
                    empty |= h < l;
                }
                if (empty) continue;
                k.setArg(i, lo);
                k.setArg(i + 1, n);
                k.setArg(i + 2, out.vl.get());
                check_arg_count(k, i + 3);
                launch(ctx_, k, size_t(n.s[0]) * size_t(n.s[1]) * size_t(n.s[2]));
            }
        }
        defines += " -DPATH_BAKED=1";
        // CPU devices: SWCL_W agents per work-item (path_model_advance_w).
        out.width = out.noise->preferred_width();
        if (out.width > 1) defines += " -DNOISE_WIDTH=" + std::to_string(out.width);
    } else {
        out.vl.allocate(ctx_, 1, "baked local field");
        // CPU devices: SWCL_W agents per work-item where the noise module
        // has a wide path for this noise (its defines carry NOISE_WIDTH).
        if (!mesh_noise_) out.width = out.noise->width();
    }
    out.advance = ctx_.kernel("path_model.cl", out.width > 1 ? "path_model_advance_w" : "path_model_advance",
                              defines + world_defines(worlds_.worlds()));
    return out;
}

void PathModel::upload_directions(uint32_t group) {
    std::vector<cl_float4> d(grid_.count());
    direction_field(grid_, costs_[group], phi_, reinterpret_cast<float*>(d.data()));
    write_buffer(ctx_, dirs_.get(), size_t(group) * grid_.count() * sizeof(cl_float4), d.size() * sizeof(cl_float4),
                 d.data());
}

double PathModel::set_goals(uint32_t group, std::vector<Goal> goals) {
    require_one_world("path model set_goals");
    const auto t0 = std::chrono::steady_clock::now();
    require(group < config_.groups.size(), "path model: group " + std::to_string(group) + " does not exist");
    std::vector<double> cost =
        solve_cost(grid_, slowness_, goals_with_targets(goals, config_.targets, group), config_.second_order);
    costs_[group] = std::move(cost);
    config_.groups[group].goals = std::move(goals);
    upload_directions(group);
    const double t = seconds_since(t0);
    ++recomputes_;
    recompute_seconds_ += t;
    return t;
}

double PathModel::retarget(std::vector<PathTarget> targets, uint32_t group, const std::vector<PathTarget>& changed) {
    if (worlds_.worlds() > 1) return retarget_worlds(std::move(targets), changed);
    const auto t0 = std::chrono::steady_clock::now();
    // Everything into temporaries first: an error (a goal check, the noise)
    // leaves the model as it was.
    std::vector<double> cost = solve_cost(grid_, slowness_,
                                          goals_with_targets(config_.groups[group].goals, targets, group),
                                          config_.second_order);
    LocalField local = build_local(config_.noise, targets, &local_, changed);
    std::vector<cl_float4> d(grid_.count());
    direction_field(grid_, cost, phi_, reinterpret_cast<float*>(d.data()));
    write_buffer(ctx_, dirs_.get(), size_t(group) * grid_.count() * sizeof(cl_float4), d.size() * sizeof(cl_float4),
                 d.data());
    costs_[group] = std::move(cost);
    local_ = std::move(local);
    config_.targets = std::move(targets);
    ctx_.queue().finish();
    const double t = seconds_since(t0);
    ++recomputes_;
    recompute_seconds_ += t;
    return t;
}

double PathModel::set_target(uint32_t index, const std::array<float, 3>& center) {
    require(index < config_.targets.size(), "path model: target " + std::to_string(index) + " does not exist (" +
                                                std::to_string(config_.targets.size()) + " targets)");
    if (config_.targets[index].center == center) return 0.0;  // not moved: nothing to recompute
    std::vector<PathTarget> targets = config_.targets;
    targets[index].center = center;
    check_target(targets[index], "path model target " + std::to_string(index));
    const uint32_t group = targets[index].group;
    const std::vector<PathTarget> changed{config_.targets[index], targets[index]};  // the old and the new place
    return retarget(std::move(targets), group, changed);
}

uint32_t PathModel::add_target(const PathTarget& target) {
    require(worlds_.worlds() == 1 || !config_.noise.baked,
            "path model add_target: chasing targets with a baked noise do not run on a swarm of several worlds");
    const uint32_t index = uint32_t(config_.targets.size());
    check_target(target, "path model target " + std::to_string(index));
    if (index == 0)  // the waypoints will move it: each must be a place it may be
        for (size_t i = 0; i < config_.waypoints.size(); ++i) {
            PathTarget t = target;
            t.center = config_.waypoints[i];
            check_target(t, "path model waypoint " + std::to_string(i) + " (target 0)");
        }
    std::vector<PathTarget> targets = config_.targets;
    targets.push_back(target);
    retarget(std::move(targets), target.group, {target});
    return index;
}

void PathModel::set_lamp(const PathLamp& lamp) {
    require_one_world("path model set_lamp");
    if (!lamp.enabled) {
        config_.lamp.enabled = false;
        upload_params();
        return;
    }
    check_lamp(lamp);
    config_.lamp = lamp;
    upload_params();
}

void PathModel::check_lamp(const PathLamp& lamp) const {
    {  // the lamp's rows of the table ("path model lamp.radius = 0 is outside (0, inf) (m)")
        PathModelConfig with;
        with.lamp = lamp;
        path_param_table().validate(&with, "lamp.");
    }
    const auto top = grid_.max_corner();
    for (int a = 0; a < 3; ++a)
        require(lamp.center[a] > grid_.origin[a] && lamp.center[a] < top[a],
                "path model lamp: center is outside the path grid");
    // Free space around it: some free cell in the shell the moths circle in
    // (between the bulb and keep_out + 2 cells beyond it).
    const double inner = lamp.radius, outer = lamp.radius + lamp.keep_out + 2.0 * grid_.h;
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::max(0, int(std::floor((lamp.center[a] - outer - grid_.origin[a]) / grid_.h)));
        hi[a] = std::min(int(grid_.dims[a]) - 1, int(std::ceil((lamp.center[a] + outer - grid_.origin[a]) / grid_.h)));
    }
    bool free = false;
    for (int k = lo[2]; k <= hi[2] && !free; ++k)
        for (int j = lo[1]; j <= hi[1] && !free; ++j)
            for (int i = lo[0]; i <= hi[0] && !free; ++i) {
                const auto p = grid_.center(i, j, k);
                double d2 = 0;
                for (int a = 0; a < 3; ++a) d2 += (p[a] - lamp.center[a]) * (p[a] - lamp.center[a]);
                const double d = std::sqrt(d2);
                free = d >= inner && d <= outer && std::isfinite(slowness_[grid_.index(i, j, k)]);
            }
    require(free, "path model lamp: no free space around it (every cell within " + std::to_string(outer) +
                      " m of its centre is inside an obstacle)");
}

void PathModel::upload_params() { blocks_current_ = false; }

void PathModel::advance(Swarm& swarm, uint64_t step) {
    if (!config_.waypoints.empty() && step > 0 && step % config_.waypoint_every == 0 && !config_.targets.empty()) {
        set_target(0, config_.waypoints[(step / config_.waypoint_every - 1) % config_.waypoints.size()]);
    } else if (!config_.waypoints.empty() && step > 0 && step % config_.waypoint_every == 0) {
        const auto& w = config_.waypoints[(step / config_.waypoint_every - 1) % config_.waypoints.size()];
        if (worlds_.worlds() > 1) move_world_goals(w);
        else set_goals(0, goals_moved_to(config_.groups[0].goals, w));
    }
    if (!blocks_current_) upload_world_blocks();
    const uint32_t n = swarm.agent_count();
    const uint32_t worlds = worlds_.worlds();
    cl::Kernel& advance_ = local_.advance;
    cl_uint i = swarm.set_step_args(advance_, step);
    const cl_uint noise_at = i;
    i = local_.noise->set_args(advance_, i);
    if (worlds > 1) {
        advance_.setArg(noise_at, noise_blocks_.get());       // the worlds' blocks
        advance_.setArg(noise_at + 1, noise_prims_.get());  // and their boundaries
    }
    advance_.setArg(i++, world_dirs_on_ ? world_dirs_.get() : dirs_.get());
    advance_.setArg(i++, grid_dims_arg());
    advance_.setArg(i++, grid_origin_arg());
    advance_.setArg(i++, group_end_.get());
    advance_.setArg(i++, cl_uint(config_.groups.size()));
    advance_.setArg(i++, params_.get());  // path_param_table()'s blocks: s0, the lamp
    advance_.setArg(i++, phi_dev_.get());
    advance_.setArg(i++, world_extra_.get());
    advance_.setArg(i++, cl_uint(world_dirs_on_ ? grid_.count() * config_.groups.size() : 0));
    advance_.setArg(i++, local_.vl.get());
    advance_.setArg(i++, local_.vl_min);
    advance_.setArg(i++, local_.vl_cell);
    advance_.setArg(i++, local_.vl_dims);
    check_arg_count(advance_, i);
    launch_worlds(ctx_, advance_, (size_t(n) + local_.width - 1) / local_.width, worlds);
    swarm.positions_changed();
}

StepStages PathModel::stages() const {
    StepStages s;
    s.min_distance = config_.min_distance;
    s.seed = config_.noise.seed;
    s.stats = true;
    if (worlds_.worlds() > 1) {
        for (uint32_t k = 0; k < worlds_.worlds(); ++k) {
            s.world_min_distance.push_back(worlds_[k].min_distance);
            s.world_seed.push_back(worlds_[k].noise.seed);
            s.min_distance = std::max(s.min_distance, worlds_[k].min_distance);
        }
    }
    return s;
}

// The goals as they are now are in the descriptor (config_.groups: moved by
// set_goals and the waypoints); the constructor solves their cost fields
// with the same code as set_goals.  The state: the recomputation counters.
void PathModel::save_checkpoint(Swarm&, ByteWriter& descriptor, ByteWriter& state) {
    write_model_descriptor(descriptor, config_);  // the other worlds: their varied parameters (WRLD)
    state.u32(recomputes_);
    state.f64(recompute_seconds_);
}
void PathModel::restore_checkpoint(Swarm&, ByteReader& state) {
    recomputes_ = state.u32();
    recompute_seconds_ = state.f64();
    state.expect_end();
}

}  // namespace swarmcl
