#include "models/force_model.hpp"

#include "models/model_descriptor.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.hpp"
#include "params/param_block.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {
namespace {

// curl_noise.cl SWCL_PRIM_* (the noise module packs its boundaries alike).
constexpr float kPrimSphere = 2.0f, kPrimBox = 3.0f;

// Padding of the fine grid's sorted copy's blocks (kernels/force_model.cl
// FM_SOA_PAD).
constexpr uint32_t kFineSoaPad = 16;

// kernels/force_model.cl, FM_REP_IN_WALK: the force kernel sums the
// repulsion zone in its walk of the exact zones (which meets every
// candidate within R_att >= R_rep) in worlds of up to this many agents.
constexpr uint32_t kRepWalkMaxAgents = 2048;  // FM_REP_WALK_MAX_AGENTS

bool rep_in_walk(const ForceModelConfig& c, uint32_t n) {
    return (c.terms & kForceRepulsion) && (c.terms & (kForceAlignment | kForceAttraction)) && c.neighbor_sample == 0 &&
           c.r_rep <= c.r_att && n <= kRepWalkMaxAgents;
}

// What every build of force_model.cl is given: the parameter block's slots
// (FORCE_R_REP, ...) and the limit above.
std::string force_program_defines() {
    return force_param_table().device_defines("FORCE") + " -DFM_REP_WALK_MAX_AGENTS=" +
           std::to_string(kRepWalkMaxAgents) + "u";
}
}  // namespace

ForceModelConfig::ForceModelConfig() {
    noise.type = NoiseType::Curl;
    noise.scale = 0.32f;   // rho (Table 1)
    noise.gain = 0.125f / 0.32f;  // eta / rho (Table 1; see the header)
}

void validate(const ForceModelConfig& c) {
    // Each parameter's range: force_param_table() ("force model alpha = 1.5
    // is outside [0, 1]"); what one row cannot say follows.
    force_param_table().validate(const_cast<ForceModelConfig*>(&c));
    require(c.r_rep <= c.r_ali && c.r_ali <= c.r_att,
            "force model zone radii must satisfy 0 < r_rep <= r_ali <= r_att (§4.1)");
    require(c.cruise_speed <= c.max_speed, "force model cruise_speed must lie in [0, max_speed]");
    for (size_t k = 1; k < c.keyframes.size(); ++k)
        require(c.keyframes[k].frame > c.keyframes[k - 1].frame,
                "force model keyframes must be in strictly increasing frame order (keyframe " + std::to_string(k) +
                    " at frame " + std::to_string(c.keyframes[k].frame) + " follows frame " +
                    std::to_string(c.keyframes[k - 1].frame) + ")");
    for (size_t k = 0; k < c.keyframes.size(); ++k)
        require(c.keyframes[k].mesh.triangle_count() > 0 && surface_area(c.keyframes[k].mesh) > 0.0,
                "force model keyframe " + std::to_string(k) + ": empty or degenerate mesh");
    if (c.keyframe_period > 0)
        require(!c.keyframes.empty() && c.keyframes.back().frame < c.keyframe_period,
                "force model keyframe_period must exceed the last keyframe's frame");
    if (!c.path.empty()) BSplinePath check(c.path);  // >= 4 control points, finite
    for (size_t k = 0; k < c.obstacles.size(); ++k) {
        const Boundary& b = c.obstacles[k];
        const std::string name = "force model obstacle " + std::to_string(k);
        for (float v : b.center) require(std::isfinite(v), name + ": centre must be finite");
        if (b.kind == Boundary::Kind::Sphere) {
            require(std::isfinite(b.radius) && b.radius > 0.0f, name + ": sphere radius must be > 0");
        } else if (b.kind == Boundary::Kind::Box) {
            for (float h : b.half_extents)
                require(std::isfinite(h) && h > 0.0f, name + ": box half extents must be > 0");
            require(std::isfinite(b.radius) && b.radius >= 0.0f, name + ": box rounding must be >= 0");
        } else {
            fail(Status::InvalidArgument, name + ": only spheres and boxes are obstacles of the force model");
        }
    }
    for (size_t k = 0; k < c.mesh_obstacles.size(); ++k) {
        const TriangleMesh& m = c.mesh_obstacles[k];
        const std::string name = "force model mesh obstacle " + std::to_string(k);
        for (const Vec3f& v : m.vertices)
            for (float x : v) require(std::isfinite(x), name + ": vertices must be finite");
        for (const auto& t : m.triangles)
            for (uint32_t i : t) require(i < m.vertices.size(), name + ": triangle index out of range");
        require(m.triangle_count() > 0 && surface_area(m) > 0.0, name + ": empty or degenerate mesh");
    }
    if (!c.mesh_obstacles.empty()) force_mesh_grid(c);  // the grid's size
    NoiseField::validate(c.noise);
}

Grid3 force_mesh_grid(const ForceModelConfig& c) {
    require(!c.mesh_obstacles.empty(), "the force model has no mesh obstacles");
    const MeshBounds b = bounds(merged(c.mesh_obstacles));
    const double h = c.mesh_cell > 0.0f ? double(c.mesh_cell) : double(c.obstacle_range) / 4.0;
    // Every point within obstacle_range of a mesh lies inside the grid's
    // cell centres by at least one cell (the trilinear read needs no clamp
    // there); beyond the grid the obstacles are out of range.
    const double margin = double(c.obstacle_range) + 2.0 * h;
    Grid3 g;
    g.h = h;
    uint64_t cells = 1;
    for (size_t a = 0; a < 3; ++a) {
        g.origin[a] = double(b.min[a]) - margin;
        const double n = std::ceil((double(b.max[a]) - double(b.min[a]) + 2.0 * margin) / h);
        require(n * double(cells) <= double(kForceMeshMaxCells),
                "force model mesh obstacles: a distance grid of " + std::to_string(h) +
                    " m cells (mesh_cell; 0: obstacle_range / 4) over their extent would exceed " +
                    std::to_string(kForceMeshMaxCells) + " cells; raise mesh_cell");
        g.dims[a] = std::max<uint32_t>(2, uint32_t(n));
        cells *= g.dims[a];
    }
    return g;
}

SdfGrid force_mesh_sdf(Context& ctx, const ForceModelConfig& c) {
    const Grid3 g = force_mesh_grid(c);
    const TriangleMesh all = merged(c.mesh_obstacles);
    SdfGrid sdf = compute_sdf(ctx, all, g);
    for (float v : sdf.phi)
        require(std::isfinite(v), "force model mesh obstacles: the signed distance is not finite everywhere "
                                  "(a degenerate mesh?)");
    return sdf;
}

ForceModel::ForceModel(Swarm& swarm, ForceModelConfig config)
    : config_(std::move(config)),
      worlds_(force_param_table(), config_, swarm.worlds()),
      world_count_(swarm.worlds()),
      fine_(swarm.context()) {
    validate(config_);
    // Worlds: the targets sampled from the meshes, the path's placement and
    // the obstacles are one for every world (what sets them is refused per
    // world when it differs); each world assigns its insects to the targets
    // from its own positions (activate).
    Context& ctx = swarm.context();
    check_noise_for_world_domains(config_.noise, swarm.world_domains(), "force model noise");
    noise_ = std::make_unique<NoiseField>(ctx, config_.noise, &swarm.config().domain_min, &swarm.config().domain_max);
    // On CPU devices the explicit-width force kernel (NoiseField::width()
    // agents per work-item; kernels/force_model.cl).
    width_ = noise_->width();
    // Every kernel of force_model.cl with the parameter block's slots
    // (FORCE_R_REP, ...; one program), and the block itself.
    // Worlds: -DSWCL_WORLDS only for several (world_defines), so the kernels
    // of one world are those from before worlds; a parameter block and a
    // noise block per world (world k's at k FORCE_FLOATS, k
    // NOISE_BLOCK_FLOATS).
    const std::string defines = force_program_defines() + world_defines(world_count_);
    const std::vector<cl_float> block = noise_->block();
    noise_host_.reserve(block.size() * world_count_);
    for (uint32_t k = 0; k < world_count_; ++k) noise_host_.insert(noise_host_.end(), block.begin(), block.end());
    noise_prims_host_ = world_noise_prims(ctx, swarm.world_domains(), config_.noise, *noise_, "force model noise", noise_host_);
    upload_world_blocks(ctx);
    force_k_ = noise_->kernel("force_model.cl", width_ > 1 ? "force_model_force_w" : "force_model_force", defines);
    fine_gather_k_ = noise_->kernel("force_model.cl", "force_model_fine_gather", defines);
    // One agent per work-item on every device: with a few candidates per
    // agent, 16 lanes walking the union of their boxes measured slower.
    mde_k_ = noise_->kernel("force_model.cl", "force_model_mde", defines);
    repulsion_k_ = noise_->kernel("force_model.cl", width_ > 1 ? "force_model_repulsion_w" : "force_model_repulsion",
                                  defines);
    integrate_k_ = noise_->kernel("force_model.cl", "force_model_integrate", defines);
    project_k_ = noise_->kernel("force_model.cl", "force_model_project", defines);
    scatter_k_ = noise_->kernel("force_model.cl", "force_model_scatter", defines);
    if (!config_.path.empty()) path_.emplace(config_.path);
    std::vector<cl_float4> prims;
    for (const Boundary& b : config_.obstacles) {
        const auto& c = b.center;
        if (b.kind == Boundary::Kind::Sphere) {
            prims.push_back(cl_float4{{c[0], c[1], c[2], kPrimSphere}});
            prims.push_back(cl_float4{{b.radius, 0.0f, 0.0f, 0.0f}});
        } else {
            // swcl_dist_box wants a rounding 0 < rr <= min half extent.
            const auto& h = b.half_extents;
            const float rr = std::max(1e-4f, std::min({b.radius, h[0], h[1], h[2]}));
            prims.push_back(cl_float4{{c[0], c[1], c[2], kPrimBox}});
            prims.push_back(cl_float4{{h[0], h[1], h[2], rr}});
        }
    }
    nprims_ = uint32_t(prims.size() / 2);
    prims_.allocate(ctx, std::max<size_t>(prims.size(), 2), "force model obstacles");
    prims_.upload(ctx, prims.data(), prims.size());
    if (!config_.mesh_obstacles.empty()) {
        const SdfGrid sdf = force_mesh_sdf(ctx, config_);
        mesh_grid_ = sdf.grid;
        mesh_phi_.allocate(ctx, sdf.phi.size(), "force model mesh obstacle distances");
        mesh_phi_.upload(ctx, sdf.phi.data(), sdf.phi.size());
    } else {
        mesh_phi_.allocate(ctx, 1, "force model mesh obstacle distances");
    }
    prepare(swarm);
}

void ForceModel::upload_world_blocks(Context& ctx) {
    const std::vector<float> blocks = worlds_.device_blocks();
    params_.reserve(ctx, blocks.size(), "model parameter blocks");
    params_.upload(ctx, blocks.data(), blocks.size());
    noise_blocks_.reserve(ctx, noise_host_.size(), "noise parameter blocks");
    noise_blocks_.upload(ctx, noise_host_.data(), noise_host_.size());
    noise_prims_.reserve(ctx, noise_prims_host_.size(), "noise boundaries of the worlds");
    noise_prims_.upload(ctx, noise_prims_host_.data(), noise_prims_host_.size());
    std::vector<cl_ulong> seed(world_count_);
    for (uint32_t k = 0; k < world_count_; ++k) seed[k] = worlds_[k].noise.seed;
    world_seed_.reserve(ctx, world_count_, "force model noise seeds");
    world_seed_.upload(ctx, seed.data(), world_count_);
    if (world_count_ > 1) {
        std::vector<cl_float> d_min(world_count_);
        for (uint32_t k = 0; k < world_count_; ++k) d_min[k] = worlds_[k].min_distance;
        mde_d_min_.reserve(ctx, world_count_, "force model MDE distances");
        mde_d_min_.upload(ctx, d_min.data(), world_count_);
    }
    blocks_current_ = true;
}

void ForceModel::set_world_param(Swarm& swarm, const std::string& key, const double* values, size_t count) {
    // The table's rows one for every world are checked by worlds_.set; the
    // mesh obstacles' distance grid, built once, reaches obstacle_range.
    const bool shared = key == "obstacle_range" && !config_.mesh_obstacles.empty();
    const bool noise = key.compare(0, 6, "noise.") == 0;
    std::vector<float> noise_next = noise_host_;
    std::vector<cl_float4> prims_next = noise_prims_host_;
    worlds_.set(key, values, count, [&](const ForceModelConfig& changed, uint32_t k) {
        validate(changed);  // what the table cannot say (zone order, cruise <= max speed)
        if (shared && !(values[k] == values[0]))
            fail(Status::InvalidArgument, "force model obstacle_range cannot differ between worlds: the mesh "
                                          "obstacles' distance grid, built once for every world, reaches it");
        if (!noise) return;
        write_world_noise_block(swarm.context(), changed.noise, &swarm.world_domain(k).min,
                                &swarm.world_domain(k).max, *noise_, "force model " + key, noise_next, k,
                                &prims_next);
    });
    noise_host_ = std::move(noise_next);
    noise_prims_host_ = std::move(prims_next);
    config_ = worlds_[0];
    blocks_current_ = false;
}

std::vector<double> ForceModel::world_param(const std::string& key) const { return worlds_.get(key); }

void ForceModel::prepare(Swarm& swarm) {
    const uint32_t n = swarm.agent_count();
    if (n == prepared_n_ && (n > 0 || targets_.empty())) return;
    prepared_n_ = n;
    targets_.clear();
    kf_buf_.clear();
    same_topology_.clear();
    active_ = -1;
    if (n == 0) return;
    Context& ctx = swarm.context();
    const auto& c = config_;
    for (size_t k = 0; k < c.keyframes.size(); ++k) {
        const TriangleMesh& m = c.keyframes[k].mesh;
        // Keyframes of one animation (same vertex and triangle counts) keep
        // the first one's samples by barycentric coordinates: each insect
        // keeps its target and the shape deforms without reassignment.
        const bool same = k > 0 && m.vertices.size() == c.keyframes[k - 1].mesh.vertices.size() &&
                          m.triangle_count() == c.keyframes[k - 1].mesh.triangle_count();
        same_topology_.push_back(same);
        targets_.push_back(make_targets(m, n, c.sample_seed + k, c.min_spacing, c.neighbor_k,
                                        same ? &targets_.back().samples : nullptr));
    }
    force_.allocate(ctx, size_t(n) * world_count_, "force model forces");  // every world's
    target_of_buf_.allocate(ctx, size_t(n) * world_count_, "force model target_of");  // world by world
    by_target_.allocate(ctx, size_t(n) * world_count_, "force model positions by target");
    kf_buf_.assign(targets_.size(), KeyframeBuffers{});
    for (size_t k = 0; k < targets_.size(); ++k) {
        const ShapeTargets& t = targets_[k];
        KeyframeBuffers& b = kf_buf_[k];
        std::vector<cl_float4> pts(n);
        for (uint32_t i = 0; i < n; ++i)
            pts[i] = cl_float4{{t.points[3 * i], t.points[3 * i + 1], t.points[3 * i + 2], 0}};
        b.targets.allocate(ctx, n, "force model targets");
        b.targets.upload(ctx, pts.data(), n);
        b.nbr_start.allocate(ctx, t.nbr_start.size(), "force model target neighbour ranges");
        b.nbr_start.upload(ctx, t.nbr_start.data(), t.nbr_start.size());
        b.nbr_index.allocate(ctx, std::max<size_t>(t.nbr_index.size(), 1), "force model target neighbours");
        b.nbr_index.upload(ctx, t.nbr_index.data(), t.nbr_index.size());
    }
}

int ForceModel::keyframe_at(uint64_t step) const {
    const auto& kf = config_.keyframes;
    if (kf.empty()) return -1;
    const uint64_t s = config_.keyframe_period ? step % config_.keyframe_period : step;
    int found = -1;
    for (size_t k = 0; k < kf.size(); ++k)
        if (kf[k].frame <= s) found = int(k);
    // A repeating cycle before its first keyframe is still in its last one.
    if (found < 0 && config_.keyframe_period && step >= config_.keyframe_period) found = int(kf.size()) - 1;
    return found;
}

Vec3f ForceModel::path_offset(uint64_t step, float dt) const {
    if (!path_) return {0.0f, 0.0f, 0.0f};
    return path_->at_length(double(config_.path_speed) * double(step) * dt);
}

ForceModel::Placement ForceModel::placement(uint64_t step, float dt) const {
    Placement p;
    p.offset = path_offset(step, dt);
    if (!path_ || !config_.path_orient) return p;
    // §6: the shape's frame follows the path.  The generated animals face +x
    // with +z up (shapes/shape_library.cpp); R takes +x to the tangent T, +z
    // to the frame's up U and +y to U x T (a proper rotation: T x (U x T) = U).
    const BSplinePath::Frame f = path_->frame_at_length(double(config_.path_speed) * double(step) * dt);
    const auto& t = f.tangent;
    const auto& u = f.up;
    const std::array<double, 3> l{u[1] * t[2] - u[2] * t[1], u[2] * t[0] - u[0] * t[2], u[0] * t[1] - u[1] * t[0]};
    for (int r = 0; r < 3; ++r) p.rotation[size_t(r)] = {t[size_t(r)], l[size_t(r)], u[size_t(r)]};
    p.rotated = true;
    return p;
}

std::vector<float> ForceModel::placed(const std::vector<float>& xyz, uint64_t step, float dt) const {
    const Placement p = placement(step, dt);
    std::vector<float> out(xyz.size());
    for (size_t i = 0; i + 2 < xyz.size(); i += 3)
        for (size_t r = 0; r < 3; ++r)
            out[i + r] = p.rotated ? float(p.rotation[r][0] * xyz[i] + p.rotation[r][1] * xyz[i + 1] +
                                           p.rotation[r][2] * xyz[i + 2] + p.offset[r])
                                   : xyz[i + r] + p.offset[r];  // translation only, bit for bit as before path_orient
    return out;
}

void ForceModel::activate(Swarm& swarm, int k) {
    Context& ctx = swarm.context();
    const ShapeTargets& t = targets_[size_t(k)];
    const uint32_t n = swarm.agent_count();
    // A keyframe of the same animation as the active one keeps the
    // assignment (its targets correspond); otherwise assign anew from the
    // insects' current positions to the targets where they will be.
    const bool keep = active_ >= 0 && !target_of_.empty() &&
                      ((k == active_ + 1 && same_topology_[size_t(k)]) ||
                       (k == 0 && active_ == int(targets_.size()) - 1 && config_.keyframe_period &&
                        std::all_of(same_topology_.begin() + 1, same_topology_.end(), [](bool b) { return b; })));
    if (!keep) {  // each world from its own insects (target indices within it)
        const size_t total = size_t(n) * world_count_;
        std::vector<float> agents(3 * total);
        swarm.read(Attribute::Position, agents.data(), total);
        const std::vector<float> where = placed(t.points, swarm.step_count(), swarm.config().dt);
        std::vector<uint32_t> target_of;
        target_of.reserve(total);
        for (uint32_t w = 0; w < world_count_; ++w) {
            const std::vector<float> mine(agents.begin() + 3 * size_t(w) * n, agents.begin() + 3 * size_t(w + 1) * n);
            const std::vector<uint32_t> a = assign_targets(mine, where, config_.assignment);
            target_of.insert(target_of.end(), a.begin(), a.end());
        }
        target_of_ = std::move(target_of);
        target_of_buf_.upload(ctx, target_of_.data(), total);
    }
    active_ = k;
}

void ForceModel::enqueue_force(Swarm& swarm, uint64_t step) {
    if (!blocks_current_) upload_world_blocks(swarm.context());
    prepare(swarm);
    const uint32_t n = swarm.agent_count();
    if (n == 0) return;
    const int k = keyframe_at(step);
    if (k != active_ && k >= 0) activate(swarm, k);
    swarm.ensure_grid();
    const auto& c = config_;
    const ShapeTargets* t = current_targets();
    // sigma (omega spacing) and the default distance scale (2 spacing) are
    // derived by the kernel from its parameter block and the spacing.
    const float spacing = t ? float(t->spacing) : 1.0f;
    const float dt = swarm.config().dt;
    const Placement place = placement(step, dt);
    cl_float4 frame[3];  // rows of [R | offset] (kernels/force_model.cl)
    for (size_t r = 0; r < 3; ++r)
        frame[r] = cl_float4{{float(place.rotation[r][0]), float(place.rotation[r][1]), float(place.rotation[r][2]),
                              place.offset[r]}};
    if (t) {
        set_args(scatter_k_, swarm.positions().get(), swarm.ids().get(), cl_uint(n), target_of_buf_.get(),
                 by_target_.get());
        launch_worlds(swarm.context(), scatter_k_, n, world_count_);
    }
    cl_uint i = 0;
    cl::Kernel& kf = force_k_;
    kf.setArg(i++, swarm.positions().get());
    kf.setArg(i++, swarm.velocities().get());
    kf.setArg(i++, swarm.ids().get());
    kf.setArg(i++, n);
    i = swarm.grid().set_world_grid_args(kf, i);  // the cells of a world (unread with one)
    kf.setArg(i++, params_.get());
    kf.setArg(i++, spacing);
    kf.setArg(i++, cl_ulong(c.sample_seed));
    kf.setArg(i++, cl_uint(t ? 1 : 0));
    kf.setArg(i++, target_of_buf_.get());
    if (t) {
        const KeyframeBuffers& b = kf_buf_[size_t(active_)];
        kf.setArg(i++, b.targets.get());
        kf.setArg(i++, b.nbr_start.get());
        kf.setArg(i++, b.nbr_index.get());
    } else {  // not read without targets (has_targets 0)
        kf.setArg(i++, force_.get());
        kf.setArg(i++, target_of_buf_.get());
        kf.setArg(i++, target_of_buf_.get());
    }
    kf.setArg(i++, by_target_.get());
    for (const cl_float4& row : frame) kf.setArg(i++, row);
    kf.setArg(i++, float(double(step) * dt));
    kf.setArg(i++, cl_uint(step));
    kf.setArg(i++, force_.get());
    rep_.reserve(swarm.context(), size_t(n) * world_count_, "force model repulsion");
    fine_current_ = false;
    // Exact, through the fine grid, unless every world's force kernel sums
    // the repulsion zone in its walk (rep_in_walk) and no world enforces a
    // minimum distance (which reuses this grid: the same grid, so the same
    // pushes, whether or not the repulsion needed it).
    bool fine_needed = false;
    for (uint32_t k = 0; k < world_count_; ++k)
        fine_needed |= !rep_in_walk(worlds_[k], n) || worlds_[k].min_distance > 0.0f;
    if ((c.terms & kForceRepulsion) && fine_needed) {
        build_fine_grid(swarm);
        fine_current_ = true;
        set_args(repulsion_k_, fine_soa_.get(), fine_.sorted_slots().get(), cl_uint(n), fine_.geometry().get(),
                 fine_.cell_start().get(), params_.get(), rep_.get());
        launch_worlds(swarm.context(), repulsion_k_, (n + width_ - 1) / width_, world_count_);
    }
    kf.setArg(i++, rep_.get());
    const cl_uint noise_at = i;
    i = noise_->set_args(kf, i);
    kf.setArg(noise_at, noise_blocks_.get());      // the worlds' blocks (world 0's with one)
    kf.setArg(noise_at + 1, noise_prims_.get());  // and their boundaries
    check_arg_count(kf, i);
    launch_worlds(swarm.context(), kf, (n + width_ - 1) / width_, world_count_);
}

std::vector<cl_float4> ForceModel::sample_mesh_obstacles(Swarm& swarm, const std::vector<float>& xyz) {
    require(!config_.mesh_obstacles.empty(), "the force model has no mesh obstacles");
    Context& ctx = swarm.context();
    const size_t n = xyz.size() / 3;
    std::vector<cl_float4> pts(std::max<size_t>(n, 1));
    for (size_t i = 0; i < n; ++i) pts[i] = cl_float4{{xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2], 0.0f}};
    DeviceBuffer<cl_float4> in(ctx, pts.size(), "mesh obstacle sample points"), out(ctx, pts.size(), "mesh obstacle samples");
    in.upload(ctx, pts.data(), pts.size());
    cl::Kernel k = noise_->kernel("force_model.cl", "force_model_mesh_distance",
                                  force_program_defines());
    const cl_int4 mdims{{cl_int(mesh_grid_.dims[0]), cl_int(mesh_grid_.dims[1]), cl_int(mesh_grid_.dims[2]), 0}};
    const cl_float4 morigin{{float(mesh_grid_.origin[0]), float(mesh_grid_.origin[1]), float(mesh_grid_.origin[2]),
                             float(mesh_grid_.h)}};
    set_args(k, in.get(), cl_uint(n), mesh_phi_.get(), mdims, morigin, out.get());
    if (n) launch(ctx, k, n);
    std::vector<cl_float4> r(pts.size());
    out.download(ctx, r.data(), r.size());
    r.resize(n);
    return r;
}

void ForceModel::build_fine_grid(Swarm& swarm) {
    Context& ctx = swarm.context();
    const uint32_t n = swarm.agent_count();
    if (n != fine_n_ || !fine_soa_.get()()) {
        fine_n_ = n;
        fine_soa_.allocate(ctx, 3 * (size_t(n) + kFineSoaPad) * world_count_, "force model fine grid positions");
        // The pads are read, never written, by the explicit-width kernels'
        // vector loads (lanes past n, masked): zeros rather than whatever the
        // allocation held (Oclgrind reported the reads, docs/reliability.md).
        fine_soa_.fill(ctx, 0.0f, fine_soa_.size());
    }
    if (n == 0) return;
    const auto& pos = swarm.positions();
    if (world_count_ == 1) {
        fine_.build(pos, n, config_.r_rep);
    } else {
        // Each world's cells over its own bounding box at its own R_rep: the
        // geometry, so the order of its repulsion and MDE sums, it has alone.
        std::vector<float> r_rep(world_count_);
        for (uint32_t k = 0; k < world_count_; ++k) r_rep[k] = worlds_[k].r_rep;
        fine_.build_groups_apart(pos, n * world_count_, r_rep);
    }
    set_args(fine_gather_k_, pos.get(), fine_.sorted_slots().get(), cl_uint(n), fine_soa_.get());
    launch_worlds(ctx, fine_gather_k_, n, world_count_);
}

StepStages ForceModel::stages() const {
    StepStages s;
    s.min_distance = config_.min_distance;
    s.seed = config_.noise.seed;
    s.own_min_distance = true;
    s.stats = true;
    s.count_empty_steps = false;
    if (world_count_ > 1) {
        for (uint32_t k = 0; k < world_count_; ++k) {
            s.world_min_distance.push_back(worlds_[k].min_distance);
            s.world_seed.push_back(worlds_[k].noise.seed);
            s.min_distance = std::max(s.min_distance, worlds_[k].min_distance);
        }
    }
    return s;
}

void ForceModel::enforce_min_distance(Swarm& swarm, DeviceBuffer<cl_uint>& moved) {
    const uint32_t n = swarm.agent_count();
    Context& ctx = swarm.context();
    fill_buffer(ctx, moved.get(), cl_uint(0), 0, sizeof(cl_uint) * world_count_);  // moved[k]: this pass
    if (n == 0) return;
    // The fine grid of this step's forces, built before the Newton step
    // moved each agent by at most max_speed dt (force_model_mde), or one of
    // the current positions.
    float slack = 0.0f;
    if (fine_current_) {
        // Worlds: the largest max_speed bounds every world's move; a wider
        // box adds only candidates that fail the distance test and keeps the
        // order of the others (rows, then slots), so each world's sums are
        // those it has alone.
        float max_speed = config_.max_speed;
        for (uint32_t k = 1; k < world_count_; ++k) max_speed = std::max(max_speed, worlds_[k].max_speed);
        slack = 1.001f * max_speed * swarm.config().dt;
    } else {
        build_fine_grid(swarm);
    }
    fine_current_ = false;
    if (world_count_ == 1) {
        set_args(mde_k_, swarm.positions().get(), swarm.ids().get(), cl_uint(n), fine_.geometry().get(),
                 fine_.cell_start().get(), fine_.sorted_slots().get(), config_.min_distance, slack,
                 cl_ulong(config_.noise.seed), swarm.scratch().get(), moved.get());
    } else {
        set_args(mde_k_, swarm.positions().get(), swarm.ids().get(), cl_uint(n), fine_.geometry().get(),
                 fine_.cell_start().get(), fine_.sorted_slots().get(), mde_d_min_.get(), slack, world_seed_.get(),
                 swarm.scratch().get(), moved.get());
    }
    launch_worlds(ctx, mde_k_, n, world_count_);
    swarm.swap_positions_with_scratch();
}

void ForceModel::compute_forces(Swarm& swarm, uint64_t step) { enqueue_force(swarm, step); }

namespace {
cl_int4 mesh_dims_arg(const Grid3& g) { return cl_int4{{cl_int(g.dims[0]), cl_int(g.dims[1]), cl_int(g.dims[2]), 0}}; }
cl_float4 mesh_origin_arg(const Grid3& g) {
    return cl_float4{{float(g.origin[0]), float(g.origin[1]), float(g.origin[2]), float(g.h)}};
}
}  // namespace

void ForceModel::advance(Swarm& swarm, uint64_t step) {
    enqueue_force(swarm, step);
    const uint32_t n = swarm.agent_count();
    if (n == 0) return;
    Context& ctx = swarm.context();
    const cl_uint has_mesh = config_.mesh_obstacles.empty() ? 0u : 1u;
    set_args(integrate_k_, swarm.positions().get(), swarm.velocities().get(), force_.get(), cl_uint(n),
             swarm.config().dt, params_.get(), prims_.get(), cl_uint(nprims_), has_mesh, mesh_phi_.get(),
             mesh_dims_arg(mesh_grid_), mesh_origin_arg(mesh_grid_), swarm.ids().get(), world_seed_.get());
    launch_worlds(ctx, integrate_k_, n, world_count_);
    swarm.positions_changed();
}

void ForceModel::after_constraints(Swarm& swarm, uint64_t) {
    const uint32_t n = swarm.agent_count();
    if (n == 0) return;
    // The push-out: after MDE for every obstacle; after each step for mesh
    // obstacles too, whose sampled surface is only accurate to about a cell
    // (docs/force-model.md).
    const cl_uint has_mesh = config_.mesh_obstacles.empty() ? 0u : 1u;
    const bool project_mesh = has_mesh != 0u;
    // Worlds: the kernel keeps the primitives to the worlds with MDE on.
    bool mde = config_.min_distance > 0.0f;
    for (uint32_t k = 1; k < world_count_; ++k) mde |= worlds_[k].min_distance > 0.0f;
    if ((mde && nprims_) || project_mesh) {
        if (!blocks_current_) upload_world_blocks(swarm.context());
        set_args(project_k_, swarm.positions().get(), cl_uint(n), prims_.get(), cl_uint(mde ? nprims_ : 0u),
                 has_mesh, mesh_phi_.get(), mesh_dims_arg(mesh_grid_), mesh_origin_arg(mesh_grid_),
                 mde_d_min_.get());
        launch_worlds(swarm.context(), project_k_, n, world_count_);
        swarm.positions_changed();
    }
}

// Targets are sampled again from the descriptor for the agent count (the
// constructor's prepare(), seeded); the keyframe in effect and the
// assignment of agents to its targets, made from the positions when it
// became active, are the state.
void ForceModel::save_checkpoint(Swarm&, ByteWriter& descriptor, ByteWriter& state) {
    write_model_descriptor(descriptor, config_);
    state.u32(prepared_n_);
    state.i32(active_);
    state.u64(target_of_.size());
    for (uint32_t t : target_of_) state.u32(t);
}
void ForceModel::restore_checkpoint(Swarm& swarm, ByteReader& state) {
    const uint32_t prepared = state.u32();
    const int32_t active = state.i32();
    const uint64_t count = state.count(4);
    const uint32_t n = swarm.agent_count();
    if (prepared != prepared_n_) {
        // Saved after the agent count changed and before a step: the next
        // step prepares anew and drops the old assignment, as here.
        for (uint64_t i = 0; i < count; ++i) state.u32();
        state.expect_end();
        return;
    }
    if (active < -1 || active >= int32_t(targets_.size()))
        state.bad("active keyframe " + std::to_string(active) + " of " + std::to_string(targets_.size()));
    const uint64_t all = uint64_t(n) * world_count_;  // world by world
    if (count != 0 && count != all)
        state.bad("an assignment of " + std::to_string(count) + " agents for " + std::to_string(all));
    if (active >= 0 && count != all) state.bad("an active keyframe without an assignment");
    std::vector<uint32_t> target_of(static_cast<size_t>(count));
    for (uint32_t& t : target_of) {
        t = state.u32();
        if (t >= n) state.bad("target " + std::to_string(t) + " of " + std::to_string(n));
    }
    state.expect_end();
    if (!target_of.empty()) target_of_buf_.upload(swarm.context(), target_of.data(), target_of.size());
    target_of_ = std::move(target_of);
    active_ = active;
}

}  // namespace swarmcl
