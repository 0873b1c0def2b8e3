// A typed device buffer that owns its cl::Buffer (released with it) and knows
// its element count.
#pragma once
#include <cstddef>
#include <string>

#include "core/error.hpp"
#include "device/context.hpp"

namespace swarmcl {

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
        if (count) ctx.queue().enqueueFillBuffer(buffer_, value, 0, count * sizeof(T));
    }
    void upload(Context& ctx, const T* src, size_t count, bool blocking = true) {
        if (count) ctx.queue().enqueueWriteBuffer(buffer_, blocking ? CL_TRUE : CL_FALSE, 0, count * sizeof(T), src);
    }
    void download(Context& ctx, T* dst, size_t count) {
        if (count) ctx.queue().enqueueReadBuffer(buffer_, CL_TRUE, 0, count * sizeof(T), dst);
    }

private:
    cl::Buffer buffer_;
    size_t count_ = 0;
};

// Sets kernel arguments in order: set_args(k, a, b, c).
template <typename... Args>
void set_args(cl::Kernel& kernel, const Args&... args) {
    cl_uint index = 0;
    (kernel.setArg(index++, args), ...);
}

// Enqueues a 1-D kernel over `n` work-items with the local size left to the
// implementation (DESIGN.md: PoCL picks it best).
inline void launch(Context& ctx, cl::Kernel& kernel, size_t n) {
    if (n) ctx.queue().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(n), cl::NullRange);
}

}  // namespace swarmcl
