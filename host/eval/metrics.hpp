// The seven time-varying metrics of the data-driven evaluation (noise paper
// §3.2): speed v, acceleration a, angular velocity ω, angular acceleration α,
// Cartesian jerk μ, nearest-neighbour ("shortest") distance d and velocity
// difference η, sampled from trajectories on the host.  This is the
// reference for the device path and the path for real tracks.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "data/tracks.hpp"
#include "eval/metric_table.hpp"

namespace swarmcl {

// Metric, kMetricCount and metric_name(): the metric table
// (eval/metric_table.hpp).

// Samples of every metric, in a fixed order (segment by segment, sample by
// sample; d and η frame by frame), so every reduction over them is
// deterministic.
struct MetricSamples {
    std::array<std::vector<double>, kMetricCount> values;
    double frame_time = 0.0;  // s between the frames the samples came from
    std::vector<double>& operator[](Metric m) { return values[size_t(m)]; }
    const std::vector<double>& operator[](Metric m) const { return values[size_t(m)]; }
};

// Metrics of loaded tracks.  Each segment of the set is gap free (the loader
// splits at gaps), so differences never cross a gap: a segment of n samples
// gives n-1 speeds, n-2 accelerations and angular velocities, n-3 angular
// accelerations and jerks (ω, and what is built on it, is skipped where the
// speed is zero: no direction).  Samples are put on frames of
// tracks.frame_time counted from the earliest sample; d is taken among the
// segments with a sample on the same frame (a frame with one insect in view
// gives no d), and η where the insect and its nearest neighbour both have a
// velocity on that frame and d > 0.
MetricSamples track_metrics(const TrackSet& tracks);

// Metrics of a simulation recording: `frames` frames of `agents` agents,
// positions packed xyz (frame-major) every dt seconds.  Each agent is one
// gap-free track; every agent is in view on every frame.  frame_stride: the
// floats from one frame's start to the next's (0: 3 * agents, packed), so
// one world's frames can be read in place from a swarm of worlds' frames.
MetricSamples frame_metrics(const float* xyz, size_t frames, size_t agents, double dt, size_t frame_stride = 0);

}  // namespace swarmcl
