#include "eval/swarm_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "core/error.hpp"

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
      groups_(0), grid_(swarm.context()) {
    swarm.require_one_world("metrics of a swarm");
    require(std::isfinite(dt_between_samples) && dt_between_samples > 0.0 &&
                float(dt_between_samples) > 0.0f && std::isfinite(float(dt_between_samples)),
            "metrics: the time between samples must be finite and > 0");
    require(n_ >= 2, "metrics: the swarm needs at least 2 agents (the nearest-neighbour distance d)");
    groups_ = (size_t(n_) + kBlock - 1) / kBlock;
    // CPU devices: histogram copies per chunk of agents, counted with plain
    // increments by metrics_histogram (2 chunks per compute unit); GPUs:
    // one histogram, atomic_inc.
    copies_ = ctx_.device().cpu_profile ? 2 * std::max<uint32_t>(1, ctx_.device().compute_units) : 1;
    const std::string defines = metric_defines(kBlock, copies_ == 1);
    gather_ = ctx_.kernel("metrics.cl", "metrics_gather", defines);
    sample_ = ctx_.kernel("metrics.cl", "metrics_sample", defines);
    nearest_ = ctx_.kernel("metrics.cl", "metrics_nearest", defines);
    sort_ = ctx_.kernel("metrics.cl", "metrics_sort_points", defines);
    moments_ = ctx_.kernel("metrics.cl", "metrics_moments", defines);
    if (copies_ > 1) histogram_ = ctx_.kernel("metrics.cl", "metrics_histogram", defines);
    for (auto& r : ring_) r.allocate(ctx_, n_, "metrics position ring");
    nn_idx_.allocate(ctx_, n_, "metrics nearest neighbours");
    sorted_.allocate(ctx_, n_, "metrics sorted points");
    vals_.allocate(ctx_, kMetricCount * size_t(n_), "metrics values of a sample");
    omega_.allocate(ctx_, n_, "metrics angular velocities");
    omega_.fill(ctx_, cl_float2{{std::numeric_limits<float>::quiet_NaN(), 0.0f}}, n_);
    nn_dist_.allocate(ctx_, n_, "metrics nearest distances");
    nn_idx_.fill(ctx_, 0u, n_);  // written by every sample before use; defined anyway
    nn_dist_.fill(ctx_, 0.0f, n_);
    hist_.allocate(ctx_, copies_ * kMetricCount * size_t(fine_bins::kCount), "metrics histograms");
    hist_.fill(ctx_, 0u, hist_.size());
    for (int b = 0; b < 2; ++b) {
        part_[b].allocate(ctx_, kMetricCount * groups_, "metrics moments");
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
    size_t b = 5 * size_t(n_) * sizeof(cl_float4) + size_t(n_) * (sizeof(cl_uint) + sizeof(cl_float)) +
               kMetricCount * size_t(n_) * sizeof(cl_float) + size_t(n_) * sizeof(cl_float2) +
               hist_.size() * sizeof(cl_uint) + 2 * part_[0].size() * sizeof(cl_float4);
    // The point grid: keys and slots twice, cell starts (at most max_cells + 1).
    b += 4 * size_t(n_) * sizeof(cl_uint) + (size_t(PointGrid::max_cells(n_)) + 1) * sizeof(cl_uint);
    return b;
}

void SwarmMetrics::sample() {
    require(swarm_.agent_count() == n_, "metrics: the swarm's agent count changed since sampling began");
    // Device counters are 32-bit: fold them into the host's before a sample
    // could overflow one (each sample adds at most n per metric).
    if ((since_fold_ + 1) * uint64_t(n_) > fold_limit_) fold_histogram();
    const uint64_t s = samples_;
    const uint32_t buf = uint32_t(s % 2);
    auto& cur = ring_[s % 4];
    set_args(gather_, swarm_.positions().get(), swarm_.ids().get(), n_, cur.get());
    launch(ctx_, gather_, n_);
    const cl_uint groups = cl_uint(groups_);
    if (s >= 1) {
        auto& r1 = ring_[(s + 3) % 4];
        auto& r2 = s >= 2 ? ring_[(s + 2) % 4] : cur;
        auto& r3 = s >= 3 ? ring_[(s + 1) % 4] : cur;
        const cl_uint have = cl_uint(std::min<uint64_t>(s, 3));
        set_args(sample_, cur.get(), r1.get(), r2.get(), r3.get(), n_, have, cl_float(dt_), nn_idx_.get(),
                 nn_dist_.get(), omega_.get(), hist_.get(), vals_.get());
        launch(ctx_, sample_, n_);
    }
    // Cells of the bounding box at most 8 per point (PointGrid's own bound):
    // exact at any cell size, so the size only sets the speed.
    grid_.build(cur, n_, 0.0f);
    set_args(sort_, cur.get(), grid_.sorted_slots().get(), n_, sorted_.get());
    launch(ctx_, sort_, n_);
    set_args(nearest_, sorted_.get(), n_, grid_.geometry().get(), grid_.cell_start().get(), nn_idx_.get(),
             nn_dist_.get(), hist_.get(), vals_.get());
    launch(ctx_, nearest_, n_);
    // Sample 0 has d only: the other metrics' moments stay empty (filled
    // with zeros at construction, never written for sample 0).
    const cl_uint mask = s >= 1 ? (1u << kMetricCount) - 1u : 1u << uint32_t(Metric::NearestDistance);
    set_args(moments_, vals_.get(), n_, mask, groups, part_[buf].get());
    launch(ctx_, moments_, groups_);
    if (copies_ > 1) {
        set_args(histogram_, vals_.get(), n_, mask, copies_, hist_.get());
        launch_chunks(ctx_, histogram_, copies_);
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
    for (size_t m = 0; m < kMetricCount; ++m) {
        RawMoments sum;
        for (size_t g = 0; g < groups_; ++g) {
            const cl_float4& q = p[m * groups_ + g];
            RawMoments r;
            r.count = uint64_t(q.s[0]);  // at most kBlock: exact in float
            r.mean = q.s[1];
            r.m2 = q.s[2];
            sum.merge(r);
        }
        folded_.add_raw(Metric(m), nullptr, sum);
    }
    pending_ = -1;
}

void SwarmMetrics::add_device_histograms(MetricAccumulator& to) {
    std::vector<cl_uint> h(hist_.size());
    hist_.download(ctx_, h.data(), h.size());
    const size_t per_copy = kMetricCount * size_t(fine_bins::kCount);
    std::vector<uint64_t> wide(fine_bins::kCount);
    for (size_t m = 0; m < kMetricCount; ++m) {
        std::fill(wide.begin(), wide.end(), 0);
        for (uint32_t c = 0; c < copies_; ++c)
            for (uint32_t b = 0; b < fine_bins::kCount; ++b) wide[b] += h[c * per_copy + m * fine_bins::kCount + b];
        to.add_raw(Metric(m), wide.data(), RawMoments{});
    }
}

void SwarmMetrics::fold_histogram() {
    add_device_histograms(folded_);
    hist_.fill(ctx_, 0u, hist_.size());
    since_fold_ = 0;
}

MetricAccumulator SwarmMetrics::result() {
    if (pending_ >= 0) fold_partials(uint32_t(pending_ % 2));
    MetricAccumulator out = folded_;
    add_device_histograms(out);
    return out;
}

}  // namespace swarmcl
