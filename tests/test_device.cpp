// The device layer: listing, choice by selector and $SWARMCL_DEVICE, the
// program cache, embedded versus $SWARMCL_KERNEL_DIR sources, and build
// failures reported with the compiler log.
#include <gtest/gtest.h>

#include <chrono>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/error.hpp"
#include "device/buffer.hpp"
#include "device/context.hpp"
#include "device/device_list.hpp"
#include "device/kernel_sources.hpp"
#include "swarmcl/swarmcl.h"

using namespace swarmcl;
namespace fs = std::filesystem;

namespace {

// A temporary folder of this process: ctest runs each test of this file twice
// at once (plain and gpu_profile.), and a shared name let one run remove the
// other's kernel folder mid-test.
fs::path own_temp_dir(const std::string& name) {
    return fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

std::string first_line_of(const std::string& s) { return s.substr(0, s.find('\n')); }

// swcl_last_error() after creating a default swarm, which must fail to build
// (the kernel folder holds a grid.cl that does not make the swarm's kernels).
std::string swarm_build_error() {
    swcl_context c;
    swcl_context_desc d = swcl_context_desc_default();
    EXPECT_EQ(swcl_context_create(&d, &c), SWCL_OK);
    swcl_swarm_desc sd = swcl_swarm_desc_default();
    swcl_swarm s;
    EXPECT_EQ(swcl_swarm_create(c, &sd, &s), SWCL_ERROR_BUILD);
    const std::string last = swcl_last_error();
    EXPECT_EQ(swcl_context_destroy(c), SWCL_OK);
    return last;
}


// Sets an environment variable for one scope.
class ScopedEnv {
public:
    ScopedEnv(const char* name, const std::string& value) : name_(name) {
        if (const char* old = std::getenv(name)) old_ = old, had_ = true;
        setenv(name, value.c_str(), 1);
    }
    ~ScopedEnv() { had_ ? setenv(name_, old_.c_str(), 1) : unsetenv(name_); }

private:
    const char* name_;
    std::string old_;
    bool had_ = false;
};

TEST(Devices, ListedWithNamesAndIndices) {
    const auto devices = list_devices();
    ASSERT_FALSE(devices.empty());
    for (size_t i = 0; i < devices.size(); ++i) {
        EXPECT_EQ(devices[i].index, i);
        EXPECT_FALSE(devices[i].device_name.empty());
        EXPECT_GT(devices[i].global_memory, 0u);
    }
}

TEST(Devices, SelectorByIndexSubstringAndEnvironment) {
    const auto devices = list_devices();
    const auto& last = devices.back();
    EXPECT_EQ(select_device(std::to_string(last.index)).index, last.index);
    // Case-insensitive substring of the device name.
    std::string upper = last.device_name.substr(0, 6);
    for (auto& ch : upper) ch = char(std::toupper(static_cast<unsigned char>(ch)));
    EXPECT_EQ(select_device(upper).device_name.substr(0, 6), last.device_name.substr(0, 6));
    {
        ScopedEnv env("SWARMCL_DEVICE", std::to_string(last.index));
        EXPECT_EQ(select_device("").index, last.index);
        // An explicit selector wins over the environment.
        EXPECT_EQ(select_device("0").index, 0u);
    }
    {
        ScopedEnv env("SWARMCL_DEVICE", "definitely-not-a-device");
        try {
            select_device("");
            FAIL() << "expected NoDevice";
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::NoDevice);
            EXPECT_NE(std::string(e.what()).find("$SWARMCL_DEVICE"), std::string::npos);
        }
    }
}

TEST(Devices, DefaultPrefersGpuThenCpu) {
    const auto devices = list_devices();
    bool any_gpu = false;
    for (const auto& d : devices) any_gpu |= (d.type & CL_DEVICE_TYPE_GPU) != 0;
    const auto chosen = select_device("");
    if (std::getenv("SWARMCL_DEVICE")) GTEST_SKIP() << "$SWARMCL_DEVICE overrides the default";
    EXPECT_TRUE(any_gpu ? (chosen.type & CL_DEVICE_TYPE_GPU) : (chosen.type & CL_DEVICE_TYPE_CPU));
}

TEST(Kernels, EmbeddedSourcesExpandIncludesOnce) {
    const std::string src = load_kernel_source("neighbors.cl");
    EXPECT_NE(src.find("grid_search_box"), std::string::npos);  // from grid_common.cl
    EXPECT_EQ(src.find("#include"), std::string::npos);
    EXPECT_EQ(src.find("typedef struct"), src.rfind("typedef struct"));  // Grid defined once
}

// Files in kernels/ subfolders are named by their path; a per-width body
// (*.inc.cl) is expanded at every #include, any other file once.
TEST(Kernels, IncludesResolveSubfoldersAndRepeatPerWidthBodies) {
    const fs::path dir = own_temp_dir("swarmcl_kernel_dir_inc_test");
    fs::create_directories(dir / "lib");
    fs::create_directories(dir / "wide");
    std::ofstream(dir / "top.cl") << "#include \"lib/helper.cl\"\n#define W 1\n#include \"wide/body.inc.cl\"\n"
                                     "#include \"lib/helper.cl\"\n#define W 8\n#include \"wide/body.inc.cl\"\n";
    std::ofstream(dir / "lib" / "helper.cl") << "int helper_marker;\n";
    std::ofstream(dir / "wide" / "body.inc.cl") << "#include \"lib/helper.cl\"\nint body_marker;\n";
    ScopedEnv env("SWARMCL_KERNEL_DIR", dir.string());
    const std::string src = load_kernel_source("top.cl");
    fs::remove_all(dir);
    auto count = [&](const std::string& what) {
        size_t k = 0;
        for (size_t at = src.find(what); at != std::string::npos; at = src.find(what, at + 1)) ++k;
        return k;
    };
    EXPECT_EQ(count("helper_marker"), 1u) << src;
    EXPECT_EQ(count("body_marker"), 2u) << src;
    EXPECT_EQ(src.find("#include"), std::string::npos) << src;
}

TEST(Kernels, EmbeddedLibraryFilesAreNamedByTheirPath) {
    EXPECT_NE(load_kernel_source("lib/philox.cl").find("swcl_rand_uniform4"), std::string::npos);
    EXPECT_THROW(load_kernel_source("philox.cl"), Error);
}

TEST(Kernels, MissingEmbeddedFileIsAnError) {
    EXPECT_THROW(load_kernel_source("no_such_kernel.cl"), Error);
}

TEST(Kernels, ProgramsAreBuiltOncePerContext) {
    Context ctx("", "");
    cl::Program a = ctx.program("grid.cl");
    cl::Program b = ctx.program("grid.cl");
    EXPECT_EQ(a(), b());
}

TEST(Kernels, BuildingAProgramPrintsNothing) {
    // PoCL printed "3 warnings generated." to stderr building grid.cl (clang's
    // -Wpsabi notes on vector arguments) until the options had -w.  A define
    // of its own (the clock) so that PoCL's cache of built programs misses
    // and the compiler runs.
    Context ctx("", "");
    const std::string unique =
        "-DSWCL_TEST_BUILD_" + std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
    testing::internal::CaptureStderr();
    ctx.program("grid.cl", unique);
    const std::string printed = testing::internal::GetCapturedStderr();
    EXPECT_EQ(printed, "");
}

TEST(Kernels, KernelDirOverridesAndBuildErrorsCarryTheLog) {
    const fs::path dir = own_temp_dir("swarmcl_kernel_dir_test");
    fs::create_directories(dir);
    std::ofstream(dir / "grid.cl") << "__kernel void broken(__global float* x) { x[0] = undefined_name; }\n";
    ScopedEnv env("SWARMCL_KERNEL_DIR", dir.string());
    EXPECT_NE(load_kernel_source("grid.cl").find("undefined_name"), std::string::npos);
    Context ctx("", "");
    try {
        ctx.program("grid.cl");
        FAIL() << "expected a build error";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Build);
        // The first line names the program, the device and the log's first
        // error (issue 27: a new driver refusing a kernel is read at a glance).
        const std::string what = e.what();
        const std::string first_line = first_line_of(what);
        EXPECT_NE(first_line.find("kernels/grid.cl"), std::string::npos) << what;
        EXPECT_NE(first_line.find("'" + ctx.device().device_name + "'"), std::string::npos) << what;
        EXPECT_NE(first_line.find("undefined_name"), std::string::npos) << what;
        EXPECT_NE(first_line.find("error"), std::string::npos) << what;
        EXPECT_NE(what.find("build log:"), std::string::npos) << what;
    }
    // Through the C API: SWCL_ERROR_BUILD, and in swcl_last_error() the
    // kernel the swarm asked for as well.
    const std::string last = swarm_build_error();
    EXPECT_NE(first_line_of(last).find("undefined_name"), std::string::npos) << last;
    EXPECT_NE(first_line_of(last).find("kernels/grid.cl (kernel "), std::string::npos) << last;
    fs::remove_all(dir);
}

TEST(Kernels, AProgramWithoutTheKernelNamesTheKernelAndTheDevice) {
    // A program that builds but lacks the kernel asked for (a new driver
    // leaving a kernel out, or a define that compiles it away): clCreateKernel
    // gives CL_INVALID_KERNEL_NAME, which alone names nothing.  Issue 27: the
    // status is SWCL_ERROR_BUILD and the first line names the program, the
    // kernel, the device and the driver's error; the kernels it has follow.
    const fs::path dir = own_temp_dir("swarmcl_kernel_dir_no_kernel_test");
    fs::create_directories(dir);
    std::ofstream(dir / "grid.cl") << "__kernel void not_the_one(__global float* x) { x[0] = 1.0f; }\n";
    ScopedEnv env("SWARMCL_KERNEL_DIR", dir.string());
    Context ctx("", "");
    try {
        ctx.kernel("grid.cl", "grid_keys_count");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Build);
        const std::string what = e.what();
        const std::string first_line = first_line_of(what);
        EXPECT_NE(first_line.find("kernels/grid.cl (kernel grid_keys_count)"), std::string::npos) << what;
        EXPECT_NE(first_line.find("'" + ctx.device().device_name + "'"), std::string::npos) << what;
        EXPECT_NE(first_line.find("CL_INVALID_KERNEL_NAME"), std::string::npos) << what;
        EXPECT_NE(what.find("kernels the program lists: not_the_one"), std::string::npos) << what;
        EXPECT_NE(what.find("build options: -cl-std=CL1.2"), std::string::npos) << what;
    }
    // Through the C API: SWCL_ERROR_BUILD (it was SWCL_ERROR_OPENCL, naming
    // only clCreateKernel), the kernel in swcl_last_error()'s first line.
    const std::string last = swarm_build_error();
    EXPECT_NE(first_line_of(last).find("kernels/grid.cl (kernel "), std::string::npos) << last;
    EXPECT_NE(first_line_of(last).find("CL_INVALID_KERNEL_NAME"), std::string::npos) << last;
    fs::remove_all(dir);
}

TEST(Kernels, ABuildFailureLeavesOtherContextsUsable) {
    // One context's program fails (a driver refusing a kernel); a context
    // made before it and one made after, with the good sources, still work.
    swcl_context before;
    swcl_context_desc d = swcl_context_desc_default();
    ASSERT_EQ(swcl_context_create(&d, &before), SWCL_OK);
    const fs::path dir = own_temp_dir("swarmcl_kernel_dir_usable_test");
    fs::create_directories(dir);
    std::ofstream(dir / "grid.cl") << "__kernel void broken(__global float* x) { x[0] = undefined_name; }\n";
    {
        ScopedEnv env("SWARMCL_KERNEL_DIR", dir.string());
        swcl_context bad;
        ASSERT_EQ(swcl_context_create(&d, &bad), SWCL_OK);
        swcl_swarm_desc sd = swcl_swarm_desc_default();
        swcl_swarm s;
        EXPECT_EQ(swcl_swarm_create(bad, &sd, &s), SWCL_ERROR_BUILD);
        EXPECT_EQ(swcl_context_destroy(bad), SWCL_OK);
    }
    fs::remove_all(dir);
    swcl_context after;
    ASSERT_EQ(swcl_context_create(&d, &after), SWCL_OK);
    for (swcl_context c : {before, after}) {
        swcl_swarm_desc sd = swcl_swarm_desc_default();
        sd.agent_count = 100;
        swcl_swarm s;
        ASSERT_EQ(swcl_swarm_create(c, &sd, &s), SWCL_OK) << swcl_last_error();
        EXPECT_EQ(swcl_swarm_step(s, 2), SWCL_OK) << swcl_last_error();
        EXPECT_EQ(swcl_swarm_destroy(s), SWCL_OK);
        EXPECT_EQ(swcl_context_destroy(c), SWCL_OK);
    }
}

TEST(Kernels, KernelDirWithAMissingFileSaysWhere) {
    const fs::path dir = own_temp_dir("swarmcl_empty_kernel_dir");
    fs::create_directories(dir);
    ScopedEnv env("SWARMCL_KERNEL_DIR", dir.string());
    try {
        load_kernel_source("grid.cl");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.status(), Status::Io);
        EXPECT_NE(std::string(e.what()).find("SWARMCL_KERNEL_DIR"), std::string::npos);
    }
    fs::remove_all(dir);
}

TEST(Kernels, KernelDirMatchingTheEmbeddedSourcesWorks) {
    ScopedEnv env("SWARMCL_KERNEL_DIR", std::string(SWARMCL_SOURCE_DIR) + "/kernels");
    Context ctx("", "");
    EXPECT_NO_THROW(ctx.program("neighbors.cl"));
}


// launch() on CPU devices: a local size from the fixed set (each one is a
// PoCL compile), at most the device's limit, and enough work-groups that
// both threads of a 2-core device stay busy: PoCL alone made one group of
// any global size up to ~1000.
TEST(Launch, CpuLocalSizeComesFromAFixedSetWithEnoughGroups) {
    DeviceEntry d;
    d.compute_units = 2;
    d.max_work_group_size = 4096;
    const std::vector<size_t> allowed = {16, 64, 256, 1024, 4096};
    for (size_t n : {size_t(1), size_t(37), size_t(300), size_t(625), size_t(1000), size_t(10000), size_t(10007),
                     size_t(62500), size_t(1000000), size_t(50000000)}) {
        const size_t local = cpu_local_size(n, d);
        EXPECT_NE(std::find(allowed.begin(), allowed.end(), local), allowed.end()) << n;
        const size_t groups = (n + local - 1) / local;
        if (n >= 32 * 16) EXPECT_GE(groups, 32u) << n;   // 16 per compute unit
        if (n >= 32 * 4096) EXPECT_EQ(local, 4096u) << n;  // no more groups than needed
    }
    EXPECT_EQ(cpu_local_size(1000, d), 16u);
    EXPECT_EQ(cpu_local_size(10000, d), 256u);
    d.max_work_group_size = 128;  // a device with a lower limit
    for (size_t n : {size_t(100), size_t(1000000)}) EXPECT_LE(cpu_local_size(n, d), 128u) << n;
    d.max_work_group_size = 1;
    EXPECT_EQ(cpu_local_size(1000000, d), 1u);
}

// launch() in the GPU profile: an explicit local size, a power of two of at
// most 128 (and at most max_local and the kernel's limit) instead of the
// driver's choice, the global size padded.  Left to itself PoCL made one work-group of 4000 for
// 20,000 work-items, and energy_select's private state for it overflowed the
// thread's stack (docs/benchmarks.md, "Rehearsal").
TEST(Launch, GpuLocalSizeIsSmallAndExplicit) {
    EXPECT_EQ(gpu_local_size(4096), 128u);
    EXPECT_EQ(gpu_local_size(1024, 64), 64u);
    EXPECT_EQ(gpu_local_size(96), 64u);  // a kernel with a lower limit: a power of two
    EXPECT_EQ(gpu_local_size(1024, 100), 64u);
    EXPECT_EQ(gpu_local_size(0), 1u);

    ScopedEnv env("SWARMCL_DEVICE_PROFILE", "gpu");
    Context ctx("", "");
    static const char* src =
        "__kernel void report_local(__global uint* out, uint n) {\n"
        "    const uint i = get_global_id(0);\n"
        "    if (i >= n) return;\n"
        "    out[i] = (uint)get_local_size(0);\n"
        "}\n";
    cl::Program program(ctx.cl_context(), std::string(src));
    program.build();
    cl::Kernel k(program, "report_local");
    const size_t limit = k.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(ctx.device().device);
    for (size_t max_local : {size_t(4096), size_t(64)}) {
        const size_t n = 20001;
        DeviceBuffer<cl_uint> out(ctx, n, "out");
        set_args(k, out.get(), cl_uint(n));
        launch(ctx, k, n, max_local);
        std::vector<cl_uint> got(n);
        out.download(ctx, got.data(), n);
        const cl_uint want = cl_uint(gpu_local_size(limit, max_local));
        EXPECT_LE(want, 128u);
        for (size_t i = 0; i < n; ++i) ASSERT_EQ(got[i], want) << "work-item " << i << ", max_local " << max_local;
    }
}

// launch() pads the global size to a multiple of the local size (every
// device), so every kernel must return for ids past its count before it
// touches memory.  Checked on the sources: each kernel body opens with an
// early return.
TEST(Kernels, EveryKernelReturnsForWorkItemsPastItsCount) {
    size_t kernels = 0;
    for (const auto& entry : fs::recursive_directory_iterator(fs::path(SWARMCL_SOURCE_DIR) / "kernels")) {
        if (entry.path().extension() != ".cl") continue;
        std::ifstream in(entry.path());
        std::stringstream ss;
        ss << in.rdbuf();
        // Without line comments (they hold semicolons).
        const std::string src = std::regex_replace(ss.str(), std::regex("//[^\n]*"), "");
        const std::regex kernel(R"(__kernel\s+void\s+(\w+)\s*\()");
        for (auto it = std::sregex_iterator(src.begin(), src.end(), kernel); it != std::sregex_iterator(); ++it) {
            // A per-width body (kernels/wide/*.inc.cl) names its kernel
            // SWCL_KERNEL(name): name and name_w, one body.
            kernels += (*it)[1] == "SWCL_KERNEL" ? 2 : 1;
            const size_t body = src.find('{', size_t(it->position()));
            ASSERT_NE(body, std::string::npos);
            // The first four statements of the body.
            size_t end = body;
            for (int k = 0; k < 4 && end != std::string::npos; ++k) end = src.find(';', end + 1);
            const std::string head = src.substr(body, end == std::string::npos ? std::string::npos : end - body + 1);
            EXPECT_TRUE(std::regex_search(head, std::regex(R"(if \([^;]*\) return;)")))
                << (*it)[1] << " in " << entry.path().filename() << " does not return early past its count";
        }
    }
    EXPECT_GT(kernels, 40u);
}

}  // namespace

namespace {

// The capabilities a context checks and the kernels rely on, as queried.
TEST(DeviceProfiles, CapabilitiesAreQueried) {
    const Context ctx("", "");
    const DeviceEntry& d = ctx.device();
    EXPECT_GE(opencl_c_version_number(d.opencl_c_version), 120) << d.opencl_c_version;
    EXPECT_GT(d.max_work_group_size, 0u);
    EXPECT_FALSE(d.extensions.empty());
    EXPECT_EQ(opencl_c_version_number("OpenCL C 1.2 pocl"), 120);
    EXPECT_EQ(opencl_c_version_number("OpenCL C 3.0 "), 300);
    EXPECT_EQ(opencl_c_version_number("OpenCL C 1.1"), 110);
    EXPECT_EQ(opencl_c_version_number("no version"), 0);
    DeviceEntry e;
    e.extensions = "cl_khr_fp64 cl_khr_int64_base_atomics";
    EXPECT_TRUE(e.has_extension("cl_khr_fp64"));
    EXPECT_TRUE(e.has_extension("cl_khr_int64_base_atomics"));
    EXPECT_FALSE(e.has_extension("cl_khr_fp6"));
    EXPECT_FALSE(e.has_extension("cl_khr_int64"));
}

// $SWARMCL_DEVICE_PROFILE forces the GPU paths on any device (the gpu_profile.
// ctest suites run every device test so); a bad value is refused.
TEST(DeviceProfiles, EnvironmentForcesTheProfile) {
    {
        ScopedEnv env("SWARMCL_DEVICE_PROFILE", "gpu");
        const Context ctx("", "");
        EXPECT_FALSE(ctx.device().cpu_profile);
    }
    {
        ScopedEnv env("SWARMCL_DEVICE_PROFILE", "cpu");
        const Context ctx("", "");
        EXPECT_TRUE(ctx.device().cpu_profile);
    }
    {
        ScopedEnv env("SWARMCL_DEVICE_PROFILE", "tpu");
        try {
            Context ctx("", "");
            FAIL() << "a bad profile was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.status(), Status::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("SWARMCL_DEVICE_PROFILE"), std::string::npos) << e.what();
        }
    }
}

// In the GPU profile no x86 builtin reaches the compiler: the prefetch macro
// is empty (a strict OpenCL C 1.2 compiler has no __builtin_prefetch).
TEST(DeviceProfiles, PrefetchIsCpuProfileOnly) {
    const std::string src = load_kernel_source("lib/prefetch.cl");
    const auto guard = src.find("SWCL_CPU_PROFILE");
    const auto builtin = src.find("__builtin_prefetch");
    ASSERT_NE(guard, std::string::npos);
    ASSERT_NE(builtin, std::string::npos);
    EXPECT_LT(guard, builtin);
    ScopedEnv env("SWARMCL_DEVICE_PROFILE", "gpu");
    Context ctx("", "");
    // The MDE program (the prefetch's one user) builds with the define off.
    const cl::Program p = ctx.program("min_distance.cl", "-DMDE_WIDTH=16");
    const std::string options = p.getBuildInfo<CL_PROGRAM_BUILD_OPTIONS>(ctx.device().device);
    EXPECT_NE(options.find("-DSWCL_CPU_PROFILE=0"), std::string::npos) << options;
}

}  // namespace
