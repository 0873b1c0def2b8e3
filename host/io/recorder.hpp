// Trajectory exports written by the library (usable from C through
// swcl_recorder_*): one writer per chosen format from the table of formats
// (io/export_format.hpp: CSV with Houdini/Blender attribute names, NumPy .npy
// of shape (frames, N, 3), VTK PolyData .vtp per frame with a .pvd series for
// ParaView).  Every file is written atomically (io/atomic_file.hpp).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/export_format.hpp"

namespace swarmcl {

class Recorder {
public:
    // Creates `dir` if needed (Error(Io) when it cannot be created or
    // written); `formats` is a mask of the table's bits.
    Recorder(std::string dir, std::string basename, uint32_t formats);
    // Without finish(), also removes the files already committed (.vtp
    // frames): a run that fails leaves no output that looks complete.
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    // Appends one frame: n agents' positions and velocities (packed xyz,
    // agent-id order) at simulation time `time`.  N must stay the same for
    // .npy; a frame a format refuses is written in none.
    void add_frame(uint32_t frame, double time, const float* pos, const float* vel, uint32_t n);
    // Commits the accumulated files (CSV, NPY, PVD); .vtp frames are already
    // committed one by one.  Without finish() they are discarded.
    void finish();

    // The files written so far (committed).
    const std::vector<std::string>& files() const { return files_; }
    uint32_t frames() const { return frames_; }

private:
    std::string dir_, base_;
    uint32_t frames_ = 0;
    std::vector<std::unique_ptr<FrameWriter>> writers_;  // in the table's order
    std::vector<std::string> files_;
    bool finished_ = false;
};

}  // namespace swarmcl
