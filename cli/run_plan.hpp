// What `swarmcl run` and `swarmcl resume` hand to the run loop
// (run_loop.cpp): the run's settings, from the command line and the
// scenario (run) or from checkpoint.json (resume), and where a resumed run
// starts.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include <swarmcl/swarmcl.h>

#include "run_checkpoint.hpp"

namespace swarmcl_cli {

struct RunPlan {
    std::string path, out_dir, device;
    std::string scenario_absolute;  // the scenario file, wherever the run is resumed from
    uint32_t steps = 0, every = 1, formats = 0, checkpoint_every = 0;
    bool quiet = false;
};

// Where a resumed run starts: the swarm, the step and the frames recorded before.
struct ResumePoint {
    std::string swarm_file, frames_file;
    uint32_t done = 0;
    uint32_t agents = 0;
    std::vector<swarmcl::cli::Frame> frames;
};

// Runs the plan: the swarm from the scenario (or from `resume`), frames
// recorded, statistics printed, checkpoints written, run.json last.  Returns
// the exit status; Failure on any error, with no output that looks complete.
int execute(const RunPlan& plan, swcl_scenario scn, const swcl_scenario_info& info, const ResumePoint* resume);

}  // namespace swarmcl_cli
