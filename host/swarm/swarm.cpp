#include "swarm/swarm.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "core/philox.hpp"
#include "fields/noise_field.hpp"

namespace swarmcl {
namespace {

bool finite(float x) { return std::isfinite(x); }

void validate(const SwarmConfig& c) {
    require(c.capacity > 0, "swarm capacity must be > 0");
    require(c.worlds > 0, "swarm worlds must be > 0 (1: a swarm of one world)");
    require(c.world_seeds.empty() || c.world_seeds.size() == c.worlds,
            "swarm world_seeds must be empty or hold one seed per world (" + std::to_string(c.worlds) + "), not " +
                std::to_string(c.world_seeds.size()));
    require(c.agent_count <= c.capacity, "swarm agent_count " + std::to_string(c.agent_count) +
                                             " exceeds capacity " + std::to_string(c.capacity));
    require(c.world_domains.empty() || c.world_domains.size() == c.worlds,
            "swarm world_domains must be empty or hold one domain per world (" + std::to_string(c.worlds) +
                "), not " + std::to_string(c.world_domains.size()));
    // "swarm domain_min[1] (2.000000) must be below domain_max[1] (1.000000)"
    const auto check_domain = [](const Domain& d, const std::string& what, const std::string& lo,
                                 const std::string& hi) {
        for (int a = 0; a < 3; ++a) {
            const std::string i = "[" + std::to_string(a) + "]";
            require(finite(d.min[a]) && finite(d.max[a]), what + " domain bounds must be finite");
            require(d.min[a] < d.max[a], what + " " + lo + i + " (" + std::to_string(d.min[a]) + ") must be below " +
                                             hi + i + " (" + std::to_string(d.max[a]) + ")");
        }
    };
    if (c.world_domains.empty()) check_domain({c.domain_min, c.domain_max}, "swarm", "domain_min", "domain_max");
    for (size_t k = 0; k < c.world_domains.size(); ++k)
        check_domain(c.world_domains[k], "swarm world " + std::to_string(k), "domain min", "domain max");
    require(finite(c.interaction_radius) && c.interaction_radius > 0.0f,
            "swarm interaction_radius must be a finite number > 0");
    require(finite(c.dt) && c.dt > 0.0f, "swarm dt must be a finite number > 0");
}

// Grid cells for a swarm: enough that cells stay small at any density the
// capacity allows, bounded so memory stays proportional to the capacity.
uint32_t max_cells_for(uint32_t capacity) {
    return uint32_t(std::clamp<uint64_t>(uint64_t(capacity) * 4u, 1u << 12, 1u << 24));
}

std::vector<Domain> domains_of(const SwarmConfig& c) {
    return c.world_domains.empty() ? std::vector<Domain>(c.worlds, Domain{c.domain_min, c.domain_max})
                                   : c.world_domains;
}

std::vector<GridGeometry> world_grids(const SwarmConfig& c) {
    std::vector<GridGeometry> grids;
    for (const Domain& d : domains_of(c))
        grids.push_back(GridGeometry::cover(d.min.data(), d.max.data(), c.interaction_radius,
                                            max_cells_for(c.capacity)));
    return grids;
}

SwarmConfig checked(SwarmConfig c, Context& ctx) {
    validate(c);
    if (!c.world_domains.empty()) {  // world 0's is the swarm's domain
        c.domain_min = c.world_domains[0].min;
        c.domain_max = c.world_domains[0].max;
    }
    uint64_t cells = 0;
    for (const GridGeometry& g : world_grids(c)) cells += g.cell_count();
    if (cells >= (uint64_t(1) << 31))
        fail(Status::InvalidArgument, "swarm worlds: " + std::to_string(c.worlds) + " worlds of " +
                                          std::to_string(cells) + " grid cells in all exceed 2^31 cells; use fewer "
                                          "worlds or a larger interaction_radius");
    // State, scratch and grid buffers per agent (float4 x4, uint x14, the
    // grid's mover records (16 B less its radix sort's 8 B: NeighborGrid),
    // packed xyz), and the grid's per-cell arrays (2 uints).
    const double bytes =
        (double(c.capacity) * (4 * 16 + 14 * 4 + 8 + 12) + double(max_cells_for(c.capacity)) * 8) * double(c.worlds);
    if (bytes > double(ctx.device().global_memory))
        fail(Status::OutOfMemory, "a swarm of capacity " + std::to_string(c.capacity) +
                                      (c.worlds > 1 ? " in each of " + std::to_string(c.worlds) + " worlds" : std::string()) +
                                      " needs about " + std::to_string(uint64_t(bytes)) + " bytes; the device '" +
                                      ctx.device().device_name + "' has " +
                                      std::to_string(ctx.device().global_memory));
    // Slots are 32-bit (the memory check above catches most such swarms first).
    if (c.worlds > 1 && uint64_t(c.capacity) * c.worlds > (uint64_t(1) << 31))
        fail(Status::InvalidArgument, "swarm capacity x worlds must be at most 2^31 agents (is " +
                                          std::to_string(uint64_t(c.capacity) * c.worlds) + ")");
    return c;
}

void check_finite(const float* src, size_t count, const char* what) {
    for (size_t i = 0; i < 3 * count; ++i)
        if (!std::isfinite(src[i]))
            fail(Status::InvalidArgument, std::string(what) + ": value of agent " + std::to_string(i / 3) +
                                              " is not finite (NaN or Inf); nothing was written");
}

}  // namespace

Swarm::Swarm(std::shared_ptr<Context> ctx, const SwarmConfig& config)
    : ctx_(std::move(ctx)),
      config_(checked(config, *ctx_)),
      domains_(domains_of(config_)),
      same_domain_(same_domains(domains_)),
      grid_(*ctx_, world_grids(config_), config.capacity * config.worlds),
      worlds_(config.worlds),
      stats_(*ctx_, config.worlds) {
    Context& c = *ctx_;
    const uint32_t cap = config_.capacity * worlds_;
    pos_.allocate(c, cap, "positions");
    vel_.allocate(c, cap, "velocities");
    scratch_.allocate(c, cap, "reorder scratch");
    vel_scratch_.allocate(c, cap, "velocity reorder scratch");
    ids_.allocate(c, cap, "agent ids");
    ids_scratch_.allocate(c, cap, "agent ids scratch");
    slot_of_.allocate(c, cap, "agent slots");
    packed_.allocate(c, size_t(cap) * 3, "transfer buffer");
    gather_ = c.kernel("swarm_state.cl", "gather_xyz");
    scatter_ = c.kernel("swarm_state.cl", "scatter_xyz");
    identity_ = c.kernel("swarm_state.cl", "identity_layout");
    integrate_ = c.kernel("swarm_state.cl", "integrate_ballistic");
    slot_of_k_ = c.kernel("swarm_state.cl", "slot_of_from_ids");
    frame_k_ = c.kernel("swarm_state.cl", "frame_xyz");
    const std::string worlds = world_defines(worlds_);
    // CPU devices: the count SWCL_W slots a work-item (neighbor_count_w).
    lanes_ = preferred_noise_width(c.device());
    count_ = lanes_ > 1 ? c.kernel("neighbors.cl", "neighbor_count_w", worlds + " -DNOISE_WIDTH=" + std::to_string(lanes_))
                        : c.kernel("neighbors.cl", "neighbor_count", worlds);
    nearest_ = c.kernel("neighbors.cl", "nearest_neighbor", worlds);
    lists_ = c.kernel("neighbors.cl", "neighbor_lists", worlds);
    place_uniformly(config_.agent_count);
}

Swarm::~Swarm() {
    try {
        ctx_->queue().finish();
    } catch (...) {
        // Nothing to report to: the buffers are released all the same.
    }
}

uint64_t Swarm::world_seed(uint32_t k) const {
    return config_.world_seeds.empty() ? config_.seed + k : config_.world_seeds[k];
}

void Swarm::require_one_world(const std::string& what) const {
    if (worlds_ > 1)
        fail(Status::InvalidArgument, what + " does not run on a swarm of several worlds yet (this one has " +
                                          std::to_string(worlds_) + "); docs/architecture.md, \"Worlds\"");
}

void Swarm::require_one_domain(const std::string& what) const {
    if (!same_domain_)
        fail(Status::InvalidArgument, what + " needs one domain for every world (this swarm's worlds have domains "
                                             "of their own); docs/architecture.md, \"Worlds\"");
}

void Swarm::place_uniformly(uint32_t count) {
    // Philox keyed by (seed, agent id, step 0, stream 0): the same seed gives
    // the same swarm on every device; world k's by its own seed.
    std::vector<float> xyz(size_t(count) * 3 * worlds_);
    for (uint32_t k = 0; k < worlds_; ++k) {
        const uint64_t seed = world_seed(k);
        float* out = xyz.data() + size_t(k) * count * 3;
        for (uint32_t id = 0; id < count; ++id) {
            const auto r = philox_for(seed, id, 0, 0);
            for (int a = 0; a < 3; ++a) {
                const float lo = domains_[k].min[a], hi = domains_[k].max[a];
                out[size_t(id) * 3 + a] = std::min(lo + uniform01(r[a]) * (hi - lo), std::nextafter(hi, lo));
            }
        }
    }
    write(Attribute::Position, xyz.data(), xyz.size() / 3);
}

void Swarm::check_count(size_t count, const char* what) const {
    if (count != total_agents())
        fail(Status::InvalidArgument, std::string(what) + ": count is " + std::to_string(count) +
                                          " but the swarm has " + std::to_string(total_agents()) + " agents" +
                                          (worlds_ > 1 ? " (" + std::to_string(worlds_) + " worlds of " +
                                                             std::to_string(n_) + ")"
                                                       : std::string()));
}

void Swarm::set_count(uint32_t n) {
    if (n == n_) return;
    Context& c = *ctx_;
    // Velocities of the agents that stay are kept (gathered in id order), new
    // agents start at rest; the layout restarts in id order.
    const uint32_t keep = std::min(n, n_);
    ensure_slot_of();
    if (worlds_ == 1) {
        set_args(gather_, vel_.get(), slot_of_.get(), keep, packed_.get());
        launch(c, gather_, keep);
        if (n > keep)
            fill_buffer(c, packed_.get(), 0.0f, size_t(keep) * 3 * sizeof(float), size_t(n - keep) * 3 * sizeof(float));
    } else {
        // Each world's first `keep` agents move to their new ids (world k
        // starts at k n): through the host, as a count change is rare.
        std::vector<float> old(total_agents() * 3), fresh(size_t(n) * worlds_ * 3, 0.0f);
        if (n_) {
            set_args(gather_, vel_.get(), slot_of_.get(), cl_uint(total_agents()), packed_.get());
            launch(c, gather_, total_agents());
            packed_.download(c, old.data(), old.size());
        }
        for (uint32_t k = 0; k < worlds_; ++k)
            std::copy_n(old.begin() + size_t(k) * n_ * 3, size_t(keep) * 3, fresh.begin() + size_t(k) * n * 3);
        if (!fresh.empty()) packed_.upload(c, fresh.data(), fresh.size());
    }
    const cl_uint total = n * worlds_;
    set_args(identity_, total, n ? n : 1u, ids_.get(), slot_of_.get());
    launch(c, identity_, total);
    grid_.invalidate_layout();  // id order is no order a grid build made
    set_args(scatter_, packed_.get(), slot_of_.get(), total, vel_.get());
    launch(c, scatter_, total);
    n_ = n;
    grid_current_ = false;
}

void Swarm::write(Attribute attribute, const float* src, size_t count) {
    const char* what = attribute == Attribute::Position ? "swcl_swarm_write(POSITION)" : "swcl_swarm_write(VELOCITY)";
    require(src != nullptr || count == 0, std::string(what) + ": src is NULL");
    if (attribute == Attribute::Position) {
        if (count % worlds_ != 0)
            fail(Status::InvalidArgument, std::string(what) + ": count " + std::to_string(count) +
                                              " is not a multiple of the swarm's " + std::to_string(worlds_) +
                                              " worlds (every world has the same number of agents)");
        if (count / worlds_ > config_.capacity)
            fail(Status::InvalidArgument, std::string(what) + ": count " + std::to_string(count / worlds_) +
                                              (worlds_ > 1 ? " a world" : "") + " exceeds the swarm's capacity " +
                                              std::to_string(config_.capacity));
    } else {
        check_count(count, what);
    }
    check_finite(src, count, what);
    if (attribute == Attribute::Position) set_count(uint32_t(count / worlds_));
    ensure_slot_of();
    packed_.upload(*ctx_, src, count * 3);
    set_args(scatter_, packed_.get(), slot_of_.get(), uint32_t(count),
             attribute == Attribute::Position ? pos_.get() : vel_.get());
    launch(*ctx_, scatter_, count);
    if (attribute == Attribute::Position) grid_current_ = false;
}

void Swarm::read(Attribute attribute, float* dst, size_t count) {
    const char* what = attribute == Attribute::Position ? "swcl_swarm_read(POSITION)" : "swcl_swarm_read(VELOCITY)";
    require(dst != nullptr || count == 0, std::string(what) + ": dst is NULL");
    check_count(count, what);
    ensure_slot_of();
    const cl_uint total = cl_uint(total_agents());
    set_args(gather_, attribute == Attribute::Position ? pos_.get() : vel_.get(), slot_of_.get(), total,
             packed_.get());
    launch(*ctx_, gather_, total);
    packed_.download(*ctx_, dst, size_t(total) * 3);
}

void Swarm::step_frames(uint32_t frames, uint32_t every, float* dst, size_t count) {
    const char* what = "swcl_swarm_step_frames";
    require(every > 0, std::string(what) + ": every must be >= 1 step");
    require(dst != nullptr || count == 0, std::string(what) + ": dst is NULL");
    const size_t total = total_agents();
    if (uint64_t(count) != uint64_t(frames) * total)
        fail(Status::InvalidArgument, std::string(what) + ": count is " + std::to_string(count) + " but " +
                                          std::to_string(frames) + " frames of " + std::to_string(total) +
                                          " agents are " + std::to_string(uint64_t(frames) * total));
    if (uint64_t(frames) * every > 0xFFFFFFFFull)
        fail(Status::InvalidArgument, std::string(what) + ": frames x every exceeds 2^32 steps");
    if (frames == 0) return;
    if (total == 0) {
        step(frames * every);
        return;
    }
    // Frames per read-back: up to 64 MB of them (one at least).
    const size_t frame_floats = total * 3;
    const uint32_t chunk = uint32_t(std::clamp<size_t>((size_t(64) << 20) / (frame_floats * sizeof(float)), 1, frames));
    frames_.reserve(*ctx_, size_t(chunk) * frame_floats, "step_frames frames");
    for (uint32_t f0 = 0; f0 < frames; f0 += chunk) {
        const uint32_t in_chunk = std::min(chunk, frames - f0);
        for (uint32_t f = 0; f < in_chunk; ++f) {
            step(every);
            set_args(frame_k_, pos_.get(), ids_.get(), cl_uint(total), n_ ? n_ : 1u, frames_.get(),
                     cl_ulong(size_t(f) * frame_floats));
            launch(*ctx_, frame_k_, total);
        }
        frames_.download(*ctx_, dst + size_t(f0) * frame_floats, size_t(in_chunk) * frame_floats);
    }
}

void Swarm::set_behavior(std::shared_ptr<Behavior> behavior) {
    behavior_ = std::move(behavior);
    stats_.reset(*ctx_);
    if (behavior_) {
        // The MDE kernels are built with the model, as each model built them
        // when it ran the pass itself.
        const StepStages st = behavior_->stages();
        if (st.min_distance > 0.0f && !st.own_min_distance) min_distance_pass(st);
    }
}

MinDistance& Swarm::min_distance_pass(const StepStages& st) {
    if (!mde_ || !mde_->matches(st, worlds_)) mde_.emplace(*ctx_, st, worlds_);
    return *mde_;
}

std::optional<StepStats> Swarm::take_step_stats() {
    if (!behavior_ || !behavior_->stages().stats) return std::nullopt;
    return stats_.take(*this);
}

std::optional<std::vector<StepStats>> Swarm::take_world_step_stats() {
    if (!behavior_ || !behavior_->stages().stats) return std::nullopt;
    return stats_.take_worlds(*this);
}

void Swarm::run_stages(uint64_t step) {
    behavior_->advance(*this, step);
    const StepStages st = behavior_->stages();
    if (n_ == 0 && !st.count_empty_steps) return;
    if (st.min_distance > 0.0f) {
        if (st.own_min_distance) {
            behavior_->enforce_min_distance(*this, stats_.device());
        } else {
            min_distance_pass(st).apply(*this, stats_.device());
        }
    }
    behavior_->after_constraints(*this, step);
    if (st.stats) stats_.count_step();
}

void Swarm::step(uint32_t steps) {
    for (uint32_t s = 0; s < steps; ++s) {
        if (behavior_) {
            run_stages(steps_);
        } else {
            set_args(integrate_, pos_.get(), vel_.get(), cl_uint(total_agents()), config_.dt);
            launch(*ctx_, integrate_, total_agents());
        }
        grid_current_ = false;
        ++steps_;
    }
}

SwarmState Swarm::export_state() {
    SwarmState st;
    const size_t total = total_agents();
    st.steps = steps_;
    st.positions.resize(total);
    st.velocities.resize(total);
    st.ids.resize(total);
    pos_.download(*ctx_, st.positions.data(), total);
    vel_.download(*ctx_, st.velocities.data(), total);
    ids_.download(*ctx_, st.ids.data(), total);
    st.stats = stats_.peek(*this);
    if (worlds_ > 1) st.world_stats = stats_.peek_worlds(*this);
    return st;
}

void Swarm::import_state(const SwarmState& st) {
    const size_t total = st.ids.size();
    auto bad = [](const std::string& why) { fail(Status::Parse, "checkpoint agent state: " + why); };
    if (total % worlds_ != 0)
        bad(std::to_string(total) + " agents cannot be shared by " + std::to_string(worlds_) + " worlds");
    const size_t n = total / worlds_;
    if (n > config_.capacity)
        bad(std::to_string(n) + " agents exceed the swarm's capacity " + std::to_string(config_.capacity));
    if (st.positions.size() != total || st.velocities.size() != total) bad("positions, velocities and ids differ in count");
    // ids index slot_of on the device: in each world a permutation of 0..n-1.
    std::vector<bool> seen(total, false);
    for (size_t s = 0; s < total; ++s) {
        const cl_uint id = st.ids[s];
        const size_t at = s / (n ? n : 1) * n + id;
        if (id >= n || seen[at])
            bad("the agent ids are not a permutation of 0.." + std::to_string(n) + "-1" +
                (worlds_ > 1 ? " in world " + std::to_string(s / n) : std::string()));
        seen[at] = true;
    }
    for (size_t i = 0; i < total; ++i)
        for (int a = 0; a < 3; ++a)  // xyz: w is the models' to use
            if (!std::isfinite(st.positions[i].s[a]) || !std::isfinite(st.velocities[i].s[a]))
                bad("agent " + std::to_string(st.ids[i]) + " has a value that is not finite");
    if (st.stats.mde_moved_total > 0xFFFFFFFFu) bad("the MDE counter exceeds 32 bits");
    if (!st.world_stats.empty() && st.world_stats.size() != worlds_)
        bad("step statistics for " + std::to_string(st.world_stats.size()) + " worlds, the swarm has " +
            std::to_string(worlds_));
    for (const StepStats& w : st.world_stats)
        if (w.mde_moved_total > 0xFFFFFFFFu) bad("the MDE counter exceeds 32 bits");
    if (total) {
        pos_.upload(*ctx_, st.positions.data(), total);
        vel_.upload(*ctx_, st.velocities.data(), total);
        ids_.upload(*ctx_, st.ids.data(), total);
    }
    n_ = uint32_t(n);
    steps_ = st.steps;
    grid_.invalidate_layout();  // the next build sorts every agent, to the same (cell, id) order
    grid_current_ = false;
    slot_of_current_ = false;
    if (st.world_stats.empty()) {
        restore_step_stats(st.stats);
    } else {
        restore_world_step_stats(st.world_stats);
    }
}

void Swarm::restore_step_stats(const StepStats& stats) {
    require(stats.mde_moved_total <= 0xFFFFFFFFu, "step statistics: the MDE counter exceeds 32 bits");
    require(worlds_ == 1, "step statistics of one world for a swarm of " + std::to_string(worlds_));
    stats_.restore(*ctx_, {stats});
}

void Swarm::restore_world_step_stats(const std::vector<StepStats>& stats) {
    require(stats.size() == worlds_, "step statistics: one per world expected");
    for (const StepStats& w : stats)
        require(w.mde_moved_total <= 0xFFFFFFFFu, "step statistics: the MDE counter exceeds 32 bits");
    stats_.restore(*ctx_, stats);
}

cl_uint Swarm::set_step_args(cl::Kernel& kernel, uint64_t step, cl_uint index) {
    const float dt = config_.dt;
    kernel.setArg(index++, pos_.get());
    kernel.setArg(index++, vel_.get());
    kernel.setArg(index++, ids_.get());
    kernel.setArg(index++, n_);
    kernel.setArg(index++, dt);
    kernel.setArg(index++, float(double(step) * dt));
    kernel.setArg(index++, cl_uint(step));
    return index;
}

void Swarm::swap_positions_with_scratch() {
    std::swap(pos_, scratch_);
    grid_current_ = false;
}

void Swarm::ensure_grid() {
    if (grid_current_) return;
    const uint32_t total = uint32_t(total_agents());
    grid_.build(pos_, ids_, total, n_);
    grid_.reorder_state(pos_, vel_, ids_, scratch_, vel_scratch_, ids_scratch_, total);
    slot_of_current_ = false;
    grid_current_ = true;
}

void Swarm::ensure_slot_of() {
    if (slot_of_current_) return;
    set_args(slot_of_k_, ids_.get(), cl_uint(total_agents()), n_ ? n_ : 1u, slot_of_.get());
    launch(*ctx_, slot_of_k_, total_agents());
    slot_of_current_ = true;
}

// Models that do not run worlds (swarm/behavior.hpp).
void Behavior::set_world_param(Swarm&, const std::string& key, const double*, size_t) {
    fail(Status::InvalidArgument, "this model has no per-world parameters yet (setting '" + key + "')");
}
std::vector<double> Behavior::world_param(const std::string& key) const {
    fail(Status::InvalidArgument, "this model has no per-world parameters yet (reading '" + key + "')");
}

// Models that do not implement checkpoints (swarm/behavior.hpp).
void Behavior::save_checkpoint(Swarm&, ByteWriter&, ByteWriter&) {
    fail(Status::InvalidArgument, "this model cannot be saved in a checkpoint");
}
void Behavior::restore_checkpoint(Swarm&, ByteReader&) {
    fail(Status::InvalidArgument, "this model cannot be restored from a checkpoint");
}

namespace {
void check_radius(float radius, const char* what) {
    require(std::isfinite(radius) && radius > 0.0f, std::string(what) + ": radius must be a finite number > 0");
}
}  // namespace

void Swarm::neighbor_count(float radius, uint32_t* out_counts, size_t count) {
    const char* what = "swcl_swarm_neighbor_count";
    check_radius(radius, what);
    require(out_counts != nullptr || count == 0, std::string(what) + ": out_counts is NULL");
    check_count(count, what);
    ensure_grid();
    const size_t total = total_agents();
    query_u32_.reserve(*ctx_, total, "query results");
    cl_uint i = 0;
    count_.setArg(i++, pos_.get());
    count_.setArg(i++, ids_.get());
    count_.setArg(i++, n_);
    i = grid_.set_world_grid_args(count_, i);
    count_.setArg(i++, radius);
    count_.setArg(i++, query_u32_.get());
    check_arg_count(count_, i);
    launch_worlds(*ctx_, count_, (size_t(n_) + lanes_ - 1) / lanes_, worlds_);
    query_u32_.download(*ctx_, out_counts, total);
}

void Swarm::nearest_neighbor(float* out_distances, uint32_t* out_ids, size_t count) {
    const char* what = "swcl_swarm_nearest_neighbor";
    require(out_distances != nullptr || count == 0, std::string(what) + ": out_distances is NULL");
    check_count(count, what);
    ensure_grid();
    const size_t total = total_agents();
    query_f32_.reserve(*ctx_, total, "query results");
    query_u32_.reserve(*ctx_, total, "query results");
    cl_uint i = 0;
    nearest_.setArg(i++, pos_.get());
    nearest_.setArg(i++, ids_.get());
    nearest_.setArg(i++, n_);
    i = grid_.set_world_grid_args(nearest_, i);
    nearest_.setArg(i++, query_f32_.get());
    nearest_.setArg(i++, query_u32_.get());
    check_arg_count(nearest_, i);
    launch_worlds(*ctx_, nearest_, n_, worlds_);
    query_f32_.download(*ctx_, out_distances, total);
    if (out_ids) query_u32_.download(*ctx_, out_ids, total);
}

uint32_t Swarm::neighbor_lists(float radius, uint32_t cap, uint32_t* out_ids, uint32_t* out_counts,
                               size_t count) {
    const char* what = "swcl_swarm_neighbor_lists";
    check_radius(radius, what);
    require(cap > 0, std::string(what) + ": max_neighbors must be > 0");
    require(out_ids != nullptr || count == 0, std::string(what) + ": out_ids is NULL");
    require(out_counts != nullptr || count == 0, std::string(what) + ": out_counts is NULL");
    check_count(count, what);
    const size_t total = total_agents();
    const uint64_t entries = uint64_t(total) * cap;
    if (entries * sizeof(cl_uint) > ctx_->max_allocation())
        fail(Status::OutOfMemory, std::string(what) + ": " + std::to_string(total) + " agents x " +
                                      std::to_string(cap) + " neighbours exceed the device's largest allocation");
    ensure_grid();
    DeviceBuffer<cl_uint> lists(*ctx_, size_t(entries), "neighbour lists");
    query_u32_.reserve(*ctx_, total, "query results");
    cl_uint i = 0;
    lists_.setArg(i++, pos_.get());
    lists_.setArg(i++, ids_.get());
    lists_.setArg(i++, n_);
    i = grid_.set_world_grid_args(lists_, i);
    lists_.setArg(i++, radius);
    lists_.setArg(i++, cap);
    lists_.setArg(i++, lists.get());
    lists_.setArg(i++, query_u32_.get());
    check_arg_count(lists_, i);
    launch_worlds(*ctx_, lists_, n_, worlds_);
    lists.download(*ctx_, out_ids, size_t(entries));
    query_u32_.download(*ctx_, out_counts, total);
    uint32_t truncated = 0;
    for (size_t a = 0; a < total; ++a) truncated += out_counts[a] > cap ? 1u : 0u;
    return truncated;
}

}  // namespace swarmcl
