#include "eval/time_window.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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
    double t0 = std::numeric_limits<double>::infinity(), t1 = -t0;
    for (const auto& s : tracks.tracks)
        if (!s.t.empty()) t0 = std::min(t0, s.t.front()), t1 = std::max(t1, s.t.back());
    if (!(t1 >= t0)) return out;
    const double lo = t0 + from * (t1 - t0), hi = t0 + to * (t1 - t0);
    for (const auto& s : tracks.tracks) {
        Track piece;
        piece.id = s.id;
        for (size_t k = 0; k < s.t.size(); ++k) {
            const bool inside = s.t[k] >= lo && (s.t[k] < hi || (to == 1.0 && s.t[k] <= hi));
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
