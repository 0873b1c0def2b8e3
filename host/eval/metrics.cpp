#include "eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include <nanoflann.hpp>

#include "core/error.hpp"
#include "eval/nearest_sweep.hpp"

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

// Scratch vectors of segment_metrics, kept across segments.
struct SegmentScratch {
    std::vector<Vec3> v, a;
    std::vector<double> speed, omega;
};

// The per-sample metrics of one gap-free segment of n samples, sample k at
// time t(k) and position p(k) (§3.2).  ω_k is NaN where a speed is zero; α
// and μ need three velocities in a row.  One template for loaded tracks and
// dense simulation frames, so both give the same arithmetic.
template <class Time, class Pos>
void segment_metrics(size_t n, Time t, Pos p, SegmentScratch& s, MetricSamples& out) {
    if (n < 2) return;
    auto& v = s.v;
    auto& speed = s.speed;  // |v_k|, again in ω's cosine
    v.resize(n - 1);
    speed.resize(n - 1);
    for (size_t k = 0; k + 1 < n; ++k) {
        v[k] = scale(sub(p(k + 1), p(k)), 1.0 / (t(k + 1) - t(k)));
        speed[k] = norm(v[k]);
    }
    out[Metric::Speed].insert(out[Metric::Speed].end(), speed.begin(), speed.end());
    auto& a = s.a;
    auto& omega = s.omega;
    a.clear();
    omega.clear();
    for (size_t k = 0; k + 2 < n; ++k) {
        const double dt = t(k + 1) - t(k);
        a.push_back(scale(sub(v[k + 1], v[k]), 1.0 / dt));
        out[Metric::Acceleration].push_back(norm(a.back()));
        const double n0 = speed[k], n1 = speed[k + 1];
        double w = std::numeric_limits<double>::quiet_NaN();
        if (n0 > 0.0 && n1 > 0.0) {
            const double c = std::clamp(dot(v[k], v[k + 1]) / (n0 * n1), -1.0, 1.0);
            w = std::acos(c) / dt;
            out[Metric::AngularVelocity].push_back(w);
        }
        omega.push_back(w);
    }
    for (size_t k = 0; k + 3 < n; ++k) {
        const double dt = t(k + 1) - t(k);
        if (!std::isnan(omega[k]) && !std::isnan(omega[k + 1]))
            out[Metric::AngularAcceleration].push_back((omega[k + 1] - omega[k]) / dt);
        // μ = |Δv_{k+1} - Δv_k| / Δt², written with the accelerations so an
        // uneven clock inside a segment is honoured.
        out[Metric::Jerk].push_back(norm(sub(a[k + 1], a[k])) / dt);
    }
}

void segment_metrics(const Track& s, SegmentScratch& scratch, MetricSamples& out) {
    segment_metrics(
        s.p.size(), [&](size_t k) { return s.t[k]; }, [&](size_t k) { return s.p[k]; }, scratch, out);
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

// Nearest other point of each point of one frame: up to kSweepMax points
// (every real recording we hold, a fit's worlds) by the sweep, exact with the
// lowest index on ties; above, a kd-tree (ties, which float positions almost
// never have, go to the first the tree visits).  A point with a non-finite
// coordinate (a run that blew up) has no neighbour, nn[i] = i, and is no
// one's: the others are searched alone (the sweep's sort and the tree need
// ordered coordinates).
void nearest_in_frame(const FramePoints& pts, NearestSweep& sweep, const std::vector<uint32_t>* hint,
                      std::vector<uint32_t>& nn) {
    const size_t g = pts.p.size();
    auto finite = [](const Vec3& q) { return std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]); };
    if (!std::all_of(pts.p.begin(), pts.p.end(), finite)) {
        FramePoints kept;
        std::vector<uint32_t> index, kept_nn;
        for (size_t i = 0; i < g; ++i)
            if (finite(pts.p[i])) kept.p.push_back(pts.p[i]), index.push_back(uint32_t(i));
        nn.resize(g);
        for (size_t i = 0; i < g; ++i) nn[i] = uint32_t(i);
        if (kept.p.size() < 2) return;
        nearest_in_frame(kept, sweep, nullptr, kept_nn);  // indices in the same order: ties unchanged
        for (size_t k = 0; k < index.size(); ++k) nn[index[k]] = index[kept_nn[k]];
        return;
    }
    if (g <= kSweepMax) {
        sweep.find(pts.p, hint, nn);
        return;
    }
    nn.resize(g);
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
}

// d of point i: NaN where it has no neighbour (nearest_in_frame).
double neighbour_distance(const FramePoints& pts, const std::vector<uint32_t>& nn, size_t i) {
    return nn[i] == i ? std::numeric_limits<double>::quiet_NaN() : norm(sub(pts.p[nn[i]], pts.p[i]));
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
    NearestSweep sweep;
    std::vector<uint32_t> nn;
    for (size_t begin = 0; begin < samples.size();) {
        size_t end = begin;
        while (end < samples.size() && samples[end].frame == samples[begin].frame) ++end;
        if (end - begin >= 2) {
            pts.p.clear();
            for (size_t i = begin; i < end; ++i) pts.p.push_back(tracks.tracks[samples[i].segment].p[samples[i].index]);
            nearest_in_frame(pts, sweep, nullptr, nn);
            for (size_t i = 0; i < pts.p.size(); ++i) {
                const double d = neighbour_distance(pts, nn, i);
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
    SegmentScratch scratch;
    for (const auto& s : tracks.tracks) {
        require(s.t.size() == s.p.size(), "metrics: a track's times and positions differ in count");
        for (size_t k = 1; k < s.t.size(); ++k)
            require(s.t[k] > s.t[k - 1], "metrics: a track's times must increase");
        segment_metrics(s, scratch, out);
    }
    frame_neighbour_metrics(tracks, tracks.frame_time, out);
    return out;
}

MetricSamples frame_metrics(const float* xyz, size_t frames, size_t agents, double dt, size_t frame_stride) {
    require(xyz != nullptr || frames * agents == 0, "metrics: positions are null");
    require(dt > 0.0 && std::isfinite(dt), "metrics: dt must be > 0");
    require(agents <= std::numeric_limits<uint32_t>::max() && frames <= std::numeric_limits<uint32_t>::max(),
            "metrics: too many frames or agents");
    if (frame_stride == 0) frame_stride = 3 * agents;
    require(frame_stride >= 3 * agents, "metrics: frame_stride " + std::to_string(frame_stride) +
                                            " is below 3 * agents = " + std::to_string(3 * agents));
    // The same samples, in the same order and arithmetic, as track_metrics
    // on the frames written as one track per agent (tested), without
    // building those tracks or sorting samples onto frames: here frame f of
    // every agent is at t = f dt.
    MetricSamples out;
    out.frame_time = dt;
    // Every count is known (ω and what is built on it at most): no regrowth.
    const size_t intervals = frames > 0 ? frames - 1 : 0;
    for (Metric m : {Metric::Speed, Metric::Acceleration, Metric::AngularVelocity, Metric::AngularAcceleration,
                     Metric::Jerk})
        out[m].reserve(agents * intervals);
    out[Metric::NearestDistance].reserve(agents * frames);
    out[Metric::VelocityDifference].reserve(agents * intervals);
    auto time = [dt](size_t f) { return double(f) * dt; };
    auto at = [&](size_t f, size_t i) {
        const float* q = xyz + f * frame_stride + 3 * i;
        return Vec3{q[0], q[1], q[2]};
    };
    SegmentScratch scratch;
    for (size_t i = 0; i < agents; ++i)
        segment_metrics(frames, time, [&](size_t f) { return at(f, i); }, scratch, out);
    if (agents < 2) return out;
    // d and η frame by frame (frame_neighbour_metrics), each agent's last
    // neighbour bounding its next search.
    FramePoints pts, next;
    NearestSweep sweep;
    std::vector<uint32_t> nn, last_nn;
    std::vector<double> speed(agents);
    auto positions = [&](size_t f, FramePoints& into) {
        into.p.resize(agents);
        for (size_t i = 0; i < agents; ++i) into.p[i] = at(f, i);
    };
    if (frames > 0) positions(0, next);
    for (size_t f = 0; f < frames; ++f) {
        std::swap(pts, next);
        const bool moving = f + 1 < frames;  // forward velocities exist
        if (moving) {
            positions(f + 1, next);
            for (size_t i = 0; i < agents; ++i) speed[i] = norm(sub(next.p[i], pts.p[i])) / (time(f + 1) - time(f));
        }
        nearest_in_frame(pts, sweep, f > 0 ? &last_nn : nullptr, nn);
        for (size_t i = 0; i < agents; ++i) {
            const double d = neighbour_distance(pts, nn, i);
            out[Metric::NearestDistance].push_back(d);
            if (d > 0.0 && moving) out[Metric::VelocityDifference].push_back(std::abs(speed[nn[i]] - speed[i]) / d);
        }
        std::swap(nn, last_nn);
    }
    return out;
}

}  // namespace swarmcl
