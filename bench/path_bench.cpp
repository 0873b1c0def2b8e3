// Path model benchmark (curl-noise paper §7.2, Table 1): for each of the
// paper's scenarios (examples/scenarios/path-*.json) the preprocessing time
// (signed distance + cost field + uploads) and steps per second, with the
// average share of insects MDE moved per step, printed beside Table 1; the
// cost-field recompute when a goal moves (chasing) at 64^3; and 1M insects
// in the locust setting, ms per step.
//
//   path_bench [--steps 200] [--million 1000000] [--json PATH]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "roofline.hpp"
#include "scenario/make_swarm.hpp"
#include "models/path_model.hpp"
#include "swarm/swarm.hpp"

#ifndef SWARMCL_BENCH_RESULTS_DIR
#define SWARMCL_BENCH_RESULTS_DIR "bench/results"
#endif
#ifndef SWARMCL_SCENARIO_DIR
#define SWARMCL_SCENARIO_DIR "examples/scenarios"
#endif

using namespace swarmcl;
using namespace swarmcl::bench;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Table1 {
    const char* file;
    const char* label;
    double preprocess, cpu_fps, gpu_fps, mde_percent;
};

// Table 1 of the paper (Intel Core 2 Duo E7500 and the paper's GPU).  Its
// FPS rows have 4 values for 5 scenarios; the GPU speedup row (5 values,
// GPU/CPU) places them: 1477.1/219.4 = 6.73 (two blocks), 2247.2/587.9 =
// 3.82 (chasing), 1550.4/66.2 = 23.4 (aggregation), 2331.0/1988.1 = 1.17
// (phototaxis); locusts has only its speedup, 53.9 (-1: not given).
const Table1 kPaper[] = {
    {"path_two_blocks", "two blocks (300)", 0.417, 219.4, 1477.1, 0.36},
    {"path_chasing", "chasing (100)", 0.729, 587.9, 2247.2, 0.54},
    {"path_aggregation", "aggregation (1000)", 0.235, 66.2, 1550.4, 0.03},
    {"path_phototaxis", "phototaxis (30)", 2.660, 1988.1, 2331.0, 0.01},
    {"path_locusts", "locusts (5000)", 19.405, -1, -1, 0.68},
};

struct Run {
    double preprocess = 0, steps_per_s = 0, mde_share = 0, ms_per_step = 0;
};

Run run(std::shared_ptr<Context> ctx, const Scenario& s, uint32_t steps, uint32_t agents_override = 0,
        float radius_override = 0) {
    // The scenario's swarm without its model: the model is built below, timed.
    Scenario placed = s;
    placed.model = Ballistic{};
    if (radius_override > 0) placed.swarm.interaction_radius = radius_override;
    const uint32_t n = agents_override ? agents_override : s.swarm.agent_count;
    placed.swarm.capacity = n;
    if (agents_override) {
        // Uniform in the air above the ground (2 m margins; the houses' cells
        // are pushed out by V_g within a few steps).
        const SwarmConfig& c = placed.swarm;
        std::mt19937 rng(1);
        std::vector<float> pos(3 * size_t(n));
        const float lo[3] = {c.domain_min[0] + 2, c.domain_min[1] + 2, c.domain_min[2] + 3};
        const float hi[3] = {c.domain_max[0] - 2, c.domain_max[1] - 2, c.domain_max[2] - 2};
        for (size_t i = 0; i < pos.size(); ++i) {
            std::uniform_real_distribution<float> u(lo[i % 3], hi[i % 3]);
            pos[i] = u(rng);
        }
        placed.swarm.agent_count = n;
        placed.initial.kind = InitialDistribution::Kind::Points;
        placed.initial.points = std::move(pos);
    }
    const auto owned = make_swarm(ctx, placed);
    Swarm& swarm = *owned;
    swarm.ensure_grid();  // agents in grid-cell order, as a run with MDE keeps them
    // Preprocessing as the paper times it: the fields, not the kernel builds
    // (a first model builds the programs, kept by the context).
    const PathModelConfig& config = std::get<PathModelConfig>(s.model);
    PathModel(swarm, config);
    auto model = std::make_shared<PathModel>(swarm, config);
    swarm.set_behavior(model);
    Run r;
    r.preprocess = model->preprocess_seconds();
    swarm.step(3);  // warm-up: kernels compiled, grid built
    swarm.context().queue().finish();
    swarm.take_step_stats();
    const auto t0 = Clock::now();
    swarm.step(steps);
    swarm.context().queue().finish();
    const double t = since(t0);
    const StepStats st = *swarm.take_step_stats();
    r.steps_per_s = steps / t;
    r.ms_per_step = 1000.0 * t / steps;
    r.mde_share = st.steps ? double(st.mde_moved_total) / (double(st.steps) * n) : 0.0;
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    uint32_t steps = 200, million = 1000000;
    std::string json = std::string(SWARMCL_BENCH_RESULTS_DIR) + "/path.json";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--steps") steps = uint32_t(std::atoi(next().c_str()));
        else if (a == "--million") million = uint32_t(std::atoi(next().c_str()));
        else if (a == "--json") json = next();
        else { std::fprintf(stderr, "usage: path_bench [--steps 200] [--million N] [--json PATH]\n"); return 2; }
    }
    auto ctx = std::make_shared<Context>("", "");
    std::printf("path_bench: device %s, %u steps per scenario, load %.2f\n", ctx->device().device_name.c_str(), steps,
                load_average());
    std::printf("  %-20s %12s %12s %10s | paper: %9s %9s %9s %7s\n", "scenario", "preprocess s", "steps/s", "MDE/step",
                "prep. s", "CPU FPS", "GPU FPS", "MDE");
    std::ostringstream js;
    js << "{\n  \"benchmark\": \"path_bench\",\n  \"date\": \"" << utc_now() << "\",\n  \"device\": \""
       << json_escape(ctx->device().device_name) << "\",\n  \"steps\": " << steps << ",\n  \"scenarios\": [";
    bool first = true;
    for (const Table1& p : kPaper) {
        const Scenario s = load_scenario(std::string(SWARMCL_SCENARIO_DIR) + "/" + p.file + ".json");
        const Run r = run(ctx, s, steps);
        std::printf("  %-20s %12.3f %12.1f %9.2f%% | paper: %9.3f %9.1f %9.1f %6.2f%%\n", p.label, r.preprocess,
                    r.steps_per_s, 100 * r.mde_share, p.preprocess, p.cpu_fps, p.gpu_fps, p.mde_percent);
        js << (first ? "" : ",") << "\n    {\"scenario\": \"" << p.file << "\", \"agents\": " << s.swarm.agent_count
           << ", \"grid\": [" << std::get<PathModelConfig>(s.model).resolution[0] << ", "
           << std::get<PathModelConfig>(s.model).resolution[1] << ", "
           << std::get<PathModelConfig>(s.model).resolution[2] << "], \"preprocess_seconds\": " << r.preprocess
           << ", \"steps_per_second\": " << r.steps_per_s << ", \"mde_share\": " << r.mde_share
           << ", \"paper_preprocess_seconds\": " << p.preprocess << ", \"paper_cpu_fps\": " << p.cpu_fps
           << ", \"paper_gpu_fps\": " << p.gpu_fps << ", \"paper_mde_percent\": " << p.mde_percent << "}";
        first = false;
    }
    js << "\n  ],\n";

    // Chasing: the goal moves, the cost field is recomputed (64^3, two sphere obstacles).
    {
        SwarmConfig c;
        c.capacity = 100;
        c.agent_count = 100;
        c.domain_min = {0, 0, 0};
        c.domain_max = {6.4f, 6.4f, 6.4f};
        Swarm swarm(ctx, c);
        PathModelConfig pc;
        pc.resolution = {64, 64, 64};
        pc.obstacles = {sphere_mesh({3.2f, 3.2f, 3.2f}, 0.8f, 24, 48), sphere_mesh({1.5f, 4.5f, 3.0f}, 0.5f, 24, 48)};
        Goal g;
        g.kind = Goal::Kind::Sphere;
        g.radius = 0.3f;
        g.center = {5.5f, 1.0f, 3.2f};
        pc.groups.push_back({0, {g}});
        PathModel model(swarm, pc);
        std::vector<double> times;
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> u(0.5f, 5.9f);
        while (times.size() < 15) {
            g.center = {u(rng), u(rng), u(rng)};
            try {
                times.push_back(model.set_goals(0, {g}));
            } catch (const Error&) {  // inside an obstacle: draw again
            }
        }
        std::printf("  chasing: cost field recompute at 64^3: median %.1f ms (min %.1f ms) over %zu goal moves (target < 100 ms)\n",
                    1000 * median(times), 1000 * minimum(times), times.size());
        js << "  \"chasing_recompute_64_ms\": " << 1000 * median(times) << ",\n  \"chasing_recompute_64_runs_ms\": "
           << json_array(times, 1000.0) << ",\n";
    }

    // 1M insects in the locust setting (grid, obstacles, baked noise, MDE),
    // spread over the scenario's domain (at the initial box's density, 100
    // per m^3, MDE would move a quarter of them every step); the neighbour grid's cell is
    // 0.25 m (the scenario's 1 m suits 5000 insects: with 1M it would hold
    // ~100 per cell, and MDE's search would dominate).
    if (million > 0) {
        const Scenario s = load_scenario(std::string(SWARMCL_SCENARIO_DIR) + "/path_locusts.json");
        const Run r = run(ctx, s, 10, million, 0.25f);
        Scenario no_mde = s;
        std::get<PathModelConfig>(no_mde.model).min_distance = 0.0f;
        const Run a = run(ctx, no_mde, 10, million, 0.25f);
        std::printf("  locusts with %u insects: %.1f ms per step (target 50 ms), MDE moved %.2f%% per step;\n"
                    "    without MDE (the path advance kernel alone, agents in grid order): %.1f ms per step\n",
                    million, r.ms_per_step, 100 * r.mde_share, a.ms_per_step);
        // The roofline (issue 29): the advance must at the least read a
        // position and write a position and a velocity (48 B, as the field
        // model's); the full step adds the grid rebuild with its reordering
        // (92 B) and MDE (a position read and written, 32 B).
        const double copy_gbs = swarmcl::bench::copy_bandwidth_gbs(*ctx, million);
        const std::vector<swarmcl::bench::RooflineRow> roof = {
            swarmcl::bench::roofline_row("locusts full step (advance + grid rebuild + MDE)", 48 + 92 + 32, million,
                                         r.ms_per_step, copy_gbs),
            swarmcl::bench::roofline_row("locusts advance alone (no MDE)", 48, million, a.ms_per_step, copy_gbs)};
        swarmcl::bench::print_roofline(roof, copy_gbs);
        js << "  \"locusts_roofline\": " << swarmcl::bench::roofline_json(roof, copy_gbs) << ",\n";
        js << "  \"locusts_agents\": " << million << ",\n  \"locusts_ms_per_step\": " << r.ms_per_step
           << ",\n  \"locusts_mde_share\": " << r.mde_share << ",\n  \"locusts_advance_only_ms_per_step\": "
           << a.ms_per_step << ",\n";
    }
    js << "  \"load_average\": " << load_average() << "\n}\n";
    std::ofstream(json) << js.str();
    std::printf("  wrote %s (load %.2f)\n", json.c_str(), load_average());
    return 0;
}
