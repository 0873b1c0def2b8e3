// A roofline for the benchmarks' stages (issue 29): the device's copy
// bandwidth, measured in the same run on the same device by a STREAM-like
// copy kernel (float4 in, float4 out; built here from source, not a library
// kernel), beside which a stage's bytes it must move and the bandwidth it
// reached say how near its memory limit it runs.
#pragma once
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "device/buffer.hpp"
#include "device/context.hpp"

namespace swarmcl::bench {

// GB/s (1e9 bytes) of copying `n` float4 (read + write: 32 n bytes), the
// median of `reps` passes after one warm-up.
inline double copy_bandwidth_gbs(swarmcl::Context& ctx, size_t n, int reps = 9) {
    static const char* kSource =
        "__kernel void roofline_copy(__global const float4* a, __global float4* b, uint n) {\n"
        "    const uint i = get_global_id(0);\n"
        "    if (i < n) b[i] = a[i];\n"
        "}\n";
    cl::Program program(ctx.cl_context(), kSource);
    program.build("-cl-std=CL1.2");
    cl::Kernel k(program, "roofline_copy");
    swarmcl::DeviceBuffer<cl_float4> a(ctx, n, "roofline a"), b(ctx, n, "roofline b");
    a.fill(ctx, cl_float4{{1.0f, 2.0f, 3.0f, 4.0f}}, n);
    k.setArg(0, a.get());
    k.setArg(1, b.get());
    k.setArg(2, cl_uint(n));
    auto& q = ctx.queue();
    std::vector<double> t;
    for (int r = 0; r <= reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        q.enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(n), cl::NullRange);
        q.finish();
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (r > 0) t.push_back(s);
    }
    return 32.0 * double(n) / median(t) * 1e-9;
}

// GB/s of copying `n` doubles on the host with std::copy (read + write: 16 n
// bytes), the median of `reps` passes after one warm-up: the roof of a stage
// that runs on the host (the fast-marching solver), one thread.
inline double host_copy_bandwidth_gbs(size_t n, int reps = 9) {
    std::vector<double> a(n, 1.0), b(n, 0.0);
    std::vector<double> t;
    for (int r = 0; r <= reps; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        std::copy(a.begin(), a.end(), b.begin());
        const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (r > 0) t.push_back(s);
        a[r % n] = b[(r + 1) % n];  // keeps the copies from being folded away
    }
    return 16.0 * double(n) / median(t) * 1e-9;
}

// One stage against the copy bandwidth.
struct RooflineRow {
    std::string stage;
    double bytes_per_agent = 0;  // what the stage must move at the least
    double ms = 0;               // median time of the stage
    double gbs = 0;              // bytes / time
    double of_copy = 0;          // gbs / the copy kernel's
};

inline RooflineRow roofline_row(const std::string& stage, double bytes_per_agent, double agents, double ms,
                                double copy_gbs) {
    RooflineRow r{stage, bytes_per_agent, ms, 0, 0};
    r.gbs = ms > 0 ? bytes_per_agent * agents / (ms * 1e-3) * 1e-9 : 0.0;
    r.of_copy = copy_gbs > 0 ? r.gbs / copy_gbs : 0.0;
    return r;
}

inline void print_roofline(const std::vector<RooflineRow>& rows, double copy_gbs) {
    std::printf("   roofline: copy kernel %.2f GB/s on this device, this run\n", copy_gbs);
    std::printf("   %-52s %9s %10s %9s %8s\n", "stage", "B/agent", "median ms", "GB/s", "of copy");
    for (const auto& r : rows)
        std::printf("   %-52s %9.0f %10.2f %9.2f %7.0f%%\n", r.stage.c_str(), r.bytes_per_agent, r.ms, r.gbs,
                    100.0 * r.of_copy);
}

inline std::string roofline_json(const std::vector<RooflineRow>& rows, double copy_gbs) {
    std::string j = "{\"copy_gbs\": " + std::to_string(copy_gbs) + ", \"stages\": [";
    for (size_t i = 0; i < rows.size(); ++i) {
        const auto& r = rows[i];
        j += (i ? ", " : "") + std::string("{\"stage\": \"") + json_escape(r.stage) +
             "\", \"bytes_per_agent\": " + std::to_string(r.bytes_per_agent) + ", \"ms\": " + std::to_string(r.ms) +
             ", \"gbs\": " + std::to_string(r.gbs) + ", \"of_copy\": " + std::to_string(r.of_copy) + "}";
    }
    return j + "]}";
}

}  // namespace swarmcl::bench
