#include "io/recorder.hpp"

#include <cstdio>
#include <filesystem>

#include "core/error.hpp"

namespace swarmcl {
namespace fs = std::filesystem;

Recorder::Recorder(std::string dir, std::string basename, uint32_t formats)
    : dir_(std::move(dir)), base_(std::move(basename)) {
    require((formats & ~all_export_formats()) == 0, "export formats: unknown bits in the mask");
    require(!base_.empty() && base_.find('/') == std::string::npos, "export basename must be a plain file name");
    std::error_code ec;
    fs::create_directories(dir_, ec);
    if (ec || !fs::is_directory(dir_))
        fail(Status::Io, "output folder '" + dir_ + "' cannot be created: " + (ec ? ec.message() : "not a folder"));
    for (const ExportFormatInfo& f : export_formats())
        if (formats & f.bit) writers_.push_back(f.make(dir_, base_));
}

Recorder::~Recorder() {
    if (!finished_)
        for (const auto& f : files_) std::remove(f.c_str());
}

void Recorder::add_frame(uint32_t frame, double time, const float* pos, const float* vel, uint32_t n) {
    require(!finished_, "recorder: add_frame after finish");
    require((pos && vel) || n == 0, "recorder: positions or velocities are NULL");
    for (const auto& w : writers_) w->check_frame(n);
    for (const auto& w : writers_) w->add_frame(frame, time, pos, vel, n, files_);
    ++frames_;
}

void Recorder::finish() {
    require(!finished_, "recorder: finish called twice");
    for (const auto& w : writers_) w->finish(files_);
    finished_ = true;
}

}  // namespace swarmcl
