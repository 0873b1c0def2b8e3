// Noise benchmark: swarmcl's curl noise (procedural, with domain walls, time
// varying; baked onto a grid) against libnoise's Perlin module on the same
// points in the same run, and the field model (curl-noise paper §4/§6) at 1M
// insects, step by step and stage by stage.
//
// Device-side figures time the kernel alone (enqueue + finish): the points
// and the output stay on the device, nothing is copied per call.  Each figure
// is the median of --repeats runs after one untimed warm-up (the first call
// compiles kernels).  Points are uniform in the swarm's domain box
// (20 x 20 x 10 m by default), which is also the region of the domain walls
// and of the baked grid.
//
// Peer: libnoise's noise::module::Perlin::GetValue, one octave (a single
// Perlin value; libnoise's default is 6 octaves) at QUALITY_BEST (quintic
// fade, as Perlin 2002 and swarmcl), frequency 1/scale, on --threads
// std::threads.  A curl evaluation is 3 Perlin values AND their analytic
// gradients, so the ratio per Perlin evaluation is 3x the per-curl ratio.
//
//   noise_bench [--sizes 1000000,2000000,4000000] [--repeats 5] [--quick]
//               [--agents 1000000] [--steps 10] [--radius 0.1] [--threads 2]
//               [--device SELECTOR] [--json PATH] [--seed S] [--density AGENTS_PER_M3]
// --density keeps the density of the field model's swarm fixed as --agents grows
// (the box grows, 2:2:1); without it the box is fixed (issue 29).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <noise.h>

#include "bench_util.hpp"
#include "roofline.hpp"
#include "device/buffer.hpp"
#include "device/context.hpp"
#include "fields/noise_field.hpp"
#include "models/field_model.hpp"
#include "swarm/min_distance.hpp"
#include "swarm/swarm.hpp"

#ifndef SWARMCL_BENCH_RESULTS_DIR
#define SWARMCL_BENCH_RESULTS_DIR "bench/results"
#endif

namespace {

using namespace swarmcl::bench;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }


// ---- options -------------------------------------------------------------------

struct Options {
    std::vector<uint32_t> sizes{1000000, 2000000, 4000000};
    int repeats = 5;
    uint32_t agents = 1000000;
    int steps = 10;
    int threads = 2;
    bool quick = false;
    std::string device;
    std::string json = std::string(SWARMCL_BENCH_RESULTS_DIR) + "/noise.json";
    uint64_t seed = 12345;
    // The aggregation scenario (curl-noise paper, Table 1) in a 20 x 20 x 10 m box.
    std::array<float, 3> lo{0.0f, 0.0f, 0.0f}, hi{20.0f, 20.0f, 10.0f};
    float scale = 0.4f, gain = 0.25f, s0 = 1.5f, d0 = 0.4f, min_distance = 0.05f, radius = 0.1f;
    float time_scale = 1.0f;
    uint32_t bake = 64;
    // --density D (agents per m^3, issue 29): the box keeps its 2:2:1 shape
    // and grows with --agents so the density stays D (0: the fixed box, whose
    // density rises with N).
    double density = 0.0;
};

[[noreturn]] void usage(const char* msg) {
    std::fprintf(stderr,
                 "%s\nusage: noise_bench [--sizes 1000000,2000000,4000000] [--repeats 5] [--quick]\n"
                 "                   [--agents 1000000] [--steps 10] [--threads 2] [--device SELECTOR]\n"
                 "                   [--json PATH] [--seed S] [--bake 64] [--density AGENTS_PER_M3]\n"
                 "  --quick: sizes 1000000, 3 repeats, 5 steps\n",
                 msg);
    std::exit(2);
}

Options parse(int argc, char** argv) {
    Options o;
    bool sizes_set = false, repeats_set = false, steps_set = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "-h" || a == "--help") usage("Curl noise and the field model vs libnoise Perlin.");
        if (a == "--quick") {
            o.quick = true;
            continue;
        }
        if (i + 1 >= argc) usage(("missing value for " + a).c_str());
        const std::string v = argv[++i];
        try {
            if (a == "--sizes") {
                o.sizes.clear();
                std::stringstream ss(v);
                std::string item;
                while (std::getline(ss, item, ',')) {
                    const double n = std::stod(item);  // accepts 1e6
                    if (!(n >= 1 && n <= 1.0e9)) usage(("bad size " + item).c_str());
                    o.sizes.push_back(uint32_t(n));
                }
                if (o.sizes.empty()) usage("--sizes is empty");
                sizes_set = true;
            } else if (a == "--repeats") {
                o.repeats = std::stoi(v);
                if (o.repeats < 1) usage("--repeats must be >= 1");
                repeats_set = true;
            } else if (a == "--agents") {
                const double n = std::stod(v);
                if (!(n >= 0 && n <= 1.0e9)) usage("--agents must be in [0, 1e9] (0: skip the field model)");
                o.agents = uint32_t(n);
            } else if (a == "--steps") {
                o.steps = std::stoi(v);
                if (o.steps < 1) usage("--steps must be >= 1");
                steps_set = true;
            } else if (a == "--radius") {
                o.radius = std::stof(v);
                if (!(o.radius > 0.0f)) usage("--radius must be > 0");
            } else if (a == "--bake") {
                const int b = std::stoi(v);
                if (b < 2 || b > 512) usage("--bake must be in [2, 512]");
                o.bake = uint32_t(b);
            } else if (a == "--threads") {
                o.threads = std::stoi(v);
                if (o.threads < 1) usage("--threads must be >= 1");
            } else if (a == "--device") {
                o.device = v;
            } else if (a == "--json") {
                o.json = v;
            } else if (a == "--seed") {
                o.seed = std::stoull(v);
            } else if (a == "--density") {
                o.density = std::stod(v);
                if (!(o.density > 0.0 && o.density < 1.0e9)) usage("--density must be in (0, 1e9) agents per m^3");
            } else {
                usage(("unknown option " + a).c_str());
            }
        } catch (const std::logic_error&) {
            usage(("bad value for " + a + ": " + v).c_str());
        }
    }
    if (o.density > 0.0 && o.agents > 0) {
        // 2s x 2s x s m holding agents / density m^3.
        const double side = std::cbrt(double(o.agents) / o.density / 4.0);
        o.lo = {0.0f, 0.0f, 0.0f};
        o.hi = {float(2.0 * side), float(2.0 * side), float(side)};
    }
    if (o.quick) {
        if (!sizes_set) o.sizes = {1000000};
        if (!repeats_set) o.repeats = 3;
        if (!steps_set) o.steps = 5;
    }
    return o;
}

// ---- output helpers ---------------------------------------------------------------


const char* verdict(bool ok) { return ok ? "met" : "NOT met"; }

// ---- results ----------------------------------------------------------------------

struct Row {
    std::string name;     // variant
    uint32_t n = 0;       // points
    double median_s = 0;  // seconds per pass over n points
    double min_s = 0;
    double rate() const { return median_s > 0 ? n / median_s : 0.0; }  // evaluations/s
};

struct StepRow {
    std::string name;
    double median_ms = 0, min_ms = 0;
};

struct Results {
    std::vector<Row> swarmcl, libnoise;
    double bake_ms = 0;
    uint32_t bake_nodes = 0;
    uint32_t agents = 0;
    uint32_t grid_dims[3] = {0, 0, 0};
    float grid_cell = 0;
    std::vector<StepRow> steps;
    uint32_t mde_moved_last = 0;
    double resident_bytes_per_agent = 0;  // the process's peak resident memory / agents
    double copy_gbs = 0;
    std::vector<swarmcl::bench::RooflineRow> roofline;

    const Row* find(const std::vector<Row>& v, const std::string& name, uint32_t n) const {
        for (const auto& r : v)
            if (r.name == name && r.n == n) return &r;
        return nullptr;
    }
    double step_ms(const std::string& name) const {
        for (const auto& s : steps)
            if (s.name == name) return s.median_ms;
        return 0.0;
    }
};

// ---- swarmcl noise on the device ---------------------------------------------------

struct Variant {
    std::string name;
    std::string what;
    swarmcl::NoiseConfig config;
    float time = 0.0f;
    bool cell_order = false;  // the points sorted by cell, as a swarm's agents are
};

swarmcl::NoiseConfig base_noise(const Options& o) {
    swarmcl::NoiseConfig c;
    c.type = swarmcl::NoiseType::Curl;
    c.scale = o.scale;
    c.gain = o.gain;
    c.seed = o.seed;
    c.boundary_distance = o.d0;
    c.region_min = o.lo;
    c.region_max = o.hi;
    return c;
}

std::vector<Variant> variants(const Options& o) {
    std::vector<Variant> v;
    auto c = base_noise(o);
    v.push_back({"curl", "procedural curl, static, no boundaries", c});
    c.domain_walls = true;
    v.push_back({"curl_walls", "procedural curl, static, domain walls (6 planes, boundary-aware Eq. 2-3)", c});
    c.domain_walls = false;
    c.time_scale = o.time_scale;
    v.push_back({"curl_timed", "procedural curl, time-varying (4D Perlin), no boundaries", c, 0.37f});
    c.domain_walls = true;
    v.push_back({"curl_timed_walls", "procedural curl, time-varying, domain walls", c, 0.37f});
    c = base_noise(o);
    c.type = swarmcl::NoiseType::Perlin;
    v.push_back({"perlin_vector", "Perlin vector noise (3 seeded Perlin values + gradients, no curl)", c});
    c = base_noise(o);
    c.domain_walls = true;
    c.baked = true;
    c.bake_resolution = {o.bake, o.bake, o.bake};
    v.push_back({"baked", "curl with domain walls baked on a " + std::to_string(o.bake) + "^3 grid, trilinear", c});
    v.push_back({"baked_cell_order",
                 "the same baked field at the same points sorted by bake cell (x fastest), the order a swarm's "
                 "agents are in after its grid sort",
                 c, 0.0f, true});
    return v;
}

// noise_sample over the first n device points, arguments set as NoiseField::sample sets them.
cl::Kernel sample_kernel(swarmcl::Context& ctx, swarmcl::NoiseField& field, const cl::Buffer& points,
                         const cl::Buffer& out, uint32_t n, float t) {
    (void)ctx;
    // Specialised for the field; on CPUs the explicit-width variant (NoiseField::width()).
    cl::Kernel k = field.kernel("noise_field.cl", field.width() > 1 ? "noise_sample_w" : "noise_sample");
    cl_uint i = 0;
    k.setArg(i++, points);
    k.setArg(i++, cl_uint(n));
    k.setArg(i++, t);
    k.setArg(i++, cl_uint(0));
    i = field.set_args(k, i);
    k.setArg(i, out);
    swarmcl::check_arg_count(k, i + 1);
    return k;
}

// One pass of n evaluations: enqueue + finish, seconds.
double time_kernel(swarmcl::Context& ctx, cl::Kernel& k, uint32_t n, uint32_t width = 1) {
    const auto t0 = Clock::now();
    swarmcl::launch(ctx, k, (size_t(n) + width - 1) / width);
    ctx.queue().finish();
    return seconds_since(t0);
}

// ---- libnoise --------------------------------------------------------------------

void parallel_for(uint32_t n, int threads, const std::function<void(uint32_t, uint32_t)>& body) {
    std::vector<std::thread> pool;
    const uint32_t chunk = (n + uint32_t(threads) - 1) / uint32_t(threads);
    for (int t = 0; t < threads; ++t) {
        const uint32_t b = std::min(n, uint32_t(t) * chunk), e = std::min(n, b + chunk);
        pool.emplace_back(body, b, e);
    }
    for (auto& th : pool) th.join();
}

// One pass of libnoise over n points on o.threads threads, seconds; each
// thread's sum is kept so that the calls cannot be optimised away.
double time_libnoise(const Options& o, const std::vector<float>& xyz, uint32_t n, double* checksum) {
    noise::module::Perlin perlin;
    perlin.SetOctaveCount(1);
    perlin.SetNoiseQuality(noise::QUALITY_BEST);
    perlin.SetFrequency(1.0 / o.scale);
    perlin.SetSeed(int(o.seed & 0x7fffffff));
    const uint32_t chunk = (n + uint32_t(o.threads) - 1) / uint32_t(o.threads);
    std::vector<double> sums(size_t(o.threads));
    const auto t0 = Clock::now();
    parallel_for(n, o.threads, [&](uint32_t b, uint32_t e) {
        double acc = 0;
        for (uint32_t i = b; i < e; ++i)
            acc += perlin.GetValue(xyz[3 * size_t(i)], xyz[3 * size_t(i) + 1], xyz[3 * size_t(i) + 2]);
        sums[b / chunk] = acc;
    });
    const double s = seconds_since(t0);
    *checksum = 0;
    for (double v : sums) *checksum += v;
    return s;
}

// ---- the field model at N agents ------------------------------------------------------

// VmHWM of /proc/self/status in bytes (0 where there is none).
uint64_t peak_resident_bytes() {
    std::ifstream f("/proc/self/status");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("VmHWM:", 0) == 0) return uint64_t(std::stoull(line.substr(6))) * 1024u;
    return 0;
}

swarmcl::FieldModelConfig model_config(const Options& o, bool baked) {
    swarmcl::FieldModelConfig m;
    m.noise = base_noise(o);
    m.noise.domain_walls = true;
    m.noise.baked = baked;
    m.noise.bake_resolution = {o.bake, o.bake, o.bake};
    m.has_goal = true;
    m.goal = {0.5f * (o.lo[0] + o.hi[0]), 0.5f * (o.lo[1] + o.hi[1]), 0.5f * (o.lo[2] + o.hi[2])};
    m.goal_radius = 0.5f;
    m.goal_speed = o.s0;
    m.min_distance = o.min_distance;
    return m;
}

void run_field_model(const Options& o, const std::shared_ptr<swarmcl::Context>& ctx, Results& res) {
    const uint32_t n = o.agents;
    swarmcl::SwarmConfig cfg;
    cfg.capacity = n;
    cfg.agent_count = n;
    cfg.seed = o.seed;
    cfg.domain_min = o.lo;
    cfg.domain_max = o.hi;
    cfg.interaction_radius = o.radius;
    swarmcl::Swarm swarm(ctx, cfg);
    auto& q = ctx->queue();
    const auto& geom = swarm.grid().geometry();
    res.agents = n;
    for (int a = 0; a < 3; ++a) res.grid_dims[a] = uint32_t(geom.dims[a]);
    res.grid_cell = geom.cell;
    const double vol = double(o.hi[0] - o.lo[0]) * (o.hi[1] - o.lo[1]) * (o.hi[2] - o.lo[2]);
    std::printf("\n== field model: %u agents in %gx%gx%g m (%.1f agents/m^3, mean spacing %.3f m), dt %.4g s\n", n,
                double(o.hi[0] - o.lo[0]), double(o.hi[1] - o.lo[1]), double(o.hi[2] - o.lo[2]), n / vol,
                std::cbrt(vol / n), double(cfg.dt));
    std::printf("   noise scale %g, gain %g, d0 %g, domain walls; goal at the centre, s0 %g, goal radius 0.5; "
                "min_distance %g; interaction radius %g -> grid %ux%ux%u cells of %.4g m\n",
                double(o.scale), double(o.gain), double(o.d0), double(o.s0), double(o.min_distance),
                double(o.radius), res.grid_dims[0], res.grid_dims[1], res.grid_dims[2], double(geom.cell));
    const std::string header = "stage (median of " + std::to_string(o.steps) + " after 3 warm-up)";
    std::printf("   %-52s %10s %10s\n", header.c_str(), "median ms", "min ms");
    auto add = [&](const std::string& name, const std::vector<double>& s) {
        StepRow r{name, median(s) * 1e3, minimum(s) * 1e3};
        res.steps.push_back(r);
        std::printf("   %-52s %10.2f %10.2f\n", name.c_str(), r.median_ms, r.min_ms);
        std::fflush(stdout);
    };
    // Four models on one swarm: procedural / baked, with and without MDE
    // (without: the advance kernel alone).  Every round times each stage
    // once, so load changes hit all stages alike.
    std::vector<std::shared_ptr<swarmcl::FieldModel>> full, advance;
    for (int baked = 0; baked < 2; ++baked) {
        const auto t0 = Clock::now();
        full.push_back(std::make_shared<swarmcl::FieldModel>(swarm, model_config(o, baked != 0)));
        q.finish();
        if (baked) add("baked/FieldModel construction (bake " + std::to_string(o.bake) + "^3)", {seconds_since(t0)});
        auto c = model_config(o, baked != 0);
        c.min_distance = 0.0f;
        advance.push_back(std::make_shared<swarmcl::FieldModel>(swarm, c));
    }
    swarmcl::MinDistance mde(*ctx, o.min_distance, o.seed);
    swarmcl::DeviceBuffer<cl_uint> moved(*ctx, 2, "moved");
    moved.fill(*ctx, 0u, 2);
    const char* names[6] = {"procedural/full step (advance + grid rebuild + MDE)",
                            "procedural/advance kernel (noise + goal + Euler)",
                            "baked/full step (advance + grid rebuild + MDE)",
                            "baked/advance kernel (noise + goal + Euler)",
                            "grid rebuild (build + reorder pos/vel/ids)",
                            "MDE kernel (grid current)"};
    std::vector<std::vector<double>> t(6);
    for (int k = 0; k < 3 + o.steps; ++k) {  // 3 warm-up rounds
        for (int stage = 0; stage < 6; ++stage) {
            if (stage < 4) swarm.set_behavior(stage % 2 ? advance[size_t(stage / 2)] : full[size_t(stage / 2)]);
            if (stage == 5) {  // MDE alone: the grid must be current before the clock starts
                swarm.positions_changed();
                swarm.ensure_grid();
                q.finish();
            }
            const auto t0 = Clock::now();
            if (stage < 4) {
                swarm.step(1);
            } else if (stage == 4) {
                swarm.positions_changed();
                swarm.ensure_grid();
            } else {
                mde.apply(swarm, moved);
            }
            q.finish();
            if (k >= 3) t[size_t(stage)].push_back(seconds_since(t0));
            // The swarm's statistics are the model's since set_behavior.
            if (stage == 2 && k == 2 + o.steps) res.mde_moved_last = swarm.take_step_stats()->mde_moved_last;
        }
    }
    for (int stage = 0; stage < 6; ++stage) add(names[stage], t[size_t(stage)]);
    std::printf("   (swarm has %u agents after %llu steps)\n", swarm.agent_count(), (unsigned long long)swarm.step_count());
    // Memory per agent (issue 29): on a CPU device the device's buffers are
    // the process's memory, so its peak resident size over N bounds them
    // (the noise sampling's point arrays before this count too).
    res.resident_bytes_per_agent = n ? double(peak_resident_bytes()) / n : 0.0;
    std::printf("   peak resident memory %.0f MB: %.0f bytes per agent\n", peak_resident_bytes() / 1e6,
                res.resident_bytes_per_agent);
    // The roofline (issue 29): the bytes each stage must move at the least
    // per agent, against a copy kernel's bandwidth on n float4 now.  The
    // advance reads a position and writes a position and a velocity (48 B);
    // the grid rebuild reads the positions for the keys and permutes
    // positions, velocities and ids (16 + 2 x 36 B, the sort's own passes
    // not counted); MDE reads a position and writes one (32 B; neighbours
    // come from cache).
    res.copy_gbs = swarmcl::bench::copy_bandwidth_gbs(*ctx, n);
    const double bytes[6] = {48 + 88 + 32, 48, 48 + 88 + 32, 48, 88, 32};
    for (int stage = 0; stage < 6; ++stage)
        res.roofline.push_back(swarmcl::bench::roofline_row(names[stage], bytes[stage], n,
                                                            median(t[size_t(stage)]) * 1e3, res.copy_gbs));
    swarmcl::bench::print_roofline(res.roofline, res.copy_gbs);
}

// ---- JSON ---------------------------------------------------------------------------

void write_json(const Options& o, const swarmcl::DeviceEntry& dev, const Results& r, double load_before,
                double load_after) {
    std::ostringstream j;
    j.precision(8);
    j << "{\n  \"benchmark\": \"noise\",\n  \"timestamp\": \"" << utc_now() << "\",\n";
    j << "  \"device\": {\"name\": \"" << json_escape(dev.device_name) << "\", \"platform\": \""
      << json_escape(dev.platform_name) << "\", \"version\": \"" << json_escape(dev.version)
      << "\", \"compute_units\": " << dev.compute_units << "},\n";
    j << "  \"host_threads\": " << std::thread::hardware_concurrency() << ",\n";
    j << "  \"load_average_1min\": {\"before\": " << load_before << ", \"after\": " << load_after << "},\n";
    j << "  \"peer\": {\"name\": \"libnoise\", \"module\": \"noise::module::Perlin::GetValue\", \"octaves\": 1, "
         "\"quality\": \"QUALITY_BEST\", \"threads\": "
      << o.threads << "},\n";
    j << "  \"parameters\": {\"region_min\": [" << o.lo[0] << ", " << o.lo[1] << ", " << o.lo[2]
      << "], \"region_max\": [" << o.hi[0] << ", " << o.hi[1] << ", " << o.hi[2] << "], \"scale\": " << o.scale
      << ", \"gain\": " << o.gain << ", \"d0\": " << o.d0 << ", \"time_scale\": " << o.time_scale
      << ", \"bake_resolution\": " << o.bake << ", \"points\": \"uniform in the region\", \"repeats\": " << o.repeats
      << ", \"statistic\": \"median\", \"timing\": \"enqueue + finish, data resident on the device\", \"seed\": "
      << o.seed << "},\n";
    auto rows = [&](const char* key, const std::vector<Row>& v) {
        j << "  \"" << key << "\": [\n";
        for (size_t i = 0; i < v.size(); ++i)
            j << "    {\"variant\": \"" << v[i].name << "\", \"n\": " << v[i].n << ", \"median_ms\": "
              << v[i].median_s * 1e3 << ", \"min_ms\": " << v[i].min_s * 1e3
              << ", \"mevals_per_s\": " << v[i].rate() * 1e-6 << "}" << (i + 1 < v.size() ? "," : "") << "\n";
        j << "  ],\n";
    };
    rows("swarmcl", r.swarmcl);
    rows("libnoise", r.libnoise);
    j << "  \"ratios\": [\n";
    bool first = true;
    for (uint32_t n : o.sizes) {
        const Row* peer = r.find(r.libnoise, "perlin_1octave", n);
        if (!peer) continue;
        for (const auto& s : r.swarmcl) {
            if (s.n != n) continue;
            const double per = s.rate() / peer->rate();
            const bool curl = s.name.rfind("curl", 0) == 0;  // baked: a trilinear read, no Perlin
            j << (first ? "" : ",\n") << "    {\"n\": " << n << ", \"variant\": \"" << s.name
              << "\", \"swarmcl_evals_over_libnoise_perlin\": " << per;
            if (curl || s.name == "perlin_vector") j << ", \"per_perlin_evaluation\": " << 3.0 * per;
            j << "}";
            first = false;
        }
    }
    j << "\n  ],\n";
    j << "  \"bake\": {\"resolution\": " << o.bake << ", \"nodes\": " << r.bake_nodes << ", \"ms\": " << r.bake_ms
      << "},\n";
    j << "  \"field_model\": {\"agents\": " << r.agents << ", \"grid_dims\": [" << r.grid_dims[0] << ", "
      << r.grid_dims[1] << ", " << r.grid_dims[2] << "], \"grid_cell\": " << r.grid_cell
      << ", \"min_distance\": " << o.min_distance << ", \"interaction_radius\": " << o.radius
      << ", \"steps_timed\": " << o.steps << ", \"mde_moved_last_step\": " << r.mde_moved_last
      << ", \"domain\": [" << o.hi[0] - o.lo[0] << ", " << o.hi[1] - o.lo[1] << ", " << o.hi[2] - o.lo[2]
      << "], \"density_per_m3\": " << (r.agents / (double(o.hi[0] - o.lo[0]) * (o.hi[1] - o.lo[1]) * (o.hi[2] - o.lo[2])))
      << ", \"peak_resident_bytes_per_agent\": " << r.resident_bytes_per_agent
      << ", \"median_ms\": {";
    for (size_t i = 0; i < r.steps.size(); ++i)
        j << (i ? ", " : "") << "\"" << json_escape(r.steps[i].name) << "\": " << r.steps[i].median_ms;
    j << "}, \"roofline\": " << swarmcl::bench::roofline_json(r.roofline, r.copy_gbs) << "},\n";
    // Targets.
    const uint32_t n0 = o.sizes.front();
    const Row* walls = r.find(r.swarmcl, "curl_walls", n0);
    const Row* plain = r.find(r.swarmcl, "curl", n0);
    const Row* baked = r.find(r.swarmcl, "baked", n0);
    const Row* baked_sorted = r.find(r.swarmcl, "baked_cell_order", n0);
    const double proc = r.step_ms("procedural/full step (advance + grid rebuild + MDE)");
    const double bstep = r.step_ms("baked/full step (advance + grid rebuild + MDE)");
    j << "  \"targets\": {\"curl_mevals_per_s_ge_40\": {\"n\": " << n0 << ", \"no_boundaries\": "
      << (plain ? plain->rate() * 1e-6 : 0) << ", \"domain_walls\": " << (walls ? walls->rate() * 1e-6 : 0)
      << "}, \"baked_msamples_per_s_ge_200\": {\"random_order\": " << (baked ? baked->rate() * 1e-6 : 0)
      << ", \"cell_order\": " << (baked_sorted ? baked_sorted->rate() * 1e-6 : 0) << "}"
      << ", \"field_model_ms_per_step_le_50\": {\"agents\": " << r.agents << ", \"procedural\": " << proc
      << ", \"baked\": " << bstep << "}}\n}\n";
    std::ofstream f(o.json);
    if (!f) {
        std::fprintf(stderr, "cannot write %s\n", o.json.c_str());
        return;
    }
    f << j.str();
    std::printf("wrote %s\n", o.json.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    try {
        auto ctx = std::make_shared<swarmcl::Context>(o.device, "");
        const auto& dev = ctx->device();
        std::printf("noise_bench: swarmcl curl noise and field model vs libnoise Perlin\n");
        std::printf("device: %s (%s; %s; %u compute units)\n", dev.device_name.c_str(), dev.platform_name.c_str(),
                    dev.version.c_str(), dev.compute_units);
        std::printf("peer: libnoise noise::module::Perlin::GetValue, 1 octave, QUALITY_BEST, on %d std::threads; "
                    "host has %u hardware threads\n",
                    o.threads, std::thread::hardware_concurrency());
        std::printf("parameters: region [%g,%g]x[%g,%g]x[%g,%g] m, scale %g, gain %g, d0 %g, time_scale %g, "
                    "seed %llu; points uniform in the region; median of %d repeats after 1 warm-up; device "
                    "timings are enqueue + finish with data resident on the device\n",
                    double(o.lo[0]), double(o.hi[0]), double(o.lo[1]), double(o.hi[1]), double(o.lo[2]),
                    double(o.hi[2]), double(o.scale), double(o.gain), double(o.d0), double(o.time_scale),
                    (unsigned long long)o.seed, o.repeats);
        const double load_before = load_average();
        std::printf("host load average (1 min) before: %.2f\n", load_before);
        std::fflush(stdout);

        Results res;
        const uint32_t nmax = *std::max_element(o.sizes.begin(), o.sizes.end());
        std::vector<float> xyz(size_t(nmax) * 3);
        std::vector<cl_float4> p4(nmax);
        {
            std::mt19937_64 rng(o.seed);
            std::uniform_real_distribution<float> u(0.0f, 1.0f);
            for (uint32_t i = 0; i < nmax; ++i)
                for (int a = 0; a < 3; ++a) {
                    const float v = o.lo[a] + u(rng) * (o.hi[a] - o.lo[a]);
                    xyz[3 * size_t(i) + a] = v;
                    p4[i].s[a] = v;
                }
        }
        swarmcl::DeviceBuffer<cl_float4> points(*ctx, nmax, "points"), out(*ctx, nmax, "samples");
        points.upload(*ctx, p4.data(), nmax);
        // The first n points of each size sorted by bake cell, for baked_cell_order.
        std::vector<swarmcl::DeviceBuffer<cl_float4>> sorted_points;
        for (uint32_t n : o.sizes) {
            std::vector<cl_float4> q(p4.begin(), p4.begin() + n);
            auto cell = [&](const cl_float4& x) {
                uint32_t c = 0;
                for (int a = 2; a >= 0; --a) {
                    const float u = (x.s[a] - o.lo[a]) / (o.hi[a] - o.lo[a]) * float(o.bake - 1);
                    c = c * uint32_t(o.bake) + std::min(uint32_t(o.bake - 1), uint32_t(std::max(0.0f, u)));
                }
                return c;
            };
            std::stable_sort(q.begin(), q.end(), [&](const cl_float4& a, const cl_float4& b) { return cell(a) < cell(b); });
            sorted_points.emplace_back(*ctx, n, "sorted points");
            sorted_points.back().upload(*ctx, q.data(), n);
        }

        // ---- swarmcl noise and libnoise, interleaved ----
        // Every round runs each variant once and then libnoise once, so a
        // change in machine load hits all of them alike (ratios stay fair).
        std::printf("\n== swarmcl noise evaluations (kernel noise_sample, points and output on the device)\n");
        const auto vars = variants(o);
        for (const auto& v : vars) std::printf("   %-18s %s\n", v.name.c_str(), v.what.c_str());
        std::printf("   peer: perlin_1octave = libnoise Perlin::GetValue on the same points, %d threads\n", o.threads);
        std::vector<std::unique_ptr<swarmcl::NoiseField>> fields;
        for (const auto& v : vars) {
            if (v.config.baked) {  // the bake kernel compiles on the first field: time a second one
                swarmcl::NoiseField warm(*ctx, v.config);
                const auto t0 = Clock::now();
                fields.push_back(std::make_unique<swarmcl::NoiseField>(*ctx, v.config));
                res.bake_ms = seconds_since(t0) * 1e3;
                res.bake_nodes = o.bake * o.bake * o.bake;
            } else {
                fields.push_back(std::make_unique<swarmcl::NoiseField>(*ctx, v.config));
            }
        }
        std::printf("   bake of %u^3 = %u nodes (procedural curl with walls): %.2f ms (%.1f M nodes/s)\n", o.bake,
                    res.bake_nodes, res.bake_ms, res.bake_nodes / res.bake_ms * 1e-3);
        std::printf("\n   %-18s %10s %10s %10s %12s\n", "variant", "N", "median ms", "min ms", "M evals/s");
        for (size_t si = 0; si < o.sizes.size(); ++si) {
            const uint32_t n = o.sizes[si];
            std::vector<cl::Kernel> kernels;
            for (size_t v = 0; v < vars.size(); ++v)
                kernels.push_back(sample_kernel(*ctx, *fields[v],
                                                vars[v].cell_order ? sorted_points[si].get() : points.get(),
                                                out.get(), n, vars[v].time));
            std::vector<std::vector<double>> t(vars.size());
            std::vector<double> tl;
            double checksum = 0;
            for (int r = 0; r <= o.repeats; ++r) {  // r == 0: warm-up
                for (size_t v = 0; v < vars.size(); ++v) {
                    const double s = time_kernel(*ctx, kernels[v], n, fields[v]->width());
                    if (r) t[v].push_back(s);
                }
                const double s = time_libnoise(o, xyz, n, &checksum);
                if (r) tl.push_back(s);
            }
            for (size_t v = 0; v < vars.size(); ++v) {
                Row row{vars[v].name, n, median(t[v]), minimum(t[v])};
                res.swarmcl.push_back(row);
                std::printf("   %-18s %10u %10.2f %10.2f %12.1f\n", row.name.c_str(), n, row.median_s * 1e3,
                            row.min_s * 1e3, row.rate() * 1e-6);
            }
            Row row{"perlin_1octave", n, median(tl), minimum(tl)};
            res.libnoise.push_back(row);
            std::printf("   %-18s %10u %10.2f %10.2f %12.1f   (libnoise; checksum %.3f)\n", row.name.c_str(), n,
                        row.median_s * 1e3, row.min_s * 1e3, row.rate() * 1e-6, checksum);
            std::fflush(stdout);
        }

        // ---- ratios ----
        std::printf("\n== ratios swarmcl / libnoise (evaluations per second; per Perlin = x3 for curl and "
                    "Perlin vector: 3 Perlin values + gradients per evaluation)\n");
        std::printf("   %-18s %10s %14s %14s\n", "variant", "N", "per eval", "per Perlin");
        for (uint32_t n : o.sizes) {
            const Row* peer = res.find(res.libnoise, "perlin_1octave", n);
            for (const auto& s : res.swarmcl)
                if (s.n == n && peer)
                    std::printf("   %-18s %10u %13.2fx %13.2fx\n", s.name.c_str(), n, s.rate() / peer->rate(),
                                s.name.rfind("baked", 0) == 0 ? 0.0 : 3.0 * s.rate() / peer->rate());
        }
        std::printf("   (baked: a trilinear read, not a Perlin evaluation; its per-Perlin column is left 0)\n");

        // ---- field model ----
        if (o.agents) run_field_model(o, ctx, res);

        const double load_after = load_average();
        std::printf("\nhost load average (1 min) after: %.2f\n", load_after);

        // ---- targets ----
        const uint32_t n0 = o.sizes.front();
        std::printf("\n== targets (N = %u)\n", n0);
        for (const char* name : {"curl", "curl_walls", "curl_timed", "curl_timed_walls"}) {
            const Row* r = res.find(res.swarmcl, name, n0);
            if (r)
                std::printf("   %-18s >= 40 M curl evals/s: %8.1f -> %s\n", name, r->rate() * 1e-6,
                            verdict(r->rate() >= 40e6));
        }
        for (const char* name : {"baked", "baked_cell_order"})
            if (const Row* r = res.find(res.swarmcl, name, n0))
                std::printf("   %-18s >= 200 M samples/s:   %8.1f -> %s\n", name, r->rate() * 1e-6,
                            verdict(r->rate() >= 200e6));
        if (o.agents) {
            for (const char* tag : {"procedural", "baked"}) {
                const double ms = res.step_ms(std::string(tag) + "/full step (advance + grid rebuild + MDE)");
                std::printf("   field model %-10s %u agents <= 50 ms/step: %8.2f ms -> %s\n", tag, o.agents, ms,
                            o.agents >= 1000000 ? verdict(ms <= 50.0) : "(target is at 1M agents)");
            }
        }
        write_json(o, dev, res, load_before, load_after);
        return 0;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "noise_bench: %s\n", e.what());
        return 1;
    }
}
