// Track loading options from the C descriptor, shared by the C API's
// readers of tracks (datasets, synthesis, evaluation).
#pragma once
#include "data/tracks.hpp"
#include "swarmcl/swarmcl.h"

namespace swarmcl::capi {

// The columns, time format, unit, gap splitting and smoothing of `d`.
TrackLoadOptions track_options(const swcl_dataset_desc& d);

}  // namespace swarmcl::capi
