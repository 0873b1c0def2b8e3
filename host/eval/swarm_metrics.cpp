#include "eval/swarm_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "fields/noise_field.hpp"

namespace swarmcl {
namespace {
// Values per block of the moments (metrics_moments): each block's moments in
// float, the blocks merged on the host in double.
constexpr uint32_t kBlock = 64;

std::string metric_defines(uint32_t block, bool atomic) {
    using namespace fine_bins;
    return "-DFB_SHIFT=" + std::to_string(kShift) + "u -DFB_LOW_KEY=" + std::to_string(kLowKey) +
           "u -DFB_SIDE=" + std::to_string(kSide) + "u -DFB_COUNT=" + std::to_string(fine_bins::kCount) +
           "u -DMETRICS_BLOCK=" + std::to_string(block) + "u -DHIST_ATOMIC=" + (atomic ? "1" : "0") +
           metric_kernel_defines();
}

}  // namespace

SwarmMetrics::SwarmMetrics(Swarm& swarm, double dt_between_samples)
    : swarm_(swarm), ctx_(swarm.context()), dt_(dt_between_samples), n_(swarm.agent_count()),
      worlds_(swarm.worlds()), total_(0), groups_(0), grid_(swarm.context()) {
    require(std::isfinite(dt_between_samples) && dt_between_samples > 0.0 &&
                float(dt_between_samples) > 0.0f && std::isfinite(float(dt_between_samples)),
            "metrics: the time between samples must be finite and > 0");
    require(n_ >= 2, worlds_ > 1 ? "metrics: each world needs at least 2 agents (the nearest-neighbour distance d)"
                                 : "metrics: the swarm needs at least 2 agents (the nearest-neighbour distance d)");
    require(swarm.total_agents() <= 0xffffffffu, "metrics: more than 2^32 - 1 agents in all worlds");
    total_ = uint32_t(swarm.total_agents());
    groups_ = (size_t(n_) + kBlock - 1) / kBlock;
    // CPU devices: histogram copies per chunk of agents, counted with plain
    // increments by metrics_histogram (2 chunks per compute unit in all, at
    // least one a world); GPUs: one histogram a world, atomic_inc.
    const bool cpu = ctx_.device().cpu_profile;
    const uint32_t chunks = 2 * std::max<uint32_t>(1, ctx_.device().compute_units);
    copies_ = cpu ? (chunks + worlds_ - 1) / worlds_ : 1;
    lanes_ = preferred_noise_width(ctx_.device());  // 1 on GPUs; SWARMCL_NOISE_WIDTH
    const std::string defines =
        metric_defines(kBlock, !cpu) + (lanes_ > 1 ? " -DNOISE_WIDTH=" + std::to_string(lanes_) : "");
    gather_ = ctx_.kernel("metrics.cl", "metrics_gather", defines);
    sample_ = ctx_.kernel("metrics.cl", lanes_ > 1 ? "metrics_sample_w" : "metrics_sample", defines);
    // 16 consecutive sorted points share boxes: 1 cell a point instead of 8
    // puts more of them in a row of cells (17.7 -> 16.1 ms a frame of 100k
    // agents at 2, about 4 % less again at 1 with the rows apart;
    // docs/benchmarks.md); one point a work-item keeps the 8.  The rows
    // apart (a box each row of cells the lanes lie in) where a row of the
    // world's cells is expected to hold at least as many points as lanes: 16
    // consecutive points then span one or two rows; in a fit's small worlds
    // (1,024 cells for 300 agents, 3 a row) one box over all lanes is smaller.
    if (lanes_ > 1) grid_.set_cells_per_point(1);
    const double rows = std::pow(double(grid_.cells_for(n_)), 2.0 / 3.0);
    const bool rows_apart = lanes_ > 1 && double(n_) >= double(lanes_) * rows;
    nearest_ = ctx_.kernel("metrics.cl", lanes_ > 1 ? "metrics_nearest_w" : "metrics_nearest",
                           defines + (rows_apart ? " -DMN_ROWS_APART=1" : ""));
    sort_ = ctx_.kernel("metrics.cl", "metrics_sort_points", defines);
    moments_ = ctx_.kernel("metrics.cl", "metrics_moments", defines);
    if (cpu) histogram_ = ctx_.kernel("metrics.cl", "metrics_histogram", defines);
    const uint32_t n = total_;
    for (auto& r : ring_) r.allocate(ctx_, n, "metrics position ring");
    nn_idx_.allocate(ctx_, n, "metrics nearest neighbours");
    sorted_.allocate(ctx_, n, "metrics sorted points");
    vals_.allocate(ctx_, kMetricCount * size_t(n), "metrics values of a sample");
    omega_.allocate(ctx_, n, "metrics angular velocities");
    omega_.fill(ctx_, cl_float2{{std::numeric_limits<float>::quiet_NaN(), 0.0f}}, n);
    nn_dist_.allocate(ctx_, n, "metrics nearest distances");
    nn_idx_.fill(ctx_, 0u, n);  // written by every sample before use; defined anyway
    nn_dist_.fill(ctx_, 0.0f, n);
    hist_.allocate(ctx_, size_t(worlds_) * copies_ * kMetricCount * size_t(fine_bins::kCount),
                   "metrics histograms");
    hist_.fill(ctx_, 0u, hist_.size());
    world_moments_.resize(worlds_);
    for (int b = 0; b < 2; ++b) {
        part_[b].allocate(ctx_, kMetricCount * groups_ * worlds_, "metrics moments");
        // Sample 0 writes only d's moments: the others read as empty.
        part_[b].fill(ctx_, cl_float4{{0.0f, 0.0f, 0.0f, 0.0f}}, part_[b].size());
        host_part_[b].resize(part_[b].size());
    }
}

SwarmMetrics::~SwarmMetrics() {
    // A read into host_part_ may still be queued.
    try {
        ctx_.queue().finish();
    } catch (...) {
    }
}

size_t SwarmMetrics::device_bytes() const {
    const size_t n = total_;
    size_t b = 5 * n * sizeof(cl_float4) + n * (sizeof(cl_uint) + sizeof(cl_float)) +
               kMetricCount * n * sizeof(cl_float) + n * sizeof(cl_float2) + hist_.size() * sizeof(cl_uint) +
               2 * part_[0].size() * sizeof(cl_float4);
    // The point grid: keys and slots twice, cell starts (at most max_cells + 1
    // a world).
    b += 4 * n * sizeof(cl_uint) + (size_t(PointGrid::max_cells(n_)) * worlds_ + 1) * sizeof(cl_uint);
    return b;
}

void SwarmMetrics::sample() {
    require(swarm_.agent_count() == n_ && swarm_.worlds() == worlds_,
            "metrics: the swarm's agent count changed since sampling began");
    // Device counters are 32-bit: fold them into the host's before a sample
    // could overflow one (each sample adds at most n per metric).
    if ((since_fold_ + 1) * uint64_t(n_) > fold_limit_) fold_histogram();
    const uint64_t s = samples_;
    const uint32_t buf = uint32_t(s % 2);
    auto& cur = ring_[s % 4];
    const uint32_t n = total_;
    set_args(gather_, swarm_.positions().get(), swarm_.ids().get(), n, n_, cur.get());
    launch(ctx_, gather_, n);
    const cl_uint groups = cl_uint(groups_), blocks = cl_uint(groups_ * worlds_);
    if (s >= 1) {
        auto& r1 = ring_[(s + 3) % 4];
        auto& r2 = s >= 2 ? ring_[(s + 2) % 4] : cur;
        auto& r3 = s >= 3 ? ring_[(s + 1) % 4] : cur;
        const cl_uint have = cl_uint(std::min<uint64_t>(s, 3));
        set_args(sample_, cur.get(), r1.get(), r2.get(), r3.get(), n, n_, have, cl_float(dt_), nn_idx_.get(),
                 nn_dist_.get(), omega_.get(), hist_.get(), vals_.get());
        launch(ctx_, sample_, lanes_ > 1 ? (n + lanes_ - 1) / lanes_ : n);
    }
    // Cells of the bounding box at most 8 per point of a world (PointGrid's
    // own bound), each world its own cells: exact at any cell size, so the
    // size only sets the speed.
    grid_.build_groups(cur, n, worlds_, 0.0f);
    set_args(sort_, cur.get(), grid_.sorted_slots().get(), n, sorted_.get());
    launch(ctx_, sort_, n);
    set_args(nearest_, sorted_.get(), n, n_, grid_.geometry().get(), grid_.cell_start().get(), nn_idx_.get(),
             nn_dist_.get(), hist_.get(), vals_.get());
    if (lanes_ > 1) launch_worlds(ctx_, nearest_, (n_ + lanes_ - 1) / lanes_, worlds_);
    else launch(ctx_, nearest_, n);
    // Sample 0 has d only: the other metrics' moments stay empty (filled
    // with zeros at construction, never written for sample 0).
    const cl_uint mask = s >= 1 ? (1u << kMetricCount) - 1u : 1u << uint32_t(Metric::NearestDistance);
    set_args(moments_, vals_.get(), n, n_, groups, mask, blocks, part_[buf].get());
    launch(ctx_, moments_, blocks);
    if (ctx_.device().cpu_profile) {
        const cl_uint chunks = cl_uint(copies_ * worlds_);
        set_args(histogram_, vals_.get(), n, n_, copies_, mask, chunks, hist_.get());
        launch_chunks(ctx_, histogram_, chunks);
    }
    ctx_.queue().enqueueReadBuffer(part_[buf].get(), CL_FALSE, 0, part_[buf].size() * sizeof(cl_float4),
                                   host_part_[buf].data(), nullptr, &read_done_[buf]);
    // One sample in flight: the device runs ahead while the host merges.
    if (pending_ >= 0) fold_partials(uint32_t(pending_ % 2));
    pending_ = int64_t(s);
    ++samples_;
    ++since_fold_;
}

void SwarmMetrics::fold_partials(uint32_t buffer) {
    read_done_[buffer].wait();
    const auto& p = host_part_[buffer];
    const size_t blocks = groups_ * worlds_;
    for (uint32_t w = 0; w < worlds_; ++w)
        for (size_t m = 0; m < kMetricCount; ++m) {
            RawMoments sum;
            for (size_t g = 0; g < groups_; ++g) {
                const cl_float4& q = p[m * blocks + w * groups_ + g];
                RawMoments r;
                r.count = uint64_t(q.s[0]);  // at most kBlock: exact in float
                r.mean = q.s[1];
                r.m2 = q.s[2];
                sum.merge(r);
            }
            world_moments_[w][m].merge(sum);
        }
    pending_ = -1;
}

// The copies [world copies, (world + 1) copies) of h, summed into `to`.
void SwarmMetrics::add_device_histograms(const std::vector<cl_uint>& h, uint32_t world,
                                         MetricAccumulator& to) const {
    const size_t per_copy = kMetricCount * size_t(fine_bins::kCount);
    std::vector<uint64_t> wide(fine_bins::kCount);
    for (size_t m = 0; m < kMetricCount; ++m) {
        std::fill(wide.begin(), wide.end(), 0);
        for (uint32_t c = 0; c < copies_; ++c) {
            const cl_uint* src = h.data() + (size_t(world) * copies_ + c) * per_copy + m * fine_bins::kCount;
            for (uint32_t b = 0; b < fine_bins::kCount; ++b) wide[b] += src[b];
        }
        to.add_raw(Metric(m), wide.data(), RawMoments{});
    }
}

void SwarmMetrics::fold_histogram() {
    std::vector<cl_uint> h(hist_.size());
    hist_.download(ctx_, h.data(), h.size());
    if (folded_.empty()) folded_.resize(worlds_);
    for (uint32_t w = 0; w < worlds_; ++w) add_device_histograms(h, w, folded_[w]);
    hist_.fill(ctx_, 0u, hist_.size());
    since_fold_ = 0;
}

MetricAccumulator SwarmMetrics::result(uint32_t world) {
    require(world < worlds_, "metrics: no world " + std::to_string(world) + " in a swarm of " +
                                 std::to_string(worlds_) + " worlds");
    if (pending_ >= 0) fold_partials(uint32_t(pending_ % 2));
    MetricAccumulator out = folded_.empty() ? MetricAccumulator() : folded_[world];
    // World k's histogram copies only.
    const size_t per_world = copies_ * kMetricCount * size_t(fine_bins::kCount);
    std::vector<cl_uint> h(per_world);
    ctx_.queue().enqueueReadBuffer(hist_.get(), CL_TRUE, size_t(world) * per_world * sizeof(cl_uint),
                                   per_world * sizeof(cl_uint), h.data());
    add_device_histograms(h, 0, out);
    for (size_t m = 0; m < kMetricCount; ++m) out.add_raw(Metric(m), nullptr, world_moments_[world][m]);
    return out;
}

}  // namespace swarmcl
