// A part of a recording by time, for scoring on data the fit never saw
// (issue 14: fit on the first half of the recording, score on the second).
#pragma once
#include "data/tracks.hpp"

namespace swarmcl {

// The samples whose time lies in [t0 + from * span, t0 + to * span) of the
// recording's span [t0, t1] (to == 1 keeps t1 itself), fractions with
// 0 <= from < to <= 1.  A segment crossing a boundary is cut there; pieces
// of fewer than 3 samples are dropped (as the loader drops them).
TrackSet time_window(const TrackSet& tracks, double from, double to);

}  // namespace swarmcl
