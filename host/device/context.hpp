// A device, its OpenCL context and in-order queue, and the programs built on
// it (each built once, on first use, and kept).
#pragma once
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "device/device_list.hpp"
#include "device/opencl.hpp"

namespace swarmcl {

class Context {
public:
    // selector as in select_device(); build_options appended to swarmcl's own.
    Context(const std::string& selector, const std::string& build_options);
    // Waits for the queue first: commands still queued (PoCL compiles a
    // kernel for its launch size when the command runs) must not outlive
    // the context, nor run while the process exits.
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    const DeviceEntry& device() const { return device_; }
    cl::Context& cl_context() { return context_; }
    cl::CommandQueue& queue() { return queue_; }

    // The program compiled from kernels/<file> (includes expanded), with
    // `defines` (e.g. "-DNOISE_KIND=0") appended to the build options; each
    // (file, defines) pair is built once and kept.  A build failure throws
    // Error(Build): its first line names the program, the device and the
    // log's first error; then the options and the whole compiler log.
    cl::Program program(const std::string& file, const std::string& defines = "");
    // A fresh kernel object (kernels hold arguments, so callers keep their own).
    // A build failure names the kernel too, and so does a program without
    // the kernel (CL_INVALID_KERNEL_NAME): Error(Build), the same first line
    // (program, kernel, device, what the driver said), then the kernels the
    // program has, the options and the log.
    cl::Kernel kernel(const std::string& file, const char* name, const std::string& defines = "");

    // Largest single allocation the device allows, in bytes.
    uint64_t max_allocation() const { return device_.max_allocation; }

    // True on Oclgrind, whose --uninitialized check (21.10) does not count
    // clEnqueueFillBuffer as writing the memory: fill_buffer() writes the
    // pattern from the host there instead, so every report it gives is one
    // of ours (docs/reliability.md, "Oclgrind").  False on every other device.
    bool fills_by_write() const { return fills_by_write_; }

private:
    DeviceEntry device_;
    cl::Context context_;
    cl::CommandQueue queue_;
    std::string options_;
    bool fills_by_write_ = false;
    std::mutex programs_mutex_;
    std::map<std::string, cl::Program> programs_;
};

}  // namespace swarmcl
