// A typed device buffer that owns its cl::Buffer (released with it) and knows
// its element count.
#pragma once
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "device/context.hpp"
#include "device/kernel_args.hpp"

namespace swarmcl {

// Writes `bytes` bytes from `src` at `offset` of `buffer`
// (clEnqueueWriteBuffer).  On Oclgrind (Context::on_oclgrind()) a write of
// anything but the whole buffer goes through a staging buffer and a kernel
// copy: a host write of part of a buffer would replace its whole shadow
// there.  Blocking on Oclgrind whatever `blocking` says (the staging write is).
inline void write_buffer(Context& ctx, cl::Buffer& buffer, size_t offset, size_t bytes, const void* src,
                         bool blocking = true) {
    if (!bytes) return;
    if (!ctx.on_oclgrind() || (offset == 0 && bytes == buffer.getInfo<CL_MEM_SIZE>())) {
        ctx.queue().enqueueWriteBuffer(buffer, blocking ? CL_TRUE : CL_FALSE, offset, bytes, src);
        return;
    }
    ctx.oclgrind_copy(ctx.oclgrind_staging(src, bytes), 0, buffer, offset, bytes);
}

// Copies `bytes` bytes from src at src_offset to dst at dst_offset
// (clEnqueueCopyBuffer; a kernel copy on Oclgrind, as write_buffer()).
inline void copy_buffer(Context& ctx, const cl::Buffer& src, cl::Buffer& dst, size_t src_offset, size_t dst_offset,
                        size_t bytes) {
    if (!bytes) return;
    if (!ctx.on_oclgrind()) {
        ctx.queue().enqueueCopyBuffer(src, dst, src_offset, dst_offset, bytes);
        return;
    }
    ctx.oclgrind_copy(src, src_offset, dst, dst_offset, bytes);
}

// Fills `bytes` bytes of `buffer` from `offset` with copies of `value`
// (clEnqueueFillBuffer).  On Oclgrind the pattern is written with
// write_buffer(): Oclgrind 21.10 gives a fill the shadow of one pattern
// element, so every kernel reading filled memory would be reported.
template <typename T>
void fill_buffer(Context& ctx, cl::Buffer& buffer, const T& value, size_t offset, size_t bytes) {
    if (!bytes) return;
    if (!ctx.on_oclgrind()) {
        ctx.queue().enqueueFillBuffer(buffer, value, offset, bytes);
        return;
    }
    std::vector<unsigned char> pattern(bytes);
    for (size_t at = 0; at + sizeof(T) <= bytes; at += sizeof(T)) std::memcpy(pattern.data() + at, &value, sizeof(T));
    write_buffer(ctx, buffer, offset, bytes, pattern.data());
}

template <typename T>
class DeviceBuffer {
public:
    DeviceBuffer() = default;
    DeviceBuffer(Context& ctx, size_t count, const char* what) { allocate(ctx, count, what); }

    // Replaces the buffer with one of `count` elements (contents undefined).
    void allocate(Context& ctx, size_t count, const char* what) {
        const size_t n = count ? count : 1;  // OpenCL refuses empty buffers
        const unsigned long long bytes = (unsigned long long)n * sizeof(T);
        if (bytes > ctx.max_allocation())
            fail(Status::OutOfMemory, std::string(what) + ": " + std::to_string(bytes) +
                                          " bytes exceed the device's largest allocation (" +
                                          std::to_string(ctx.max_allocation()) + ")");
        buffer_ = cl::Buffer(ctx.cl_context(), CL_MEM_READ_WRITE, bytes);
        ctx.keep(buffer_);  // Oclgrind only: its id is never reused (Context::on_oclgrind())
        count_ = count;
    }

    // Grows (never shrinks) to at least `count` elements.
    void reserve(Context& ctx, size_t count, const char* what) {
        if (!buffer_() || count > count_) allocate(ctx, count, what);
    }

    size_t size() const { return count_; }
    cl::Buffer& get() { return buffer_; }
    const cl::Buffer& get() const { return buffer_; }

    void fill(Context& ctx, const T& value, size_t count) {
        fill_buffer(ctx, buffer_, value, 0, count * sizeof(T));
    }
    void upload(Context& ctx, const T* src, size_t count, bool blocking = true) {
        write_buffer(ctx, buffer_, 0, count * sizeof(T), src, blocking);
    }
    void download(Context& ctx, T* dst, size_t count) {
        if (count) ctx.queue().enqueueReadBuffer(buffer_, CL_TRUE, 0, count * sizeof(T), dst);
    }

private:
    cl::Buffer buffer_;
    size_t count_ = 0;
};

// Sets kernel arguments in order: set_args(k, a, b, c).  They must be all
// of the kernel's arguments (check_arg_count: Status::Internal otherwise,
// before any is set).
template <typename... Args>
void set_args(cl::Kernel& kernel, const Args&... args) {
    check_arg_count(kernel, cl_uint(sizeof...(Args)));
    cl_uint index = 0;
    (kernel.setArg(index++, args), ...);
}

// The local size launch() uses on CPU devices for n work-items: the largest
// of a fixed set (PoCL compiles each local size apart) that still gives at
// least 16 work-groups per compute unit, so the threads finish close
// together.  Left to itself, PoCL 3.1 makes one work-group of any global size
// up to ~1000 (one thread runs it all: the force model's 625 work-items of
// 16 agents at 10k) and 5 groups of 2000 for 10000 (one of 2 cores runs 3);
// measured with a kernel that reports get_local_size.  Other devices:
// gpu_local_size().  max_local caps it for kernels with much private memory
// per work-item (PoCL keeps a work-group's private data together).
inline size_t cpu_local_size(size_t n, const DeviceEntry& device, size_t max_local = 4096) {
    const size_t groups = 16 * size_t(std::max<uint32_t>(1, device.compute_units));
    for (size_t local : {4096, 1024, 256, 64})
        if (local <= max_local && local <= device.max_work_group_size && (n + local - 1) / local >= groups)
            return local;
    return std::min<size_t>(16, std::max<size_t>(1, device.max_work_group_size));
}

// The local size launch() asks for on other devices (the GPU profile): the
// largest power of two up to kGpuLocalSize, max_local and `kernel_limit`
// (the kernel's CL_KERNEL_WORK_GROUP_SIZE on the device, which is at most
// the device's CL_DEVICE_MAX_WORK_GROUP_SIZE).  A power of two, so a launch
// of a multiple of 128 work-items is never padded (the policy MLP's chunks
// of 1024 tiles rely on it: policy_model.cpp).  Left to the driver (a NULL local size),
// PoCL in the GPU profile made one work-group of 4000 for 20,000 agents, and
// energy_select's private state for 4000 work-items overflowed its thread's
// stack (docs/benchmarks.md, "Rehearsal"); a driver may also pick a poor
// divisor of an awkward global size.  128 work-items is 4 warps on NVIDIA,
// 2 wavefronts on AMD; the kernels use no local memory and no barriers, so
// the size changes no result.
inline constexpr size_t kGpuLocalSize = 128;
inline size_t gpu_local_size(size_t kernel_limit, size_t max_local = 4096) {
    const size_t cap = std::min({kGpuLocalSize, max_local, kernel_limit});
    size_t local = 1;
    while (local * 2 <= cap) local *= 2;
    return local;
}

// Enqueues a 1-D kernel over `n` work-items, the global size rounded up to a
// multiple of the local size, so every kernel launched here returns at once
// for ids >= n (each checks its own count).  CPU devices: cpu_local_size().
// Other devices: gpu_local_size() (one clGetKernelWorkGroupInfo per launch).
inline void launch(Context& ctx, cl::Kernel& kernel, size_t n, size_t max_local = 4096) {
    if (!n) return;
    const DeviceEntry& device = ctx.device();
    const size_t local =
        device.cpu_profile
            ? cpu_local_size(n, device, max_local)
            : gpu_local_size(kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device.device), max_local);
    ctx.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange((n + local - 1) / local * local),
                                     cl::NDRange(local));
}

// Enqueues a 2-D kernel of groups_x x groups_y work-groups of exactly
// local_x x local_y work-items (kernels with local memory and barriers, whose
// tiles fix the group's shape: the policy MLP's tiled kernel, the grid's
// prefix sum as groups_y = local_y = 1).  The caller
// checks the kernel's CL_KERNEL_WORK_GROUP_SIZE first.
inline void launch_groups_2d(Context& ctx, cl::Kernel& kernel, size_t groups_x, size_t groups_y, size_t local_x,
                             size_t local_y) {
    if (!groups_x || !groups_y) return;
    ctx.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(groups_x * local_x, groups_y * local_y),
                                     cl::NDRange(local_x, local_y));
}

// Enqueues a 1-D kernel over `n` work-items that each process a long chunk
// (a few hundred work-items at most, and exactly n of them).  CPU devices:
// each work-item is its own work-group, so any thread can take any chunk
// (the grid merge over 245 chunks ran on one of 2 cores before).  Other
// devices: the driver's choice.
inline void launch_chunks(Context& ctx, cl::Kernel& kernel, size_t n) {
    if (!n) return;
    const bool cpu = ctx.device().cpu_profile;
    ctx.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(n), cpu ? cl::NDRange(1) : cl::NullRange);
}

}  // namespace swarmcl

namespace swarmcl {

// Enqueues a kernel over `n` work-items in each of `worlds` worlds: a 2-D
// range (n, worlds), world get_global_id(1) (lib/grid_common.cl, "Worlds").
// One world is launch()'s 1-D range exactly.  CPU devices: the local size of
// launch() for all the worlds' work-items, shrunk (within the same set of
// sizes, which PoCL compiles apart) while it still covers a world, so a small
// world does not run as a mostly empty work-group; other devices:
// gpu_local_size(), as launch().
// The build option of the kernels a swarm of `worlds` worlds launches: the
// world offsets are compiled in for several worlds only (lib/grid_common.cl).
inline std::string world_defines(uint32_t worlds) { return worlds > 1 ? " -DSWCL_WORLDS=1" : ""; }

inline void launch_worlds(Context& ctx, cl::Kernel& kernel, size_t n, size_t worlds, size_t max_local = 4096) {
    if (!n || !worlds) return;
    if (worlds == 1) {
        launch(ctx, kernel, n, max_local);
        return;
    }
    const DeviceEntry& device = ctx.device();
    size_t local = 0;
    if (device.cpu_profile) {
        local = cpu_local_size(n * worlds, device, max_local);
        while (local > 16 && local / 4 >= n) local /= 4;
    } else {
        local = gpu_local_size(kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device.device), max_local);
    }
    ctx.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange((n + local - 1) / local * local, worlds),
                                     cl::NDRange(local, 1));
}

}  // namespace swarmcl
