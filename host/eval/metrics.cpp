#include "eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <nanoflann.hpp>

#include "core/error.hpp"

namespace swarmcl {
namespace {

using Vec3 = std::array<double, 3>;

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 scale(const Vec3& a, double s) { return {a[0] * s, a[1] * s, a[2] * s}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

// One sample placed on the common frame clock, for d and η.
struct FrameSample {
    int64_t frame;
    uint32_t segment;
    uint32_t index;  // sample index inside the segment
};

// The per-sample metrics of one gap-free segment (§3.2).  ω_k is NaN where a
// speed is zero; α and μ need three velocities in a row.
void segment_metrics(const Track& s, MetricSamples& out) {
    const size_t n = s.p.size();
    if (n < 2) return;
    std::vector<Vec3> v(n - 1);
    for (size_t k = 0; k + 1 < n; ++k) {
        v[k] = scale(sub(s.p[k + 1], s.p[k]), 1.0 / (s.t[k + 1] - s.t[k]));
        out[Metric::Speed].push_back(norm(v[k]));
    }
    std::vector<Vec3> a;
    std::vector<double> omega;
    for (size_t k = 0; k + 2 < n; ++k) {
        const double dt = s.t[k + 1] - s.t[k];
        a.push_back(scale(sub(v[k + 1], v[k]), 1.0 / dt));
        out[Metric::Acceleration].push_back(norm(a.back()));
        const double n0 = norm(v[k]), n1 = norm(v[k + 1]);
        double w = std::numeric_limits<double>::quiet_NaN();
        if (n0 > 0.0 && n1 > 0.0) {
            const double c = std::clamp(dot(v[k], v[k + 1]) / (n0 * n1), -1.0, 1.0);
            w = std::acos(c) / dt;
            out[Metric::AngularVelocity].push_back(w);
        }
        omega.push_back(w);
    }
    for (size_t k = 0; k + 3 < n; ++k) {
        const double dt = s.t[k + 1] - s.t[k];
        if (!std::isnan(omega[k]) && !std::isnan(omega[k + 1]))
            out[Metric::AngularAcceleration].push_back((omega[k + 1] - omega[k]) / dt);
        // μ = |Δv_{k+1} - Δv_k| / Δt², written with the accelerations so an
        // uneven clock inside a segment is honoured.
        out[Metric::Jerk].push_back(norm(sub(a[k + 1], a[k])) / dt);
    }
}

struct FramePoints {
    std::vector<Vec3> p;
    size_t kdtree_get_point_count() const { return p.size(); }
    double kdtree_get_pt(size_t i, size_t d) const { return p[i][d]; }
    template <class B>
    bool kdtree_get_bbox(B&) const { return false; }
};
using FrameTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, FramePoints>,
                                                      FramePoints, 3, uint32_t>;

// Nearest other point of each point of one frame (the lowest index on ties).
// Brute force for the few insects a real recording has in view; a kd-tree
// for simulated frames.
std::vector<uint32_t> nearest_in_frame(const FramePoints& pts) {
    const size_t g = pts.p.size();
    std::vector<uint32_t> nn(g);
    if (g <= 32) {
        for (size_t i = 0; i < g; ++i) {
            double best = std::numeric_limits<double>::infinity();
            for (size_t j = 0; j < g; ++j) {
                if (j == i) continue;
                const Vec3 d = sub(pts.p[j], pts.p[i]);
                const double r2 = dot(d, d);
                if (r2 < best) best = r2, nn[i] = uint32_t(j);
            }
        }
        return nn;
    }
    FrameTree tree(3, pts, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    for (size_t i = 0; i < g; ++i) {
        uint32_t idx[2];
        double r2[2];
        nanoflann::KNNResultSet<double, uint32_t> result(2);
        result.init(idx, r2);
        tree.findNeighbors(result, pts.p[i].data(), nanoflann::SearchParams());
        // The point itself is one of the two (distance 0) unless it coincides
        // with another; take the first that is not i.
        nn[i] = idx[0] == i ? idx[1] : idx[0];
    }
    return nn;
}

// d and η frame by frame over the samples of every segment.
void frame_neighbour_metrics(const TrackSet& tracks, double frame_time, MetricSamples& out) {
    double t0 = std::numeric_limits<double>::infinity();
    for (const auto& s : tracks.tracks)
        if (!s.t.empty()) t0 = std::min(t0, s.t.front());
    std::vector<FrameSample> samples;
    for (uint32_t si = 0; si < tracks.tracks.size(); ++si) {
        const auto& s = tracks.tracks[si];
        int64_t last = std::numeric_limits<int64_t>::min();
        for (uint32_t k = 0; k < s.t.size(); ++k) {
            const int64_t f = std::llround((s.t[k] - t0) / frame_time);
            if (f == last) continue;  // clock jitter: one sample per segment and frame
            samples.push_back({f, si, k});
            last = f;
        }
    }
    std::stable_sort(samples.begin(), samples.end(),
                     [](const FrameSample& a, const FrameSample& b) { return a.frame < b.frame; });
    FramePoints pts;
    for (size_t begin = 0; begin < samples.size();) {
        size_t end = begin;
        while (end < samples.size() && samples[end].frame == samples[begin].frame) ++end;
        if (end - begin >= 2) {
            pts.p.clear();
            for (size_t i = begin; i < end; ++i) pts.p.push_back(tracks.tracks[samples[i].segment].p[samples[i].index]);
            const auto nn = nearest_in_frame(pts);
            for (size_t i = 0; i < pts.p.size(); ++i) {
                const double d = norm(sub(pts.p[nn[i]], pts.p[i]));
                out[Metric::NearestDistance].push_back(d);
                // Forward velocity of a sample: defined for all but its segment's last.
                auto speed = [&](const FrameSample& fs, double& v) {
                    const auto& s = tracks.tracks[fs.segment];
                    if (fs.index + 1 >= s.p.size()) return false;
                    v = norm(sub(s.p[fs.index + 1], s.p[fs.index])) / (s.t[fs.index + 1] - s.t[fs.index]);
                    return true;
                };
                double v = 0.0, v_nei = 0.0;
                if (d > 0.0 && speed(samples[begin + i], v) && speed(samples[begin + nn[i]], v_nei))
                    out[Metric::VelocityDifference].push_back(std::abs(v_nei - v) / d);
            }
        }
        begin = end;
    }
}

}  // namespace

MetricSamples track_metrics(const TrackSet& tracks) {
    require(tracks.frame_time > 0.0 && std::isfinite(tracks.frame_time), "metrics: the tracks' frame time must be > 0");
    MetricSamples out;
    out.frame_time = tracks.frame_time;
    for (const auto& s : tracks.tracks) {
        require(s.t.size() == s.p.size(), "metrics: a track's times and positions differ in count");
        for (size_t k = 1; k < s.t.size(); ++k)
            require(s.t[k] > s.t[k - 1], "metrics: a track's times must increase");
        segment_metrics(s, out);
    }
    frame_neighbour_metrics(tracks, tracks.frame_time, out);
    return out;
}

MetricSamples frame_metrics(const float* xyz, size_t frames, size_t agents, double dt) {
    require(xyz != nullptr || frames * agents == 0, "metrics: positions are null");
    require(dt > 0.0 && std::isfinite(dt), "metrics: dt must be > 0");
    require(agents <= std::numeric_limits<uint32_t>::max() && frames <= std::numeric_limits<uint32_t>::max(),
            "metrics: too many frames or agents");
    TrackSet set;
    set.frame_time = dt;
    set.tracks.resize(agents);
    for (size_t i = 0; i < agents; ++i) {
        auto& s = set.tracks[i];
        s.id = std::to_string(i);
        s.t.resize(frames);
        s.p.resize(frames);
        for (size_t f = 0; f < frames; ++f) {
            const float* q = xyz + 3 * (f * agents + i);
            s.t[f] = double(f) * dt;
            s.p[f] = {q[0], q[1], q[2]};
        }
    }
    return track_metrics(set);
}

}  // namespace swarmcl
