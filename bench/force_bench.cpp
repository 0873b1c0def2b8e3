// Force model (shape-constrained flying insects) steps per second on the
// paper's moon and running-horse scenarios (examples/scenarios/force_*.json,
// Table 1 parameters) at 5k, 10k and 20k insects, beside the paper's CPU
// simulation FPS (Table 1 on a 4-core i7-7700: moon 71.45 at 5k and 38.17 at
// 10k; running horse 70.93 at 5k, 33.99 at 10k and 8.37 at 20k, the table's
// only 20k row, which the moon at 20k is also set beside), with and without
// the neighbour sample cap
// (ForceModelConfig::neighbor_sample).
//
//   force_bench [--scenarios moon,horse] [--counts 5000,10000,20000]
//               [--caps 0,64] [--warmup 30] [--seconds 4] [--json PATH]
//
// The swarm first flies `warmup` steps from the scenario's start (so the
// shape has begun to form and the grid is in its steady layout), then steps
// are timed in batches until `seconds` have passed (at least 2 batches).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "roofline.hpp"
#include "scenario/make_swarm.hpp"
#include "models/force_model.hpp"
#include "swarm/swarm.hpp"

using namespace swarmcl;

namespace {

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string t; std::getline(ss, t, ',');)
        if (!t.empty()) out.push_back(t);
    return out;
}

// Table 1's CPU FPS for the scenario (its rows per scene: moon 5k/10k,
// mammoth-to-shark 5k/10k, running horse 5k/10k/20k).
double paper_fps(const std::string& shape, uint32_t n) {
    if (n > 10000) return 8.37;
    if (shape == "horse") return n <= 5000 ? 70.93 : 33.99;
    return n <= 5000 ? 71.45 : 38.17;
}

struct Row {
    std::string scenario;
    uint32_t n = 0, cap = 0;
    double steps_per_s = 0.0, paper = 0.0;
    std::vector<double> batch_s;
    uint32_t batch = 0;
    double copy_gbs = 0;  // the roofline's copy kernel at n float4, this run (issue 29)
    swarmcl::bench::RooflineRow roofline;
};

// The least a force-model step must move per insect (issue 29): read and
// write its position and velocity (4 float4: 64 B), and rebuild the
// neighbour grid in grid order (92 B, as neighbor_grid_bench counts it);
// the target shape's samples and the neighbours' reads stay in cache.
constexpr double kForceStepBytes = 64.0 + 92.0;

}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> scenarios{"moon", "horse"};
    std::vector<uint32_t> counts{5000, 10000, 20000}, caps{0, 64};
    uint32_t warmup = 30;
    double seconds = 4.0;
    std::string json = std::string(SWARMCL_BENCH_RESULTS_DIR) + "/force.json";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "%s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--scenarios") scenarios = split(next());
        else if (a == "--counts") { counts.clear(); for (auto& t : split(next())) counts.push_back(uint32_t(std::stoul(t))); }
        else if (a == "--caps") { caps.clear(); for (auto& t : split(next())) caps.push_back(uint32_t(std::stoul(t))); }
        else if (a == "--warmup") warmup = uint32_t(std::stoul(next()));
        else if (a == "--seconds") seconds = std::stod(next());
        else if (a == "--json") json = next();
        else {
            std::printf("force_bench [--scenarios moon,horse] [--counts 5000,10000,20000] [--caps 0,64]\n"
                        "            [--warmup 30] [--seconds 4] [--json PATH]\n");
            return a == "-h" || a == "--help" ? 0 : 2;
        }
    }
    auto ctx = std::make_shared<Context>("", "");
    const double load_before = bench::load_average();
    std::printf("force model benchmark on %s / %s, load average %.2f\n", ctx->device().platform_name.c_str(),
                ctx->device().device_name.c_str(), load_before);
    std::printf("%-6s %6s %5s %10s %10s %8s   (roofline: %.0f B an insect a step at the least)\n", "shape", "N",
                "cap", "steps/s", "paper FPS", "ratio", kForceStepBytes);
    std::vector<Row> rows;
    for (const std::string& name : scenarios) {
        const std::string file = std::string(SWARMCL_SOURCE_DIR) + "/examples/scenarios/force_" + name + "_5k.json";
        const Scenario base = load_scenario(file);
        for (uint32_t n : counts)
            for (uint32_t cap : caps) {
                Scenario s = base;
                s.swarm.agent_count = n;
                s.swarm.capacity = n;
                std::get<ForceModelConfig>(s.model).neighbor_sample = cap;
                auto swarm = make_swarm(ctx, s);
                swarm->step(warmup);
                ctx->queue().finish();
                Row r;
                r.scenario = name;
                r.n = n;
                r.cap = cap;
                r.paper = paper_fps(name, n);
                // Batches of about 1 s at the warm-up's pace.
                r.batch = 1;
                double total = 0.0;
                uint64_t steps = 0;
                while (total < seconds || r.batch_s.size() < 2) {
                    const auto t0 = std::chrono::steady_clock::now();
                    swarm->step(r.batch);
                    ctx->queue().finish();
                    const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
                    r.batch_s.push_back(dt / r.batch);
                    total += dt;
                    steps += r.batch;
                    if (dt < 0.5) r.batch *= 2;
                }
                r.steps_per_s = steps / total;
                r.copy_gbs = bench::copy_bandwidth_gbs(*ctx, n);
                r.roofline = bench::roofline_row("force model full step", kForceStepBytes, n,
                                                 1e3 * bench::median(r.batch_s), r.copy_gbs);
                std::printf("%-6s %6u %5u %10.2f %10.2f %7.2fx   roofline %.2f GB/s = %.0f%% of copy (%.2f GB/s)\n",
                            name.c_str(), n, cap, r.steps_per_s, r.paper, r.steps_per_s / r.paper, r.roofline.gbs,
                            100.0 * r.roofline.of_copy, r.copy_gbs);
                std::fflush(stdout);
                rows.push_back(r);
            }
    }
    const double load_after = bench::load_average();
    std::ofstream out(json);
    out << "{\n  \"benchmark\": \"force_bench\",\n  \"utc\": \"" << bench::utc_now() << "\",\n"
        << "  \"device\": \"" << bench::json_escape(ctx->device().device_name) << "\",\n"
        << "  \"platform\": \"" << bench::json_escape(ctx->device().platform_name) << "\",\n"
        << "  \"load_average_before\": " << load_before << ",\n  \"load_average_after\": " << load_after << ",\n"
        << "  \"warmup_steps\": " << warmup << ",\n"
        << "  \"paper\": \"Table 1 CPU FPS, 4-core i7-7700: moon 5k 71.45, 10k 38.17; horse 5k 70.93, 10k 33.99, 20k 8.37 (moon 20k set beside the horse 20k)\",\n  \"rows\": [\n";
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        out << "    {\"scenario\": \"" << r.scenario << "\", \"agents\": " << r.n << ", \"neighbor_sample\": " << r.cap
            << ", \"steps_per_s\": " << r.steps_per_s << ", \"paper_fps\": " << r.paper
            << ", \"ratio\": " << r.steps_per_s / r.paper << ", \"seconds_per_step\": " << bench::json_array(r.batch_s, 1.0)
            << ", \"roofline\": " << bench::roofline_json({r.roofline}, r.copy_gbs) << "}" << (i + 1 < rows.size() ? "," : "") << "\n";
    }
    out << "  ]\n}\n";
    std::printf("load average %.2f -> %.2f; wrote %s\n", load_before, load_after, json.c_str());
    return 0;
}
