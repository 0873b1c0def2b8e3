#include "device/context.hpp"

#include <cstdlib>

#include "core/error.hpp"
#include "device/kernel_sources.hpp"

namespace swarmcl {

namespace {

// The device as this context uses it: $SWARMCL_DEVICE_PROFILE may force the
// GPU (or CPU) code paths, and a device whose OpenCL C is older than the
// kernels' 1.2 is refused here rather than by a cryptic build log.
DeviceEntry profiled(DeviceEntry d) {
    if (const char* env = std::getenv("SWARMCL_DEVICE_PROFILE"); env && *env) {
        const std::string v(env);
        if (v == "cpu") d.cpu_profile = true;
        else if (v == "gpu") d.cpu_profile = false;
        else fail(Status::InvalidArgument, "SWARMCL_DEVICE_PROFILE must be \"cpu\" or \"gpu\" (got '" + v + "')");
    }
    const int c_version = opencl_c_version_number(d.opencl_c_version);
    if (c_version != 0 && c_version < 120)
        fail(Status::Build, "device '" + d.device_name + "' compiles " + d.opencl_c_version +
                                "; swarmcl's kernels need OpenCL C 1.2");
    return d;
}

}  // namespace

Context::Context(const std::string& selector, const std::string& build_options)
    : device_(profiled(select_device(selector))) {
    context_ = cl::Context(device_.device);
    queue_ = cl::CommandQueue(context_, device_.device);
    // No -cl-fast-relaxed-math: results must match the C++ references and be
    // the same on every run (docs/design.md, "Kernels").
    // SWCL_CPU_PROFILE: CPU-only constructs (x86 prefetch, lib/prefetch.cl)
    // compile only where the CPU paths run.
    options_ = std::string("-cl-std=CL1.2 -DSWCL_CPU_PROFILE=") + (device_.cpu_profile ? "1" : "0");
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
