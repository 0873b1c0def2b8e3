// Statistics of a swarm now, as `swarmcl run` prints them per frame and
// writes them to run.json (curl-noise paper item 8): mean speed,
// nearest-neighbour distance percentiles, the fraction of pairs closer than
// the MDE distance, and the share MDE moved per step since the last call.
#pragma once
#include <cstdint>

#include <swarmcl/swarmcl.h>

namespace swarmcl_cli {

struct FrameStats {
    double mean_speed = 0, nn_p5 = 0, nn_p50 = 0, nn_p95 = 0, close_pair_fraction = 0, mde_moved = 0;
};

// Reads the swarm (n agents) and takes its step statistics (Failure on a C error).
FrameStats frame_stats(swcl_swarm swarm, uint32_t n, float min_distance);
// The table's header line and one row per frame, on stdout.
void print_stats_header();
void print_stats(uint32_t step, const FrameStats& f);

}  // namespace swarmcl_cli
