// The trajectory export formats, in one table (export_format.cpp): each
// format's name (the scenario's output.formats, `swarmcl run --format`,
// run.json), its bit in swcl_export_format masks, the files it writes, and
// its writer.  A new format is its writer (a FrameWriter in
// io/<name>_writer.cpp), one row of that table and its bit in the C header's
// swcl_export_format; the Recorder, scenario files, the C API and the CLI
// take it from the table (docs/architecture.md, "Where a change goes").
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace swarmcl {

// The formats' bits: the values of swcl_export_format (capi_recorder.cpp
// checks that they agree).
enum ExportFormat : uint32_t { kExportCsv = 1, kExportNpy = 2, kExportVtp = 4 };

// One format's files for a Recorder: created by the table's `make` when the
// Recorder is made, fed every frame, committed by finish().  A writer
// destroyed unfinished leaves no temporary behind (io/atomic_file.hpp); the
// Recorder removes the files it reported as committed.
class FrameWriter {
public:
    virtual ~FrameWriter() = default;
    // Error(InvalidArgument) when this format cannot take a frame of n
    // agents now.  The Recorder asks every writer before any writes, so a
    // refused frame writes nothing in any format.
    virtual void check_frame(uint32_t n) const { (void)n; }
    // Appends one frame (n agents' packed xyz positions and velocities, in
    // agent-id order); the path of each file committed now is appended to
    // `committed`.
    virtual void add_frame(uint32_t frame, double time, const float* pos, const float* vel, uint32_t n,
                           std::vector<std::string>& committed) = 0;
    // Commits the files still open and appends their paths to `committed`.
    virtual void finish(std::vector<std::string>& committed) = 0;
};

struct ExportFormatInfo {
    const char* name;   // "csv"
    uint32_t bit;       // kExportCsv
    const char* files;  // what it writes, for messages and docs: "<base>.csv"
    // The writer of `dir`/`base`...; its files are opened here.
    std::unique_ptr<FrameWriter> (*make)(const std::string& dir, const std::string& base);
};

// The table, in the order the Recorder creates, feeds and finishes writers.
const std::vector<ExportFormatInfo>& export_formats();
// Every format's bit together.
uint32_t all_export_formats();
// The format of that name, or nullptr (names are lower case and exact).
const ExportFormatInfo* find_export_format(const std::string& name);
// The known names for messages: "csv, npy or vtp" (quote "\"": "\"csv\", \"npy\" or \"vtp\"").
std::string export_format_choices(const std::string& quote = "");
// "csv,npy" -> kExportCsv | kExportNpy.  Error(InvalidArgument) for an
// unknown name (naming it and the known ones), an empty name or an empty list.
uint32_t parse_export_formats(const std::string& list);
// The names of a mask's formats, in table order; Error(InvalidArgument)
// when it holds a bit no format has.
std::vector<std::string> export_format_names(uint32_t mask);

// "%.9g": how the text formats write a float or a time (every float32 exactly).
std::string format_g9(double v);

}  // namespace swarmcl
