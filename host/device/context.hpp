// A device, its OpenCL context and in-order queue, and the programs built on
// it (each built once, on first use, and kept).
#pragma once
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

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

    // True on Oclgrind (its platform or device named so).  Oclgrind 21.10's
    // uninitialised-memory check keeps one shadow per buffer *id*, and gets
    // two things wrong (docs/reliability.md, "Oclgrind"): a host write, fill
    // or copy into a buffer replaces the buffer's whole shadow by one the
    // size of that write (so the rest reads as uninitialised and later kernel
    // stores there are dropped; at an offset above 0 the write itself is
    // lost), and a released buffer's shadow stays for the next buffer given
    // its id.  So on Oclgrind every buffer is kept until the context goes
    // (keep(): ids are never reused), and write_buffer(), copy_buffer() and
    // fill_buffer() (device/buffer.hpp) turn anything but a host write of a
    // whole buffer into a kernel copy (oclgrind_copy()), whose stores mark
    // exactly the bytes written.  Elsewhere none of this runs.
    bool on_oclgrind() const { return on_oclgrind_; }
    // On Oclgrind: holds `buffer` until the context is destroyed.  Elsewhere
    // nothing.
    void keep(const cl::Buffer& buffer);
    // On Oclgrind only: a new buffer holding `bytes` bytes of `data`, written
    // whole from the host (kept, as every buffer there).
    cl::Buffer oclgrind_staging(const void* data, size_t bytes);
    // On Oclgrind only: copies `bytes` bytes from src at src_offset to dst at
    // dst_offset with a kernel (the copy's shadow is the source's).
    void oclgrind_copy(const cl::Buffer& src, size_t src_offset, const cl::Buffer& dst, size_t dst_offset,
                       size_t bytes);

private:
    DeviceEntry device_;
    cl::Context context_;
    cl::CommandQueue queue_;
    std::string options_;
    bool on_oclgrind_ = false;
    std::mutex programs_mutex_;
    std::map<std::string, cl::Program> programs_;
    // Oclgrind only (on_oclgrind()): every buffer made, and the copy kernels.
    std::mutex kept_mutex_;
    std::vector<cl::Buffer> kept_;
    cl::Kernel oclgrind_copy_words_, oclgrind_copy_bytes_;
};

}  // namespace swarmcl
