// The seven metrics (noise paper §3.2) of a running swarm, any model,
// computed on the device frame by frame (kernels/metrics.cl) and streamed
// into fine histograms and moments (eval/metric_accumulator.hpp): memory is
// fixed by the agent count (a ring of the last 4 sampled positions, the
// positions in grid order, the nearest neighbours of the last frame, each
// agent's last ω, one sample's values, the point grid) and the histograms
// (7 x 61444 counters; one copy per chunk of agents on CPU devices), not by
// the number of frames.  Holds a reference to
// the swarm: destroy it first.
//
// Use: step the swarm K steps, sample(), repeat; result() at any time.  The
// samples are frames dt_between_samples apart (K times the swarm's dt), as
// if the positions of every sample were recorded and given to
// frame_metrics(): v, η of a frame are known one sample later (forward
// differences), a, ω two and α, μ three samples later; the last frame has
// d only.
//
// Worlds (docs/architecture.md, "Worlds"): a swarm of W worlds gets W sets
// of metrics from the same launches, each world's from its own agents only
// (nearest neighbours within the world, its own histograms and blocks of
// moments), bitwise what SwarmMetrics gives for the world's swarm alone;
// result(k) is world k's.  Each world holds its own histograms on the device
// (7 x 61444 counters, 1.7 MB).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "device/buffer.hpp"
#include "eval/metric_accumulator.hpp"
#include "spatial/point_grid.hpp"
#include "swarm/swarm.hpp"

namespace swarmcl {

class SwarmMetrics {
public:
    // Error(InvalidArgument) for dt_between_samples <= 0 or not finite, and
    // for a swarm of fewer than 2 agents a world (no nearest-neighbour
    // distance).
    SwarmMetrics(Swarm& swarm, double dt_between_samples);
    ~SwarmMetrics();
    SwarmMetrics(const SwarmMetrics&) = delete;
    SwarmMetrics& operator=(const SwarmMetrics&) = delete;

    // Samples the swarm's current positions (enqueued; reads nothing back
    // but the previous sample's few per-block moments).  The agent
    // count must not have changed since construction.
    void sample();
    uint64_t samples() const { return samples_; }
    double dt() const { return dt_; }
    uint32_t worlds() const { return worlds_; }

    // Everything sampled so far in world k (waits for the device);
    // Error(InvalidArgument) for k >= worlds().  Sampling may go on.
    MetricAccumulator result(uint32_t world = 0);

    // Bytes of device memory this object holds (fixed at construction).
    size_t device_bytes() const;

    // The most a device counter may reach before the histograms are folded
    // into the host's 64-bit counts (default 2^32 - 1; lower only to test
    // the fold).
    void set_fold_limit(uint64_t counts) { fold_limit_ = counts; }

private:
    void fold_partials(uint32_t buffer);
    void fold_histogram();
    void add_device_histograms(const std::vector<cl_uint>& device, uint32_t world, MetricAccumulator& to) const;

    Swarm& swarm_;
    Context& ctx_;
    double dt_;
    uint32_t n_;        // agents a world
    uint32_t worlds_;   // W
    uint32_t total_;    // n W
    size_t groups_;     // blocks of moments a world
    uint32_t copies_ = 1;  // histogram copies a world on the device (per chunk of agents on CPU devices)
    uint64_t samples_ = 0;
    uint64_t since_fold_ = 0;
    uint64_t fold_limit_ = 0xffffffffu;    // samples counted into the device histogram since it was last folded
    int64_t pending_ = -1;       // the sample whose moments are still being read back
    std::array<DeviceBuffer<cl_float4>, 4> ring_;  // positions of the last 4 samples, id order
    DeviceBuffer<cl_float4> sorted_;               // the last sample's positions in grid order
    DeviceBuffer<cl_uint> nn_idx_, hist_;
    DeviceBuffer<cl_float2> omega_;           // ω of the last sample's frame f-2 (hi, lo), for α
    DeviceBuffer<cl_float> nn_dist_, vals_;  // vals_: the sample's values, metric-major (NaN: none)
    std::array<DeviceBuffer<cl_float4>, 2> part_;  // per-block moments, alternate samples
    std::array<std::vector<cl_float4>, 2> host_part_;
    std::array<cl::Event, 2> read_done_;
    PointGrid grid_;
    // Per world: every merged moment, and the histograms folded in (empty
    // until the first fold: 3.4 MB a world on the host).
    std::vector<std::array<RawMoments, kMetricCount>> world_moments_;
    std::vector<MetricAccumulator> folded_;
    cl::Kernel gather_, sample_, nearest_, sort_, moments_, histogram_;
    // Lanes of the nearest-neighbour kernel: 1 (metrics_nearest, one point a
    // work-item), or 8 or 16 on CPU devices (metrics_nearest_w).
    uint32_t lanes_ = 1;
};

}  // namespace swarmcl
