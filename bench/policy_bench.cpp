// The policy model's speed (issue 15 item 7): steps per second of a swarm of
// N agents driven by a policy (observations over the neighbour grid + the
// MLP + Eq. 2 on the device, one swarm), with the MLP and the observations
// timed apart, beside the RAG-driven environment step at the same number of
// agents (W worlds of 100: the environment's neighbour loops are per world).
//   policy_bench [--weights FILE] [--out FILE] [--cell M] [N [steps]] ...
//   (default: the shipped policy, 10k, 100k and 1M agents)
// Agents are placed uniformly at the density of a 200-agent swarm in a ball
// of radius 15 (~0.014 per m^3: ~370 agents within R_coh + body = 18.5 m of
// each), headings random, speed 1; the leader in the middle.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "device/context.hpp"
#include "roofline.hpp"
#include "models/policy_model.hpp"
#include "policy_scene.hpp"
#include "rl/leader_env.hpp"
#include "rl/rl_scenarios.hpp"
#include "swarm/swarm.hpp"

using namespace swarmcl;
using Clock = std::chrono::steady_clock;

namespace {

double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

struct Row {
    uint32_t n = 0;
    int steps = 0;
    double step_s = 0, observe_s = 0, mlp_s = 0, infer_s = 0, env_step_s = 0, rag_s = 0, neighbours = 0;
    double copy_gbs = 0;  // the roofline's copy kernel at n float4, this run (issue 29)
    std::string mlp_kernel;  // policy_mlp_tiled (the GPU profile) or policy_mlp at its lanes
    uint32_t observe_lanes = 1;  // policy_observe_w's agents per work-item (1: policy_observe)
    std::vector<bench::RooflineRow> roofline;
};

float g_cell = bench::kPolicyCell;  // the swarm's interaction_radius: the grid's cell edge

Row run(std::shared_ptr<Context> ctx, const std::shared_ptr<const std::string>& bytes, uint32_t n, int steps) {
    Row r;
    r.n = n;
    r.steps = steps;
    auto swarm_ptr = bench::policy_random_swarm(ctx, n, g_cell);
    Swarm& swarm = *swarm_ptr;
    auto model = bench::policy_model_on(swarm, bytes);
    r.mlp_kernel = model->tiled_mlp() ? "policy_mlp_tiled"
                                      : "policy_mlp, " + std::to_string(model->mlp_lanes()) + " lanes";
    r.observe_lanes = model->lanes();
    // Mean neighbours within 18.5 m, from the grid's count query (a sample).
    {
        std::vector<uint32_t> counts(n);
        swarm.neighbor_count(18.5f, counts.data(), n);
        double s = 0;
        for (uint32_t c : counts) s += c;
        r.neighbours = s / n;
    }
    swarm.step(1);  // warm-up: PoCL compiles per launch size
    ctx->queue().finish();
    std::vector<double> ts;
    for (int i = 0; i < steps; ++i) {
        const auto t0 = Clock::now();
        swarm.step(1);
        ctx->queue().finish();
        ts.push_back(since(t0));
    }
    r.step_s = bench::median(ts);
    // The observations alone (on the device, nothing read back), then the
    // MLP alone on this step's observations (with their copies).
    std::vector<double> to;
    model->observe_on_device(swarm);  // the grid of this state built outside the timing
    for (int i = 0; i < 3; ++i) {
        const auto t1 = Clock::now();
        model->observe_on_device(swarm);
        to.push_back(since(t1));
    }
    r.observe_s = bench::median(to);
    // The MLP alone on those observations, on the device.
    std::vector<double> td;
    model->mlp_on_device(swarm);  // warm-up
    for (int i = 0; i < 3; ++i) {
        const auto t3 = Clock::now();
        model->mlp_on_device(swarm);
        td.push_back(since(t3));
    }
    r.mlp_s = bench::median(td);
    // And through infer(), the host's copies of observations and actions
    // included (a GPU's bus: on a CPU device the copies are memcpy).
    std::vector<float> obs;
    model->observe(swarm, &obs, nullptr);
    std::vector<double> tm;
    const uint32_t sub = std::min<uint32_t>(n, 100000);
    obs.resize(size_t(sub) * model->obs_dim());
    model->infer(obs, sub);  // warm-up
    for (int i = 0; i < 3; ++i) {
        const auto t2 = Clock::now();
        model->infer(obs, sub);
        tm.push_back(since(t2));
    }
    r.infer_s = bench::median(tm) * double(n) / sub;
    // The environment at the same number of agents: W worlds of 100, RAG actions.
    RlEnvConfig ec;
    apply_rl_scenario("roaming", ec);
    ec.worlds = std::max<uint32_t>(1, n / 100);
    ec.agents = 100;
    ec.max_steps = 1u << 30;
    LeaderEnv env(*ctx, ec);
    env.reset(1);
    std::vector<float> act(4 * size_t(ec.worlds) * 100);
    env.rag_actions(act.data(), act.size());
    env.step(act.data(), act.size());
    std::vector<double> te, tr;
    const int env_steps = std::max(2, steps / 2);
    for (int i = 0; i < env_steps; ++i) {
        auto t0 = Clock::now();
        env.rag_actions(act.data(), act.size());
        tr.push_back(since(t0));
        t0 = Clock::now();
        env.step(act.data(), act.size());
        ctx->queue().finish();
        te.push_back(since(t0));
    }
    r.env_step_s = bench::median(te);
    r.rag_s = bench::median(tr);
    return r;
}

}  // namespace

int run(const std::string& weights, const std::string& out, const std::vector<std::pair<uint32_t, int>>& sizes);

int main(int argc, char** argv) {
    std::string weights = std::string(SWARMCL_SOURCE_DIR) + "/models/policy_roaming.safetensors";
    std::string out = std::string(SWARMCL_SOURCE_DIR) + "/bench/results/policy.json";
    std::vector<std::pair<uint32_t, int>> sizes;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--weights" && i + 1 < argc) {
            weights = argv[++i];
        } else if (a == "--cell" && i + 1 < argc) {
            g_cell = float(std::atof(argv[++i]));
        } else if ((a == "--out" || a == "--json") && i + 1 < argc) {
            out = argv[++i];
        } else if (a.empty() || a[0] < '0' || a[0] > '9') {
            std::fprintf(stderr, "policy_bench: unknown argument '%s'\nusage: policy_bench [--weights FILE] "
                                 "[--json FILE] [--cell M] [N [steps]] ...\n", a.c_str());
            return 2;
        } else {
            const uint32_t n = uint32_t(std::atol(argv[i]));
            int steps = 10;
            if (i + 1 < argc && std::atol(argv[i + 1]) < 1000 && std::string(argv[i + 1]).find('-') != 0) steps = std::atoi(argv[++i]);
            sizes.push_back({n, steps});
        }
    }
    if (sizes.empty()) sizes = {{10000, 10}, {100000, 10}, {1000000, 3}};
    try {
        return run(weights, out, sizes);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "policy_bench: %s\n", e.what());
        return 1;
    }
}

int run(const std::string& weights, const std::string& out, const std::vector<std::pair<uint32_t, int>>& sizes) {
    auto ctx = std::make_shared<Context>("", "");
    auto bytes = std::make_shared<const std::string>(read_policy_file(weights));
    const PolicyWeights w = parse_policy_weights(reinterpret_cast<const uint8_t*>(bytes->data()), bytes->size());
    double macs = 0;
    std::string shape = std::to_string(w.obs_dim);
    for (const auto& L : w.layers) {
        macs += double(L.in) * L.out;
        shape += "-" + std::to_string(L.out);
    }
    std::printf("policy_bench on %s (%u compute units), policy %s (%.0f multiply-adds per agent), grid cell %.2f m; "
                "load %.1f\n", ctx->device().device_name.c_str(), ctx->device().compute_units, shape.c_str(), macs,
                g_cell, bench::load_average());
    std::vector<Row> rows;
    for (auto [n, steps] : sizes) {
        Row r = run(ctx, bytes, n, steps);
        // The roofline (issue 29): the least each stage must move per agent.
        // Observations: read the agent's state (2 float4) and write its
        // observation; the MLP: read the observation, write 4 action floats
        // (its weights stay in cache); the step: the agent's state read and
        // written, the grid rebuilt in grid order (92 B) and the observation
        // written and read back.
        const double obs_bytes = 4.0 * w.obs_dim;
        r.copy_gbs = bench::copy_bandwidth_gbs(*ctx, n);
        r.roofline = {bench::roofline_row("observations", 32 + obs_bytes, n, 1e3 * r.observe_s, r.copy_gbs),
                      bench::roofline_row("MLP", obs_bytes + 16, n, 1e3 * r.mlp_s, r.copy_gbs),
                      bench::roofline_row("policy full step", 64 + 92 + 2 * obs_bytes, n, 1e3 * r.step_s,
                                          r.copy_gbs)};
        rows.push_back(r);
        std::printf("N %8u: policy step %9.2f ms = %7.2f steps/s (observe %.1f ms [%u lanes], MLP %.1f ms = %.1f GFLOP/s "
                    "[%s], %.1f ms with the host's copies; %.0f neighbours within 18.5 m) | env step (%u worlds x "
                    "100, RAG) %8.2f ms + RAG %7.2f ms\n",
                    n, 1e3 * r.step_s, 1.0 / r.step_s, 1e3 * r.observe_s, r.observe_lanes, 1e3 * r.mlp_s,
                    2.0 * macs * n / r.mlp_s * 1e-9, r.mlp_kernel.c_str(), 1e3 * r.infer_s, r.neighbours, std::max<uint32_t>(1, n / 100), 1e3 * r.env_step_s,
                    1e3 * r.rag_s);
        bench::print_roofline(r.roofline, r.copy_gbs);
        std::fflush(stdout);
    }
    std::ofstream f(out);
    f << "{\n  \"benchmark\": \"policy_bench\",\n  \"date\": \"" << bench::utc_now() << "\",\n  \"device\": \""
      << bench::json_escape(ctx->device().device_name) << "\",\n  \"compute_units\": " << ctx->device().compute_units
      << ",\n  \"load_average\": " << bench::load_average() << ",\n  \"grid_cell_m\": " << g_cell << ",\n  \"policy\": \"" << shape
      << "\",\n  \"macs_per_agent\": " << macs << ",\n  \"density_per_m3\": " << bench::kPolicyDensity << ",\n  \"rows\": [\n";
    for (size_t i = 0; i < rows.size(); ++i) {
        const Row& r = rows[i];
        f << "    {\"agents\": " << r.n << ", \"steps_timed\": " << r.steps << ", \"policy_step_ms\": " << 1e3 * r.step_s
          << ", \"policy_steps_per_s\": " << 1.0 / r.step_s << ", \"observe_ms\": " << 1e3 * r.observe_s
          << ", \"mlp_ms\": " << 1e3 * r.mlp_s << ", \"mlp_gflops\": " << 2.0 * macs * r.n / r.mlp_s * 1e-9
          << ", \"infer_with_copies_ms\": " << 1e3 * r.infer_s << ", \"mlp_kernel\": \"" << r.mlp_kernel << "\", \"observe_lanes\": " << r.observe_lanes << ", \"mean_neighbours\": " << r.neighbours
          << ", \"env_worlds_x_100_step_ms\": " << 1e3 * r.env_step_s << ", \"env_rag_ms\": " << 1e3 * r.rag_s
          << ", \"roofline\": " << bench::roofline_json(r.roofline, r.copy_gbs) << "}"
          << (i + 1 < rows.size() ? "," : "") << "\n";
    }
    f << "  ]\n}\n";
    std::printf("wrote %s\n", out.c_str());
    return 0;
}
