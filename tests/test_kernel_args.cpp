// Kernel argument counts (host/device/kernel_args.hpp): set_args() and the
// index chains' check_arg_count() refuse a count other than the kernel's
// CL_KERNEL_NUM_ARGS with Status::Internal naming the kernel, the count set
// and the count it takes.
#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "device/buffer.hpp"
#include "device/context.hpp"
#include "device/kernel_args.hpp"

using namespace swarmcl;

namespace {

// A three-argument kernel built here (no file of kernels/ involved).
cl::Kernel scale_kernel(Context& ctx) {
    static const char* src =
        "__kernel void scale_by(__global float* a, uint n, float x) {\n"
        "    const uint i = get_global_id(0);\n"
        "    if (i < n) a[i] *= x;\n"
        "}\n";
    cl::Program program(ctx.cl_context(), std::string(src));
    program.build();
    return cl::Kernel(program, "scale_by");
}

// The Internal error's message, or "" if `f` did not throw it.
template <typename F>
std::string internal_message(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Internal) << e.what();
        return e.what();
    }
    return "";
}

TEST(KernelArgs, CountAndNameQueried) {
    Context ctx("", "");
    cl::Kernel k = scale_kernel(ctx);
    EXPECT_EQ(kernel_arg_count(k), 3u);
    EXPECT_EQ(kernel_name(k), "scale_by");
}

TEST(KernelArgs, SetArgsRefusesTooFew) {
    Context ctx("", "");
    cl::Kernel k = scale_kernel(ctx);
    DeviceBuffer<cl_float> a(ctx, 4, "a");
    const std::string m = internal_message([&] { set_args(k, a.get(), cl_uint(4)); });
    EXPECT_NE(m.find("scale_by"), std::string::npos) << m;
    EXPECT_NE(m.find("2 arguments set"), std::string::npos) << m;
    EXPECT_NE(m.find("takes 3"), std::string::npos) << m;
}

TEST(KernelArgs, SetArgsRefusesTooMany) {
    Context ctx("", "");
    cl::Kernel k = scale_kernel(ctx);
    DeviceBuffer<cl_float> a(ctx, 4, "a");
    const std::string m = internal_message([&] { set_args(k, a.get(), cl_uint(4), 2.0f, 1.0f); });
    EXPECT_NE(m.find("scale_by"), std::string::npos) << m;
    EXPECT_NE(m.find("4 arguments set"), std::string::npos) << m;
    EXPECT_NE(m.find("takes 3"), std::string::npos) << m;
}

TEST(KernelArgs, SetArgsWithTheRightCountRuns) {
    Context ctx("", "");
    cl::Kernel k = scale_kernel(ctx);
    std::vector<float> v{1, 2, 3, 4};
    DeviceBuffer<cl_float> a(ctx, 4, "a");
    a.upload(ctx, v.data(), 4);
    EXPECT_NO_THROW(set_args(k, a.get(), cl_uint(4), 2.0f));
    launch(ctx, k, 4);
    a.download(ctx, v.data(), 4);
    EXPECT_EQ(v, (std::vector<float>{2, 4, 6, 8}));
}

TEST(KernelArgs, IndexChainCheckedBeforeLaunch) {
    Context ctx("", "");
    cl::Kernel k = scale_kernel(ctx);
    DeviceBuffer<cl_float> a(ctx, 4, "a");
    cl_uint i = 0;
    k.setArg(i++, a.get());
    k.setArg(i++, cl_uint(4));
    // One short: the third argument would be whatever was there before.
    std::string m = internal_message([&] { check_arg_count(k, i); });
    EXPECT_NE(m.find("scale_by: 2 arguments set, it takes 3"), std::string::npos) << m;
    k.setArg(i++, 2.0f);
    EXPECT_NO_THROW(check_arg_count(k, i));
    m = internal_message([&] { check_arg_count(k, i + 1); });
    EXPECT_NE(m.find("scale_by: 4 arguments set, it takes 3"), std::string::npos) << m;
}

// The query runs once per launch: it must cost nothing next to a launch
// (a few microseconds).  A loose bound, so a loaded machine does not fail it.
TEST(KernelArgs, CheckIsCheap) {
    Context ctx("", "");
    cl::Kernel k = scale_kernel(ctx);
    const int reps = 100000;
    const auto t0 = std::chrono::steady_clock::now();
    for (int r = 0; r < reps; ++r) check_arg_count(k, 3);
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() / reps;
    RecordProperty("check_arg_count_ns", std::to_string(ns));
    std::printf("check_arg_count: %.1f ns per call\n", ns);
    EXPECT_LT(ns, 2000.0);
}

}  // namespace
