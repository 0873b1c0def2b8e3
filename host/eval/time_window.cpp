#include "eval/time_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/error.hpp"

namespace swarmcl {

TrackSet time_window(const TrackSet& tracks, double from, double to) {
    require(std::isfinite(from) && std::isfinite(to) && from >= 0.0 && from < to && to <= 1.0,
            "time window: expected 0 <= from < to <= 1 (fractions of the recording's time span)");
    TrackSet out;
    out.frame_time = tracks.frame_time;
    out.rows = tracks.rows;
    out.dropped_segments = tracks.dropped_segments;
    if (from == 0.0 && to == 1.0) {
        out.tracks = tracks.tracks;
        return out;
    }
    // Cut at time quantiles of the samples: real recordings are uneven in
    // time (the mosquito data has most samples in its last tenth), and a cut
    // at the median sample time halves the data while still splitting it by
    // time.
    std::vector<double> times;
    for (const auto& s : tracks.tracks) times.insert(times.end(), s.t.begin(), s.t.end());
    if (times.empty()) return out;
    std::sort(times.begin(), times.end());
    const size_t n = times.size();
    const double lo = times[std::min(n - 1, size_t(std::floor(from * double(n))))];
    const double hi = to == 1.0 ? std::numeric_limits<double>::infinity()
                                : times[std::min(n - 1, size_t(std::floor(to * double(n))))];
    for (const auto& s : tracks.tracks) {
        Track piece;
        piece.id = s.id;
        for (size_t k = 0; k < s.t.size(); ++k) {
            const bool inside = s.t[k] >= lo && s.t[k] < hi;
            if (!inside) continue;
            piece.t.push_back(s.t[k]);
            piece.p.push_back(s.p[k]);
        }
        // Samples of one segment inside the window are contiguous: the window is one interval.
        if (piece.t.size() >= 3) out.tracks.push_back(std::move(piece));
        else if (!piece.t.empty()) ++out.dropped_segments;
    }
    return out;
}

}  // namespace swarmcl
