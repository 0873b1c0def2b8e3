#include "device/context.hpp"

#include "core/error.hpp"
#include "device/kernel_sources.hpp"

namespace swarmcl {

Context::Context(const std::string& selector, const std::string& build_options)
    : device_(select_device(selector)) {
    context_ = cl::Context(device_.device);
    queue_ = cl::CommandQueue(context_, device_.device);
    // No -cl-fast-relaxed-math: results must match the C++ references and be
    // the same on every run (docs/design.md, "Kernels").
    options_ = "-cl-std=CL1.2";
    if (!build_options.empty()) options_ += " " + build_options;
}

Context::~Context() {
    try {
        queue_.finish();
    } catch (...) {
        // Nothing to report to: a failed wait leaves the release to OpenCL.
    }
}

cl::Program Context::program(const std::string& file, const std::string& defines) {
    std::lock_guard<std::mutex> lock(programs_mutex_);
    const std::string key = defines.empty() ? file : file + '\n' + defines;
    if (auto it = programs_.find(key); it != programs_.end()) return it->second;
    cl::Program program(context_, load_kernel_source(file));
    const std::string options = defines.empty() ? options_ : options_ + " " + defines;
    try {
        program.build({device_.device}, options.c_str());
    } catch (const cl::BuildError& e) {
        std::string log;
        for (const auto& entry : e.getBuildLog()) log += entry.second;
        fail(Status::Build, "building kernels/" + file + " with '" + options + "' failed:\n" + log);
    } catch (const cl::Error& e) {
        std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_.device);
        fail(Status::Build, "building kernels/" + file + " failed (" + std::to_string(e.err()) + "):\n" + log);
    }
    programs_.emplace(key, program);
    return program;
}

cl::Kernel Context::kernel(const std::string& file, const char* name, const std::string& defines) {
    return cl::Kernel(program(file, defines), name);
}

}  // namespace swarmcl
