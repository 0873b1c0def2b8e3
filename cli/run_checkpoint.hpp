// What `swarmcl run --checkpoint-every K` leaves in the output folder so that
// `swarmcl resume DIR` can finish the run with the outputs an uninterrupted
// run writes (docs/checkpoint-format.md, "The CLI's run checkpoints"):
//
//   DIR/checkpoint-<step>.swcl    the swarm (swcl_swarm_save)
//   DIR/checkpoint-<step>.frames  the frames recorded up to that step, which
//                                 the resumed run records again first
//   DIR/checkpoint.json           the run's settings and the step; written
//                                 last, so it names only complete files
//
// Older step files are removed once checkpoint.json names newer ones.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

namespace swarmcl::cli {

// One recorded frame: packed xyz positions and velocities of n agents.
struct Frame {
    uint32_t frame = 0;
    double time = 0.0;
    std::vector<float> pos, vel;
};

// The run's settings (what the command line and scenario gave) and where it is.
struct RunCheckpoint {
    std::string scenario_file;       // as given on the command line
    std::string scenario_absolute;   // the same, absolute (read by resume)
    uint32_t scenario_crc32 = 0;     // of its bytes: resume refuses a changed file
    std::string out_dir, device;
    uint32_t steps = 0, every = 1, formats = 0, checkpoint_every = 0;
    uint32_t done = 0;               // steps taken when it was written
    std::string swarm_file, frames_file;  // names inside the output folder
};

// Writes the frames file and checkpoint.json (atomically, in that order) and
// removes the previous step's files.  Error(Io) naming the file.
void write_run_checkpoint(const RunCheckpoint& run, const std::vector<Frame>& frames, uint32_t agents,
                          const std::string& previous_swarm_file, const std::string& previous_frames_file);
// Error(Io) / Error(Parse) naming the file and what is wrong.
RunCheckpoint read_run_checkpoint(const std::string& dir);
std::vector<Frame> read_frames(const std::string& path, uint32_t& agents);
// The parses of those files' bytes (the fuzz target bench/fuzz/fuzz_run_checkpoint.cpp
// calls them): `path`/`name` in messages; out_dir is left empty.  verify_checksum
// false only for fuzzing (mutations then reach the FRMS section).
RunCheckpoint parse_run_checkpoint(const std::string& text, const std::string& path);
std::vector<Frame> frames_from_bytes(const std::string& bytes, const std::string& name, uint32_t& agents,
                                     bool verify_checksum = true);
// CRC-32 of a file's bytes (Error(Io) when it cannot be read).
uint32_t file_crc32(const std::string& path);

}  // namespace swarmcl::cli
