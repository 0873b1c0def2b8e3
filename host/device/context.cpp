#include "device/context.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <unistd.h>

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

// The line of a compiler log a reader needs first: the first that says
// "error" (clang, PoCL, NVIDIA and Oclgrind all write "error:"), else the
// first non-empty line, else a note that the driver gave no log.
std::string first_error(const std::string& log) {
    std::string first_nonempty;
    size_t begin = 0;
    while (begin < log.size()) {
        size_t end = log.find('\n', begin);
        if (end == std::string::npos) end = log.size();
        std::string line = log.substr(begin, end - begin);
        begin = end + 1;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        if (first_nonempty.empty()) first_nonempty = line;
        std::string lower = line;
        for (char& c : lower) c = char(std::tolower((unsigned char)c));
        if (lower.find("error") != std::string::npos) return line;
    }
    return first_nonempty.empty() ? std::string("(the driver gave no build log)") : first_nonempty;
}

// $SWARMCL_PROGRAM_DUMP_DIR (development, docs/reliability.md, "NVIDIA
// compile"): every program as built, its includes expanded, written to
// <dir>/<file stem>-<hash>.cl with its build options in a first-line comment,
// so tools (scripts/nvptx-check.sh) compile exactly what the host builds.
// Written to a temporary name and renamed, so concurrent test processes
// never leave a half-written file; a failure to write is ignored (it is a
// debugging aid, never a reason to fail a build).
void dump_program(const std::string& file, const std::string& options, const std::string& source) {
    const char* dir = std::getenv("SWARMCL_PROGRAM_DUMP_DIR");
    if (!dir || !*dir) return;
    const std::string text = "// swarmcl-build-options: " + options + "\n" + source;
    uint64_t h = 1469598103934665603ull;  // FNV-1a 64
    for (unsigned char c : text) h = (h ^ c) * 1099511628211ull;
    std::string stem = file.substr(0, file.rfind('.'));
    for (char& c : stem)
        if (c == '/') c = '_';
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", (unsigned long long)h);
    const std::string path = std::string(dir) + "/" + stem + "-" + hex + ".cl";
    const std::string tmp = path + ".tmp" + std::to_string(getpid());
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    {
        std::ofstream out(tmp, std::ios::binary);
        if (!out) return;
        out << text;
        if (!out) return;
    }
    std::rename(tmp.c_str(), path.c_str());
}

// The copies Context::oclgrind_copy() runs on Oclgrind (never elsewhere):
// not a program of kernels/, a stand-in for clEnqueueWriteBuffer and
// clEnqueueCopyBuffer that Oclgrind's shadow memory follows.  Work-item g of
// G copies the words (bytes) g, g + G, ...
const char* const kOclgrindCopySource = R"CLC(
__kernel void swcl_oclgrind_copy_words(__global const uint* src, ulong src_at, __global uint* dst, ulong dst_at,
                                       ulong count) {
    for (ulong k = get_global_id(0); k < count; k += get_global_size(0)) dst[dst_at + k] = src[src_at + k];
}
__kernel void swcl_oclgrind_copy_bytes(__global const uchar* src, ulong src_at, __global uchar* dst, ulong dst_at,
                                       ulong count) {
    for (ulong k = get_global_id(0); k < count; k += get_global_size(0)) dst[dst_at + k] = src[src_at + k];
}
)CLC";

}  // namespace

Context::Context(const std::string& selector, const std::string& build_options)
    : device_(profiled(select_device(selector))) {
    context_ = cl::Context(device_.device);
    queue_ = cl::CommandQueue(context_, device_.device);
    // No -cl-fast-relaxed-math: results must match the C++ references and be
    // the same on every run (docs/design.md, "Kernels").
    // SWCL_CPU_PROFILE: CPU-only constructs (x86 prefetch, lib/prefetch.cl)
    // compile only where the CPU paths run.
    on_oclgrind_ = device_.platform_name.find("Oclgrind") != std::string::npos ||
                      device_.device_name.find("Oclgrind") != std::string::npos;
    // -w (an OpenCL build option): PoCL printed "N warnings generated." to
    // stderr for most programs, the first time each was built: clang's
    // -Wpsabi notes on the static helpers' vector arguments (float16 without
    // AVX-512), harmless within one program.  A library must not print; a
    // failed build's errors still reach the build log and the Status::Build
    // message.
    options_ = std::string("-cl-std=CL1.2 -w -DSWCL_CPU_PROFILE=") + (device_.cpu_profile ? "1" : "0");
    if (!build_options.empty()) options_ += " " + build_options;
}

Context::~Context() {
    try {
        queue_.finish();
    } catch (...) {
        // Nothing to report to: a failed wait leaves the release to OpenCL.
    }
}

void Context::keep(const cl::Buffer& buffer) {
    if (!on_oclgrind_) return;
    std::lock_guard<std::mutex> lock(kept_mutex_);
    kept_.push_back(buffer);
}

cl::Buffer Context::oclgrind_staging(const void* data, size_t bytes) {
    cl::Buffer staged(context_, CL_MEM_READ_WRITE, bytes ? bytes : 1);
    keep(staged);
    if (bytes) queue_.enqueueWriteBuffer(staged, CL_TRUE, 0, bytes, data);
    return staged;
}

void Context::oclgrind_copy(const cl::Buffer& src, size_t src_offset, const cl::Buffer& dst, size_t dst_offset,
                            size_t bytes) {
    if (!bytes) return;
    std::lock_guard<std::mutex> lock(kept_mutex_);
    if (!oclgrind_copy_words_()) {
        cl::Program p(context_, std::string(kOclgrindCopySource));
        p.build({device_.device}, "-cl-std=CL1.2");
        oclgrind_copy_words_ = cl::Kernel(p, "swcl_oclgrind_copy_words");
        oclgrind_copy_bytes_ = cl::Kernel(p, "swcl_oclgrind_copy_bytes");
    }
    const bool words = src_offset % 4 == 0 && dst_offset % 4 == 0 && bytes % 4 == 0;
    const size_t unit = words ? 4 : 1, count = bytes / unit;
    cl::Kernel& k = words ? oclgrind_copy_words_ : oclgrind_copy_bytes_;
    k.setArg(0, src);
    k.setArg(1, cl_ulong(src_offset / unit));
    k.setArg(2, dst);
    k.setArg(3, cl_ulong(dst_offset / unit));
    k.setArg(4, cl_ulong(count));
    queue_.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(std::min<size_t>(count, 64)), cl::NullRange);
}

cl::Program Context::program(const std::string& file, const std::string& defines) {
    std::lock_guard<std::mutex> lock(programs_mutex_);
    const std::string key = defines.empty() ? file : file + '\n' + defines;
    if (auto it = programs_.find(key); it != programs_.end()) return it->second;
    const std::string source = load_kernel_source(file);
    const std::string options = defines.empty() ? options_ : options_ + " " + defines;
    dump_program(file, options, source);
    cl::Program program(context_, source);
    // A failed build names the device, the program and the log's first error
    // on its first line (a new driver refusing one kernel is found at a
    // glance), then the options and the whole log.  Only this context's
    // program fails: other contexts, on other devices, stay usable.
    auto build_failed = [&](const std::string& how, const std::string& log) {
        fail(Status::Build, "building kernels/" + file + " for device '" + device_.device_name + "' (" +
                                device_.platform_name + ") failed" + how + ": " + first_error(log) +
                                "\nbuild options: " + options + "\nbuild log:\n" + log);
    };
    try {
        program.build({device_.device}, options.c_str());
    } catch (const cl::BuildError& e) {
        std::string log;
        for (const auto& entry : e.getBuildLog()) log += entry.second;
        build_failed("", log);
    } catch (const cl::Error& e) {
        std::string log;
        try {
            log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_.device);
        } catch (const cl::Error&) {
            // No log either: the status code below is all there is.
        }
        build_failed(" (OpenCL error " + std::to_string(e.err()) + ")", log);
    }
    programs_.emplace(key, program);
    return program;
}

cl::Kernel Context::kernel(const std::string& file, const char* name, const std::string& defines) {
    cl::Program built;
    try {
        built = program(file, defines);
    } catch (const Error& e) {
        if (e.status() != Status::Build) throw;
        // The kernel the caller wanted, in the first line with the rest.
        std::string message = e.what();
        const std::string head = "building kernels/" + file;
        if (message.compare(0, head.size(), head) == 0)
            message.insert(head.size(), std::string(" (kernel ") + name + ")");
        fail(Status::Build, message);
    }
    try {
        return cl::Kernel(built, name);
    } catch (const cl::Error& e) {
        // The program built but the kernel cannot be made from it: most often
        // CL_INVALID_KERNEL_NAME (a driver or a define that left the kernel
        // out; Oclgrind says so too for a kernel it cannot run, e.g. one
        // calling an LLVM intrinsic it lacks).  Same first line as a build
        // failure: the program, the kernel, the device, then what the driver
        // said and the log's first line, which may say why; the kernels the
        // program lists follow.
        std::string have, log;
        try {
            have = built.getInfo<CL_PROGRAM_KERNEL_NAMES>();
        } catch (const cl::Error&) {
            have = "(the driver did not say)";
        }
        try {
            log = built.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_.device);
        } catch (const cl::Error&) {
            // No log: the error code is all there is.
        }
        const std::string why = e.err() == CL_INVALID_KERNEL_NAME
                                    ? "CL_INVALID_KERNEL_NAME (-46): no kernel of that name could be made from "
                                      "the built program"
                                    : "OpenCL error " + std::to_string(e.err()) + " from " + e.what();
        fail(Status::Build, "building kernels/" + file + " (kernel " + name + ") for device '" +
                                device_.device_name + "' (" + device_.platform_name + ") failed: " + why +
                                "; build log: " + first_error(log) + "\nkernels the program lists: " +
                                (have.empty() ? "none" : have) + "\nbuild options: " + options_ +
                                (defines.empty() ? "" : " " + defines) + "\nbuild log:\n" + log);
    }
}

}  // namespace swarmcl
