// Metrics benchmark (issue 14, item 1): the seven metrics of the noise
// paper (§3.2) on the device from a running swarm (eval/swarm_metrics.hpp),
// streamed into histograms, at --agents agents over --frames sampled frames,
// the nearest-neighbour search included.  Target: 100k agents x 500 frames
// within 10 s on the 2-core PoCL CPU (issue 14), 5 s since issue 29.
//
// The swarm runs the field model (curl noise, time varying, domain walls),
// --steps-between steps per sample.  Figures (each the median of --repeats
// runs after one untimed warm-up that compiles the kernels):
//   step_s       the steps alone (frames x steps-between steps)
//   with_s       the same steps with a sample() after each group, and result()
//   metrics_s    with_s - step_s: what sampling adds
// agent-frames/s = agents x frames / metrics_s.
// Peer: the host path (eval/metrics.cpp frame_metrics, one thread: each
// frame's nearest neighbours by a sweep up to 2,048 agents, nanoflann's
// kd-tree above) on --host-frames of the same frames, read back from the
// device; its agent-frames/s and the ratio.
//
// --worlds W (issue 25): a swarm of W worlds of --agents agents each, every
// world measured apart by one SwarmMetrics; peer in the same run: the W
// swarms alone, each with its own SwarmMetrics, stepped and sampled in turn
// (how fits ran before worlds), and the ratio of what sampling adds.  The
// host path then measures world 0's frames.
//
//   metrics_bench [--agents 100000] [--worlds 1] [--frames 500] [--steps-between 1]
//                 [--repeats 3] [--host-frames 20] [--device SELECTOR] [--json PATH]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "roofline.hpp"
#include "device/context.hpp"
#include "eval/metric_accumulator.hpp"
#include "eval/metrics.hpp"
#include "eval/swarm_metrics.hpp"
#include "models/field_model.hpp"
#include "swarm/swarm.hpp"

#ifndef SWARMCL_BENCH_RESULTS_DIR
#define SWARMCL_BENCH_RESULTS_DIR "bench/results"
#endif

namespace {

using namespace swarmcl;
using namespace swarmcl::bench;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// CPU seconds of the whole process (PoCL's worker threads included): on a
// machine shared with other work, CPU time / cores is what the wall time
// would be with the cores to itself.
double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

struct Options {
    uint32_t agents = 100000, worlds = 1, frames = 500, steps_between = 1, repeats = 3, host_frames = 20;
    std::string device, json = std::string(SWARMCL_BENCH_RESULTS_DIR) + "/eval/metrics.json";
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "%s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--agents") o.agents = uint32_t(std::stoul(next()));
        else if (a == "--worlds") o.worlds = uint32_t(std::stoul(next()));
        else if (a == "--frames") o.frames = uint32_t(std::stoul(next()));
        else if (a == "--steps-between") o.steps_between = uint32_t(std::stoul(next()));
        else if (a == "--repeats") o.repeats = uint32_t(std::stoul(next()));
        else if (a == "--host-frames") o.host_frames = uint32_t(std::stoul(next()));
        else if (a == "--device") o.device = next();
        else if (a == "--json") o.json = next();
        else {
            std::fprintf(stderr, "unknown option %s\n", a.c_str());
            std::exit(2);
        }
    }
    return o;
}

std::unique_ptr<Swarm> make_swarm(std::shared_ptr<Context> ctx, uint32_t agents, uint32_t worlds = 1,
                                  uint64_t seed = 1) {
    SwarmConfig c;
    c.capacity = agents;
    c.agent_count = agents;
    c.seed = seed;
    c.worlds = worlds;
    // About 0.02 m between neighbours at 100k agents, as a dense swarm.
    c.domain_min = {-1.0f, -1.0f, -1.0f};
    c.domain_max = {1.0f, 1.0f, 1.0f};
    c.interaction_radius = 0.1f;
    c.dt = 1.0f / 60.0f;
    auto swarm = std::make_unique<Swarm>(ctx, c);
    FieldModelConfig m;
    m.noise.seed = 1;
    m.noise.time_scale = 0.5f;
    m.noise.gain = 0.5f;
    // No goal: the pull gathers everything into a small core within seconds,
    // a uniform grid's worst case (cells from the bounding box), not a swarm.
    m.noise.domain_walls = true;
    swarm->set_behavior(std::make_shared<FieldModel>(*swarm, m));
    return swarm;
}

// Seconds of `frames` x (step, sample) over W swarms alone of `agents` each
// (seeds 1 + k, as the worlds' defaults), sampling or not.
double alone_seconds(std::shared_ptr<Context> ctx, const Options& o, bool sample) {
    std::vector<std::unique_ptr<Swarm>> swarms;
    std::vector<std::unique_ptr<SwarmMetrics>> metrics;
    for (uint32_t k = 0; k < o.worlds; ++k) {
        swarms.push_back(make_swarm(ctx, o.agents, 1, 1 + k));
        if (sample) metrics.push_back(std::make_unique<SwarmMetrics>(*swarms.back(), o.steps_between / 60.0));
    }
    const auto t0 = Clock::now();
    for (uint32_t f = 0; f < o.frames; ++f)
        for (uint32_t k = 0; k < o.worlds; ++k) {
            swarms[k]->step(o.steps_between);
            if (sample) metrics[k]->sample();
        }
    for (auto& m : metrics) m->result();
    ctx->queue().finish();
    return seconds_since(t0);
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    auto ctx = std::make_shared<Context>(o.device, "");
    const double dt = double(o.steps_between) / 60.0;
    std::printf("metrics_bench: %u world(s) x %u agents x %u sampled frames, %u step(s) between, device %s\n",
                o.worlds, o.agents, o.frames, o.steps_between, ctx->device().device_name.c_str());
    std::vector<double> step_s, with_s, step_cpu, with_cpu, alone_step_s, alone_with_s;
    uint64_t checksum = 0;
    for (uint32_t r = 0; r <= o.repeats; ++r) {  // r = 0: warm-up
        {
            auto swarm = make_swarm(ctx, o.agents, o.worlds);
            auto t0 = Clock::now();
            const double c0 = cpu_seconds();
            for (uint32_t f = 0; f < o.frames; ++f) swarm->step(o.steps_between);
            ctx->queue().finish();
            if (r) step_s.push_back(seconds_since(t0)), step_cpu.push_back(cpu_seconds() - c0);
        }
        {
            auto swarm = make_swarm(ctx, o.agents, o.worlds);
            SwarmMetrics metrics(*swarm, dt);
            auto t0 = Clock::now();
            const double c0 = cpu_seconds();
            for (uint32_t f = 0; f < o.frames; ++f) {
                swarm->step(o.steps_between);
                metrics.sample();
            }
            checksum = 0;
            for (uint32_t k = 0; k < o.worlds; ++k) checksum += metrics.result(k).count(Metric::NearestDistance);
            if (r) with_s.push_back(seconds_since(t0)), with_cpu.push_back(cpu_seconds() - c0);
        }
        if (r) std::printf("  run %u: steps %.3f s, steps + metrics %.3f s\n", r, step_s.back(), with_s.back());
        if (o.worlds > 1) {  // the peer, alternated with the worlds
            alone_step_s.push_back(alone_seconds(ctx, o, false));
            alone_with_s.push_back(alone_seconds(ctx, o, true));
            if (r) std::printf("  run %u: %u swarms alone: steps %.3f s, steps + metrics %.3f s\n", r, o.worlds,
                               alone_step_s.back(), alone_with_s.back());
            else alone_step_s.clear(), alone_with_s.clear();
        }
    }
    const double steps = median(step_s), with = median(with_s), metrics_s = with - steps;
    const double metrics_cpu = median(with_cpu) - median(step_cpu);
    const unsigned cores = std::max(1u, ctx->device().compute_units);
    const double af = double(o.agents) * o.worlds * o.frames;
    double alone_metrics_s = 0.0;
    if (o.worlds > 1) {
        alone_metrics_s = median(alone_with_s) - median(alone_step_s);
        std::printf("%u swarms alone: metrics %.3f s = %.3g agent-frames/s; worlds %.2fx faster\n", o.worlds,
                    alone_metrics_s, af / alone_metrics_s, alone_metrics_s / metrics_s);
    }
    // Issue 29's target: 100k agents x 500 frames in 5 s, 1e7 agent-frames/s.
    const double target_rate = 100000.0 * 500.0 / 5.0;
    std::printf("steps alone %.3f s; with metrics %.3f s; metrics %.3f s = %.3g agent-frames/s (target %.3g: %s)\n",
                steps, with, metrics_s, af / metrics_s, target_rate, af / metrics_s >= target_rate ? "met" : "NOT met");

    // The roofline (issue 29): the bytes one sampled frame must move at the
    // least per agent: the position gathered into the ring (20 + 16 B), the
    // four ring positions read (64 B), the seven values written and read by
    // the moments and the histogram (3 x 28 B), the nearest-neighbour search
    // (keys from a position, the sorted copy written and read, 16 + 4 + 16 +
    // 16 B) and what is kept for the next sample (ω, the neighbour: 16 B).
    const double copy_gbs = swarmcl::bench::copy_bandwidth_gbs(*ctx, size_t(o.agents) * o.worlds);
    const std::vector<swarmcl::bench::RooflineRow> roof = {swarmcl::bench::roofline_row(
        "metrics of one sampled frame", 36 + 64 + 84 + 52 + 16, double(o.agents) * o.worlds,
        metrics_s / o.frames * 1e3, copy_gbs)};
    swarmcl::bench::print_roofline(roof, copy_gbs);
    std::printf("CPU time of sampling %.3f s (all threads; load average %.2f): %.3f s over %u cores with them to itself\n",
                metrics_cpu, load_average(), metrics_cpu / cores, cores);

    // Peer: the host path on the first host_frames frames of the same run.
    double host_s = 0.0;
    if (o.host_frames >= 4) {
        auto swarm = make_swarm(ctx, o.agents, o.worlds);
        std::vector<float> xyz(size_t(o.host_frames) * o.agents * 3), all(size_t(o.agents) * o.worlds * 3);
        for (uint32_t f = 0; f < o.host_frames; ++f) {
            swarm->step(o.steps_between);
            swarm->read(Attribute::Position, all.data(), all.size() / 3);  // world 0 first
            std::copy(all.begin(), all.begin() + size_t(o.agents) * 3, xyz.begin() + size_t(f) * o.agents * 3);
        }
        auto t0 = Clock::now();
        const MetricSamples s = frame_metrics(xyz.data(), o.host_frames, o.agents, dt);
        MetricAccumulator acc;
        acc.add(s);
        host_s = seconds_since(t0);
        const double host_af = double(o.agents) * o.host_frames / host_s;
        std::printf("host path (frame_metrics + accumulator, 1 thread): %u frames %.3f s = %.3g agent-frames/s; "
                    "device %.1fx\n",
                    o.host_frames, host_s, host_af, (af / metrics_s) / host_af);
    }

    std::ostringstream j;
    j.precision(6);
    j << "{\n  \"benchmark\": \"metrics\",\n  \"date\": \"" << utc_now() << "\",\n  \"device\": \""
      << json_escape(ctx->device().device_name) << "\",\n  \"load_average\": " << load_average()
      << ",\n  \"agents\": " << o.agents << ",\n  \"worlds\": " << o.worlds << ",\n  \"frames\": " << o.frames
      << ",\n  \"steps_between\": " << o.steps_between << ",\n  \"repeats\": " << o.repeats
      << ",\n  \"model\": \"field (curl noise, time varying, domain walls)\""
      << ",\n  \"step_s\": " << json_array(step_s, 1.0) << ",\n  \"with_metrics_s\": " << json_array(with_s, 1.0)
      << ",\n  \"step_cpu_s\": " << json_array(step_cpu, 1.0) << ",\n  \"with_metrics_cpu_s\": "
      << json_array(with_cpu, 1.0) << ",\n  \"metrics_cpu_s\": " << metrics_cpu << ",\n  \"compute_units\": " << cores
      << ",\n  \"metrics_s_median\": " << metrics_s << ",\n  \"agent_frames_per_s\": " << af / metrics_s
      << ",\n  \"d_samples\": " << checksum << ",\n  \"host_frames\": " << o.host_frames
      << ",\n  \"alone_step_s\": " << json_array(alone_step_s, 1.0) << ",\n  \"alone_with_metrics_s\": "
      << json_array(alone_with_s, 1.0) << ",\n  \"alone_metrics_s_median\": " << alone_metrics_s
      << ",\n  \"roofline\": " << swarmcl::bench::roofline_json(roof, copy_gbs) << ",\n  \"host_s\": " << host_s << ",\n  \"host_agent_frames_per_s\": "
      << (host_s > 0 ? double(o.agents) * o.host_frames / host_s : 0.0) << "\n}\n";
    const auto dir = std::filesystem::path(o.json).parent_path();
    std::error_code ec;
    if (!dir.empty()) std::filesystem::create_directories(dir, ec);
    std::ofstream out(o.json);
    if (!out) {
        std::fprintf(stderr, "cannot write %s\n", o.json.c_str());
        return 1;
    }
    out << j.str();
    std::printf("wrote %s\n", o.json.c_str());
    return 0;
}
