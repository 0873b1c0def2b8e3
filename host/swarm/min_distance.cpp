#include "swarm/min_distance.hpp"

#include <algorithm>
#include <cstdlib>
#include <string>

#include "core/error.hpp"
#include "fields/noise_field.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

StepCounters::StepCounters(Context& ctx, uint32_t worlds)
    : moved_(ctx, size_t(2) * worlds, "MDE counters"), worlds_(worlds) {
    moved_.fill(ctx, 0u, size_t(2) * worlds_);
}

void StepCounters::reset(Context& ctx) {
    moved_.fill(ctx, 0u, size_t(2) * worlds_);
    steps_ = 0;
}

std::vector<StepStats> StepCounters::read(Swarm& swarm) {
    std::vector<cl_uint> counts(size_t(2) * worlds_);
    moved_.download(swarm.context(), counts.data(), counts.size());
    std::vector<StepStats> out(worlds_);
    for (uint32_t k = 0; k < worlds_; ++k) {
        out[k].agents = swarm.agent_count();
        out[k].mde_moved_last = counts[k];
        out[k].mde_moved_total = counts[worlds_ + k];
        out[k].steps = steps_;
    }
    return out;
}

namespace {
StepStats summed(const std::vector<StepStats>& worlds) {
    StepStats s = worlds.at(0);
    for (size_t k = 1; k < worlds.size(); ++k) {
        s.agents += worlds[k].agents;
        s.mde_moved_last += worlds[k].mde_moved_last;
        s.mde_moved_total += worlds[k].mde_moved_total;
    }
    return s;
}
}  // namespace

std::vector<StepStats> StepCounters::take_worlds(Swarm& swarm) {
    std::vector<StepStats> out = read(swarm);
    reset(swarm.context());
    return out;
}

StepStats StepCounters::take(Swarm& swarm) { return summed(take_worlds(swarm)); }

StepStats StepCounters::peek(Swarm& swarm) { return summed(read(swarm)); }

void StepCounters::restore(Context& ctx, const std::vector<StepStats>& stats) {
    require(stats.size() == worlds_, "step statistics: one per world expected");
    // moved[W + k] is a 32-bit device counter (the total since the last read).
    std::vector<cl_uint> counts(size_t(2) * worlds_);
    for (uint32_t k = 0; k < worlds_; ++k) {
        counts[k] = stats[k].mde_moved_last;
        counts[worlds_ + k] = cl_uint(stats[k].mde_moved_total);
    }
    moved_.upload(ctx, counts.data(), counts.size());
    steps_ = stats[0].steps;
}

namespace {
// Measured on 1M agents at 0.05 m (2-core PoCL CPU, CPU time of the pass):
// the wide kernel takes 0.55x the scalar one's at cells of 2 d_min, the same
// at 3 and 4 d_min, 1.6x at 6 d_min.  Since it prefetches its cell starts
// (1M locusts, AVX-512 EPYC, d_min 0.1 m): 0.8x at 4.4 d_min, about the same
// at 6, 1.3x at 9 and 1.8x at 12.  Since its any() is one mask test
// (kernels/lib/lanes.cl), the whole field step of 200k agents, wide / scalar
// (bench/mde_kernel_bench.py, 2-core Xeon with AVX-512, 2026-12-02,
// bench/results/mde_kernel.json): 0.82 at cells of 5 d_min, 0.88 at 7.5,
// 0.96 at 10, 1.13 at 14, 1.24 at 20 (with a goal gathering them 0.84, 0.93,
// 1.04, 1.21, 1.37).
constexpr float kWideCellPerDistance = 8.0f;
// Worlds (or swarms) of at most kSmallWorld agents run it up to cells of
// kSmallWorldCellPerDistance d_min: a fit's 64 worlds of 300 agents (the
// same bench and JSON), wide / scalar 0.82, 0.80 and 0.84 of the step at
// about 10, 14 and 20 d_min with the goal gathering them, 0.91, 0.93 and
// 0.95 without.  (Between 300 and 200k agents a world the bound is a guess.)
constexpr uint32_t kSmallWorld = 4096;
constexpr float kSmallWorldCellPerDistance = 20.0f;
// The explicit-width kernel where the noise module uses one (CPU devices;
// $SWARMCL_NOISE_WIDTH = 1 selects the scalar kernel everywhere).
uint32_t mde_width(Context& ctx) { return preferred_noise_width(ctx.device()); }
}  // namespace

namespace {
StepStages one_world(float d_min, uint64_t seed) {
    StepStages st;
    st.min_distance = d_min;
    st.seed = seed;
    return st;
}
template <typename T>
std::vector<T> per_world(const std::vector<T>& given, T all, uint32_t worlds) {
    return given.empty() ? std::vector<T>(worlds, all) : given;
}
}  // namespace

MinDistance::MinDistance(Context& ctx, float d_min, uint64_t seed) : MinDistance(ctx, one_world(d_min, seed), 1) {}

MinDistance::MinDistance(Context& ctx, const StepStages& st, uint32_t worlds)
    : d_min_(per_world(st.world_min_distance, st.min_distance, worlds)),
      seed_(per_world(st.world_seed, st.seed, worlds)), width_(mde_width(ctx)),
      kernel_choice_(std::getenv("SWARMCL_MDE_KERNEL") ? std::getenv("SWARMCL_MDE_KERNEL") : ""),
      kernel_(ctx.kernel("min_distance.cl", "min_distance_enforce", world_defines(worlds))) {
    require(d_min_.size() == worlds && seed_.size() == worlds,
            "minimum distance enforcement: one distance and seed per world expected");
    d_min_smallest_ = *std::min_element(d_min_.begin(), d_min_.end());
    if (width_ > 1)
        wide_ = ctx.kernel("min_distance.cl", "min_distance_enforce_w",
                           "-DMDE_WIDTH=" + std::to_string(width_) + world_defines(worlds));
    d_min_buf_.allocate(ctx, worlds, "MDE distances");
    d_min_buf_.upload(ctx, d_min_.data(), worlds);
    seed_buf_.allocate(ctx, worlds, "MDE seeds");
    seed_buf_.upload(ctx, reinterpret_cast<const cl_ulong*>(seed_.data()), worlds);
}

bool MinDistance::matches(const StepStages& st, uint32_t worlds) const {
    return d_min_ == per_world(st.world_min_distance, st.min_distance, worlds) &&
           seed_ == per_world(st.world_seed, st.seed, worlds);
}

bool MinDistance::uses_wide_kernel(const GridGeometry& g, uint32_t n, uint32_t world_agents) const {
    // The wide kernel pays off where each agent's box holds few candidates:
    // cells of at most kWideCellPerDistance * d_min (the scalar kernel's long
    // loops over big cells predict well), or kSmallWorldCellPerDistance in
    // small worlds.  $SWARMCL_MDE_KERNEL ("wide" or "scalar", read when the
    // pass is made) overrides the choice, for benchmarks
    // (bench/mde_kernel_bench.py).
    // Its lanes index floats and cells as 32-bit ints.
    const float limit = world_agents <= kSmallWorld ? kSmallWorldCellPerDistance : kWideCellPerDistance;
    const bool small_cells =
        kernel_choice_.empty() ? g.cell <= limit * d_min_smallest_ : kernel_choice_ == "wide";
    return width_ > 1 && small_cells && uint64_t(n) * 4 < (uint64_t(1) << 31) &&
           uint64_t(g.cell_count()) + 1 < (uint64_t(1) << 31);
}

void MinDistance::apply(Swarm& swarm, DeviceBuffer<cl_uint>& moved) {
    swarm.ensure_grid();
    const uint32_t n = swarm.agent_count(), worlds = swarm.worlds();
    require(worlds == d_min_.size(), "minimum distance enforcement: built for another number of worlds");
    bool wide = true;  // where every world's grid suits it
    for (uint32_t k = 0; k < worlds; ++k)
        wide = wide && uses_wide_kernel(swarm.grid().world_geometry(k), uint32_t(swarm.total_agents()), n);
    cl::Kernel& k = wide ? wide_ : kernel_;
    cl_uint i = 0;
    k.setArg(i++, swarm.positions().get());
    k.setArg(i++, swarm.ids().get());
    k.setArg(i++, n);
    i = swarm.grid().set_world_grid_args(k, i);
    k.setArg(i++, d_min_buf_.get());
    k.setArg(i++, seed_buf_.get());
    k.setArg(i++, swarm.scratch().get());
    k.setArg(i++, moved.get());
    check_arg_count(k, i);
    fill_buffer(swarm.context(), moved.get(), cl_uint(0), 0, sizeof(cl_uint) * worlds);
    launch_worlds(swarm.context(), k, wide ? (n + width_ - 1) / width_ : n, worlds);
    swarm.swap_positions_with_scratch();
}

}  // namespace swarmcl
