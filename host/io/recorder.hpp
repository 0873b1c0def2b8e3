// Trajectory exports written by the library (usable from C through
// swcl_recorder_*): CSV with Houdini/Blender attribute names, NumPy .npy of
// shape (frames, N, 3), and VTK PolyData .vtp per frame with a .pvd series for
// ParaView.  Every file is written atomically (io/atomic_file.hpp).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/atomic_file.hpp"

namespace swarmcl {

enum ExportFormat : uint32_t { kExportCsv = 1, kExportNpy = 2, kExportVtp = 4, kExportAll = 7 };

// "csv,npy,vtp" -> bit mask; Error(InvalidArgument) naming an unknown format.
uint32_t parse_export_formats(const std::string& list);

class Recorder {
public:
    // Creates `dir` if needed (Error(Io) when it cannot be created or written).
    Recorder(std::string dir, std::string basename, uint32_t formats);
    // Without finish(), also removes the .vtp frames already written: a run
    // that fails leaves no output that looks complete.
    ~Recorder();
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    // Appends one frame: n agents' positions and velocities (packed xyz,
    // agent-id order) at simulation time `time`.  N must stay the same for .npy.
    void add_frame(uint32_t frame, double time, const float* pos, const float* vel, uint32_t n);
    // Commits the accumulated files (CSV, NPY, PVD); .vtp frames are already
    // committed one by one.  Without finish() they are discarded.
    void finish();

    // The files written so far (committed).
    const std::vector<std::string>& files() const { return files_; }
    uint32_t frames() const { return frames_; }

private:
    void write_vtp(uint32_t frame, const float* pos, const float* vel, uint32_t n);

    std::string dir_, base_;
    uint32_t formats_;
    uint32_t frames_ = 0;
    uint32_t agents_ = 0;
    std::unique_ptr<AtomicFile> csv_, npy_pos_, npy_vel_;
    std::string pvd_entries_;
    std::vector<std::string> files_;
    bool finished_ = false;
};

}  // namespace swarmcl
