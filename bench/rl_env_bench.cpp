// The RL environment's speed (issue 15): agent-steps per second of a whole
// environment step (actions in, leader + kinematics + observations + rewards
// on the device, observations and rewards out), with actions from the RAG
// (timed apart), for W worlds x N agents.
//   rl_env_bench [--scenario NAME] [W N [steps]] ...   (default: roaming,
//   10 x 100 and 64 x 100)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "bench_util.hpp"
#include "device/context.hpp"
#include "rl/leader_env.hpp"
#include "rl/rl_scenarios.hpp"
#include <string>

using namespace swarmcl;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

void run(Context& ctx, const std::string& scenario, uint32_t W, uint32_t N, int steps) {
    RlEnvConfig c;
    apply_rl_scenario(scenario, c);
    c.worlds = W;
    c.agents = N;
    c.max_steps = 1u << 30;
    LeaderEnv env(ctx, c);
    env.reset(1);
    const size_t n = size_t(W) * N;
    std::vector<float> act(4 * n), obs(size_t(env.obs_dim()) * n), rew(n);
    std::vector<uint8_t> term(W), trunc(W);
    // Warm-up: PoCL compiles each kernel for its launch size on first use.
    env.rag_actions(act.data(), act.size());
    env.step(act.data(), act.size());
    std::vector<double> t_step, t_rag;
    for (int i = 0; i < steps; ++i) {
        auto t0 = Clock::now();
        env.rag_actions(act.data(), act.size());
        t_rag.push_back(seconds_since(t0));
        t0 = Clock::now();
        env.step(act.data(), act.size());
        env.read_observations(obs.data(), obs.size());
        env.read_rewards(rew.data(), rew.size());
        env.read_terminated(term.data(), W);
        env.read_truncated(trunc.data(), W);
        t_step.push_back(seconds_since(t0));
    }
    const double s = bench::median(t_step), r = bench::median(t_rag);
    std::printf("%-13s %5u worlds x %4u agents = %7zu: env step %8.2f ms  %10.0f agent-steps/s   RAG %7.2f ms  "
                "(median of %d; load %.1f)\n",
                scenario.c_str(), W, N, n, 1e3 * s, double(n) / s, 1e3 * r, steps, bench::load_average());
}

}  // namespace

int main(int argc, char** argv) {
    Context ctx("", "");
    std::printf("rl_env_bench on %s (timings on a shared machine are noisy)\n", ctx.device().device_name.c_str());
    std::string scenario = "roaming";
    int first = 1;
    if (argc >= 3 && std::string(argv[1]) == "--scenario") {
        scenario = argv[2];
        first = 3;
    }
    if (argc - first >= 2) {
        for (int i = first; i + 1 < argc;) {
            const uint32_t W = uint32_t(std::atoi(argv[i])), N = uint32_t(std::atoi(argv[i + 1]));
            int steps = 20;
            i += 2;
            if (i < argc && argc - i == 1) steps = std::atoi(argv[i++]);
            run(ctx, scenario, W, N, steps);
        }
    } else {
        run(ctx, scenario, 10, 100, 20);
        run(ctx, scenario, 64, 100, 20);
    }
    return 0;
}
