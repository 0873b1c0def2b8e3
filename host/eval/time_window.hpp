// A part of a recording by time, for scoring on data the fit never saw
// (issue 14: fit on the first half of the recording, score on the second).
#pragma once
#include "data/tracks.hpp"

namespace swarmcl {

// The samples whose time lies in [q(from), q(to)), where q(f) is the time of
// the sample at fraction f of all samples ordered by time (q(1): past the
// last), with 0 <= from < to <= 1: (0, 0.5) is the first half of the data by
// time, (0.5, 1) the second.  A segment crossing a boundary is cut there; pieces
// of fewer than 3 samples are dropped (as the loader drops them).
TrackSet time_window(const TrackSet& tracks, double from, double to);

}  // namespace swarmcl
