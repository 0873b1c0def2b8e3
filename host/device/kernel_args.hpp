// Kernel argument counts.  Arguments are set by position, so a launch that
// sets fewer than the kernel takes would run with whatever an earlier launch
// left in the missing ones (a silent mis-binding), and a helper that sets
// one argument too many or too few shifts every argument after it.  Every
// launch site therefore checks the count it set against the kernel's
// CL_KERNEL_NUM_ARGS: set_args() (device/buffer.hpp) before it sets
// anything, index chains (`i = swarm.set_step_args(k, step); ...
// k.setArg(i++, x);`) with check_arg_count(k, i) before the launch.  A
// mismatch is a bug in swarmcl, so it is Status::Internal.
#pragma once
#include <string>

#include "core/error.hpp"
#include "device/opencl.hpp"

namespace swarmcl {

// The kernel's name (CL_KERNEL_FUNCTION_NAME), or "?" if the query fails.
inline std::string kernel_name(const cl::Kernel& kernel) {
    size_t size = 0;
    if (clGetKernelInfo(kernel(), CL_KERNEL_FUNCTION_NAME, 0, nullptr, &size) != CL_SUCCESS || size == 0) return "?";
    std::string name(size, '\0');
    if (clGetKernelInfo(kernel(), CL_KERNEL_FUNCTION_NAME, size, &name[0], nullptr) != CL_SUCCESS) return "?";
    name.resize(name.find('\0') == std::string::npos ? name.size() : name.find('\0'));
    return name;
}

// How many arguments the kernel takes (CL_KERNEL_NUM_ARGS).  A plain field
// read in the driver: no cache needed (docs/architecture.md).
inline cl_uint kernel_arg_count(const cl::Kernel& kernel) {
    cl_uint count = 0;
    const cl_int err = clGetKernelInfo(kernel(), CL_KERNEL_NUM_ARGS, sizeof count, &count, nullptr);
    if (err != CL_SUCCESS)
        fail(Status::OpenCL, "clGetKernelInfo(CL_KERNEL_NUM_ARGS) failed (" + std::to_string(err) + ")");
    return count;
}

// The failure, apart from the check so the check stays small.
[[noreturn]] inline void fail_arg_count(const cl::Kernel& kernel, cl_uint count, cl_uint expected) {
    fail(Status::Internal, "kernel " + kernel_name(kernel) + ": " + std::to_string(count) +
                               " arguments set, it takes " + std::to_string(expected) + " (CL_KERNEL_NUM_ARGS)");
}

// Throws Status::Internal unless `count` is the number of arguments `kernel`
// takes.  Index chains call it with their final index, before the launch.
inline void check_arg_count(const cl::Kernel& kernel, cl_uint count) {
    const cl_uint expected = kernel_arg_count(kernel);
    if (count != expected) fail_arg_count(kernel, count, expected);
}

}  // namespace swarmcl
