// Worlds (issue 25): agent-steps per second of W worlds x N agents stepped
// as one swarm of worlds, against one swarm of W x N agents of the same model
// at the same density (its domain W^(1/3) times as wide) in the same run,
// rounds alternated, beside the same W worlds each in a domain of its own
// (own grid and placement; not the path model, whose grid covers one
// domain).  And W swarms of N stepped one after another (what a fit did
// before worlds), timed over fewer steps.
//   worlds_bench [--model field|force|energy|path|policy] [--worlds 1000] [--agents 300] [--steps 20]
//                [--rounds 3] [--alone-worlds 64] [--json PATH]
// The model: the field model (curl noise, a goal, MDE), the force model
// (examples/evaluation/force_mosquito.json's zones and weights, curl noise,
// MDE) or the energy model (Table 1 aggregation about each swarm's own
// centre, the synthetic dataset of energy_bench) or the path model
// (examples/evaluation/path_mosquito.json's: curl noise, a sphere goal's cost
// field on a 24^3 grid, MDE) or the policy model (the shipped policy after
// a leader, at policy_bench's density: each world a 27.8 m cube, cells of
// 6.17 m).  Writes bench/results/worlds.json (worlds_force.json,
// worlds_energy.json, worlds_path.json, worlds_policy.json).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "device/context.hpp"
#include "models/field_model.hpp"
#include "data/dataset.hpp"
#include "models/energy_model.hpp"
#include "models/force_model.hpp"
#include "models/path_model.hpp"
#include "models/policy_model.hpp"
#include "rl/policy_weights.hpp"
#include "swarm/swarm.hpp"

using namespace swarmcl;
using Clock = std::chrono::steady_clock;

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

constexpr float kHalfSide = 1.5f;  // m: one world's domain is [-1.5, 1.5]^3
// The policy model at policy_bench's density (200 agents in a ball of radius
// 15 m): 300 agents a world in [-13.9, 13.9]^3, cells of (r_coh + body) / 3.
constexpr float kPolicyHalfSide = 13.9f, kPolicyCell = 6.17f;

FieldModelConfig model() {
    FieldModelConfig m;
    m.noise.type = NoiseType::Curl;
    m.noise.scale = 0.4f;
    m.noise.gain = 0.25f;
    m.noise.seed = 3;
    m.has_goal = true;
    m.goal = {0.3f, 0.0f, 0.0f};
    m.goal_radius = 0.3f;
    m.goal_speed = 0.5f;
    m.min_distance = 0.03f;
    return m;
}

// examples/evaluation/force_mosquito.json's model, with MDE.
ForceModelConfig force_model() {
    ForceModelConfig m;
    m.r_rep = 0.05f;
    m.r_ali = 0.2f;
    m.r_att = 1.0f;
    m.w_rep = 1.0f;
    m.w_ali = 1.0f;
    m.w_att = 4.0f;
    m.alpha = 0.7f;
    m.max_speed = 1.2f;
    m.cruise_speed = 0.3f;
    m.noise.type = NoiseType::Curl;
    m.noise.scale = 0.3f;
    m.noise.gain = 1.0f;
    m.noise.seed = 2;
    m.min_distance = 0.03f;
    return m;
}

// examples/evaluation/path_mosquito.json's model.
PathModelConfig path_model() {
    PathModelConfig m;
    m.noise.type = NoiseType::Curl;
    m.noise.scale = 0.4f;
    m.noise.gain = 0.5f;
    m.noise.seed = 2;
    m.noise.boundary_distance = 0.3f;
    m.noise.domain_walls = true;
    m.resolution = {24, 24, 24};
    m.speed = 0.5f;
    m.goal_falloff = 1.0f;
    Goal g;
    g.kind = Goal::Kind::Sphere;
    g.radius = 0.3f;
    m.groups.push_back({0, {g}});
    m.min_distance = 0.02f;
    return m;
}

// The models this bench runs: --model's name and what the JSON says of it.
struct BenchModel {
    const char* name;
    const char* description;
};
constexpr BenchModel kModels[] = {
    {"field", "field (curl noise, goal, MDE 0.03 m)"},
    {"force", "force (force_mosquito zones and weights, curl noise, MDE 0.03 m)"},
    {"energy", "energy (Table 1 aggregation, each swarm's centre, synthetic dataset)"},
    {"path", "path (path_mosquito: curl noise, a sphere goal's field on 24^3 cells, MDE 0.02 m)"},
    {"policy", "policy (the shipped policy after a leader, policy_bench's density, dt 0.1 s)"},
};
std::string g_model = "field";  // --model
bool g_policy = false;          // g_model == "policy": its own scale and time step
std::shared_ptr<const Dataset> g_dataset;
std::shared_ptr<const std::string> g_policy_bytes;  // the shipped policy

// own_domains: world k in a box of its own, each axis 0.8 to 1.2 times the
// cube's and shifted (so each world has its own grid and placement; the
// noise region stays the cube's).
std::unique_ptr<Swarm> make(std::shared_ptr<Context> ctx, uint32_t worlds, uint32_t agents, float half,
                            uint64_t seed, bool own_domains = false) {
    SwarmConfig c;
    c.capacity = agents;
    c.agent_count = agents;
    c.seed = seed;
    c.worlds = worlds;
    c.domain_min = {-half, -half, -half};
    c.domain_max = {half, half, half};
    for (uint32_t k = 0; own_domains && k < worlds; ++k) {
        Domain d;
        for (int a = 0; a < 3; ++a) {
            const float f = 0.8f + 0.4f * float((k * 7 + a * 3) % 11) / 10.0f;
            const float shift = 0.1f * half * float((k + a) % 3);
            d.min[a] = -half * f + shift;
            d.max[a] = half * f + shift;
        }
        c.world_domains.push_back(d);
    }
    c.interaction_radius = g_policy ? kPolicyCell : 0.2f;
    c.dt = g_policy ? 0.1f : 0.01f;
    auto s = std::make_unique<Swarm>(std::move(ctx), c);
    if (g_policy) {
        s->set_behavior(std::make_shared<PolicyModel>(*s, PolicyModelConfig{}, g_policy_bytes));
        return s;
    }
    if (g_model == "force") {
        ForceModelConfig m = force_model();
        if (m.noise.domain_walls && !m.noise.has_region()) {  // the cube's walls for every world
            m.noise.region_min = c.domain_min;
            m.noise.region_max = c.domain_max;
        }
        s->set_behavior(std::make_shared<ForceModel>(*s, m));
        return s;
    }
    if (g_model == "energy") {
        EnergyModelConfig e;  // Table 1 aggregation; the centre: each swarm's own
        s->set_behavior(std::make_shared<EnergyModel>(*s, e, g_dataset));
        return s;
    }
    if (g_model == "path") {
        s->set_behavior(std::make_shared<PathModel>(*s, path_model()));
        return s;
    }
    FieldModelConfig m = model();
    m.noise.region_min = c.domain_min;
    m.noise.region_max = c.domain_max;
    s->set_behavior(std::make_shared<FieldModel>(*s, m));
    return s;
}

// Seconds per step of `s` over `steps` steps (after one warm-up step).
double time_steps(Context& ctx, Swarm& s, int steps) {
    s.step(1);
    ctx.queue().finish();
    const auto t0 = Clock::now();
    s.step(uint32_t(steps));
    ctx.queue().finish();
    return seconds_since(t0) / steps;
}

}  // namespace

int main(int argc, char** argv) {
    uint32_t worlds = 1000, agents = 300, alone_worlds = 64;
    int steps = 20, rounds = 3;
    std::string json;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const auto next = [&]() -> const char* {
            if (i + 1 >= argc) {
                std::fprintf(stderr, "worlds_bench: %s needs a value\n", a.c_str());
                std::exit(2);
            }
            return argv[++i];
        };
        if (a == "--model") {
            const std::string m = next();
            if (std::none_of(std::begin(kModels), std::end(kModels), [&](const BenchModel& b) { return m == b.name; })) {
                std::fprintf(stderr, "worlds_bench: --model field, force, energy, path or policy\n");
                return 2;
            }
            g_model = m;
            g_policy = m == "policy";
        } else if (a == "--worlds") worlds = uint32_t(std::atoi(next()));
        else if (a == "--agents") agents = uint32_t(std::atoi(next()));
        else if (a == "--steps") steps = std::atoi(next());
        else if (a == "--rounds") rounds = std::atoi(next());
        else if (a == "--alone-worlds") alone_worlds = uint32_t(std::atoi(next()));
        else if (a == "--json") json = next();
        else {
            std::fprintf(stderr, "usage: worlds_bench [--model field|force|energy|path|policy] [--worlds W] [--agents N] [--steps S] [--rounds R] "
                                 "[--alone-worlds K] [--json PATH]\n");
            return 2;
        }
    }
    if (!worlds || !agents || steps < 1 || rounds < 1) {
        std::fprintf(stderr, "worlds_bench: worlds, agents, steps and rounds must be > 0\n");
        return 2;
    }
    if (json.empty())
        json = std::string(SWARMCL_BENCH_RESULTS_DIR) +
               (g_model == "field" ? std::string("/worlds.json") : "/worlds_" + g_model + ".json");
    const char* model_name =
        std::find_if(std::begin(kModels), std::end(kModels), [](const BenchModel& b) { return g_model == b.name; })
            ->description;
    if (g_model == "energy") g_dataset = std::make_shared<const Dataset>(synthetic_dataset(DatasetOptions{}));
    if (g_policy)
        g_policy_bytes = std::make_shared<const std::string>(
            read_policy_file(std::string(SWARMCL_SOURCE_DIR) + "/models/policy_roaming.safetensors"));
    const float half_side = g_policy ? kPolicyHalfSide : kHalfSide;
    auto ctx = std::make_shared<Context>("", "");
    const auto& dev = ctx->device();
    std::printf("device: %s (%s; %u compute units); load %.1f\n", dev.device_name.c_str(), dev.platform_name.c_str(),
                dev.compute_units, bench::load_average());
    const size_t total = size_t(worlds) * agents;
    const float big_half = half_side * std::cbrt(float(worlds));
    std::printf("%s model: %u worlds x %u agents in [-%.1f, %.1f]^3 each, "
                "against one swarm of %zu agents in [-%.1f, %.1f]^3 (the same density); %d steps, %d rounds\n",
                model_name, worlds, agents, half_side, half_side, total, big_half, big_half, steps, rounds);

    auto ensemble = make(ctx, worlds, agents, half_side, 1);
    auto single = make(ctx, 1, uint32_t(total), big_half, 1);
    // Worlds of their own domains (not the path model's: its grid covers one).
    auto own = g_model == "path" ? nullptr : make(ctx, worlds, agents, half_side, 1, true);
    std::vector<double> t_worlds, t_single, t_own;
    for (int r = 0; r < rounds; ++r) {
        t_worlds.push_back(time_steps(*ctx, *ensemble, steps));
        t_single.push_back(time_steps(*ctx, *single, steps));
        if (own) t_own.push_back(time_steps(*ctx, *own, steps));
        std::printf("  round %d: worlds %8.2f ms/step   one swarm %8.2f ms/step   worlds of own domains %8.2f "
                    "ms/step  (load %.1f)\n", r + 1, 1e3 * t_worlds.back(), 1e3 * t_single.back(),
                    own ? 1e3 * t_own.back() : 0.0, bench::load_average());
    }
    ensemble.reset();
    single.reset();
    own.reset();
    // Before worlds: K swarms of N stepped one after another, each its own
    // launches (the fit's way), per agent-step.
    std::vector<std::unique_ptr<Swarm>> alone;
    for (uint32_t k = 0; k < alone_worlds; ++k) alone.push_back(make(ctx, 1, agents, half_side, k + 1));
    for (auto& s : alone) s->step(1);
    ctx->queue().finish();
    const int alone_steps = std::max(1, steps / 2);
    const auto t0 = Clock::now();
    for (int i = 0; i < alone_steps; ++i)
        for (auto& s : alone) s->step(1);
    ctx->queue().finish();
    const double alone_rate = double(alone_worlds) * agents * alone_steps / seconds_since(t0);
    alone.clear();

    const double w = bench::median(t_worlds), s = bench::median(t_single);
    const double rate_w = double(total) / w, rate_s = double(total) / s;
    std::printf("worlds:        %8.2f ms/step  %6.2f M agent-steps/s\n", 1e3 * w, rate_w / 1e6);
    std::printf("one swarm:     %8.2f ms/step  %6.2f M agent-steps/s\n", 1e3 * s, rate_s / 1e6);
    const double o = t_own.empty() ? 0.0 : bench::median(t_own), rate_o = o > 0.0 ? double(total) / o : 0.0;
    if (o > 0.0)
        std::printf("worlds of their own domains: %8.2f ms/step  %6.2f M agent-steps/s (%.2f x the worlds of one)\n",
                    1e3 * o, rate_o / 1e6, rate_o / rate_w);
    std::printf("swarms alone:  %u x %u stepped one after another: %6.2f M agent-steps/s\n", alone_worlds, agents,
                alone_rate / 1e6);
    std::printf("worlds / one swarm = %.2f (target >= 0.70: %s); worlds / swarms alone = %.1fx\n", rate_w / rate_s,
                rate_w / rate_s >= 0.70 ? "met" : "missed", rate_w / alone_rate);

    std::ofstream f(json);
    if (!f) {
        std::fprintf(stderr, "worlds_bench: cannot write %s\n", json.c_str());
        return 1;
    }
    f << "{\n  \"benchmark\": \"worlds_bench\",\n  \"date\": \"" << bench::utc_now() << "\",\n"
      << "  \"device\": \"" << bench::json_escape(dev.device_name) << "\",\n  \"load_average\": "
      << bench::load_average() << ",\n  \"model\": \"" << model_name << "\",\n"
      << "  \"worlds\": " << worlds << ",\n  \"agents_per_world\": " << agents << ",\n  \"steps\": " << steps
      << ",\n  \"rounds\": " << rounds << ",\n  \"worlds_s_per_step\": " << bench::json_array(t_worlds, 1.0)
      << ",\n  \"one_swarm_s_per_step\": " << bench::json_array(t_single, 1.0)
      << ",\n  \"own_domains_s_per_step\": " << bench::json_array(t_own, 1.0)
      << ",\n  \"own_domains_agent_steps_per_s\": " << rate_o
      << ",\n  \"worlds_agent_steps_per_s\": " << rate_w << ",\n  \"one_swarm_agent_steps_per_s\": " << rate_s
      << ",\n  \"ratio\": " << rate_w / rate_s << ",\n  \"target_ratio\": 0.7,\n  \"alone_swarms\": " << alone_worlds
      << ",\n  \"alone_agent_steps_per_s\": " << alone_rate << ",\n  \"worlds_over_alone\": " << rate_w / alone_rate
      << "\n}\n";
    std::printf("wrote %s\n", json.c_str());
    return 0;
}
