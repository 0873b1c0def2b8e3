// Two kernel sources in one process: a stage is built four times, twice
// from each directory (old, new, new, old; $SWARMCL_KERNEL_DIR for each
// build, a context each), and its launches alternate forwards then
// backwards, so both sources see the same machine at the same moment.  On a
// shared 2-core machine whose speed swings by 2x over minutes, runs
// alternated between processes could not show a 5% change; the ratio of
// each round here can (docs/benchmarks.md, "Masks from one compare").  Also
// checks the four results are bitwise the same.
//
//   kernel_ab --stage mde|noise|neighbors|energy|policy --old DIR --new DIR [--old-width W] [--new-width W]
//             [--old-cell M] [--new-cell M] [--agents N] [--reps R] [--json PATH]
//
// --old-width / --new-width: the explicit-width kernels' lanes (1, 8 or 16;
// set_kernel_width_override) for that side, to compare widths with one
// source; --old-cell / --new-cell: the energy stage's grid cell (m, 0.2 by
// default) for that side, to compare cells with one source.  The kernel folder goes through the environment
// ($SWARMCL_KERNEL_DIR), set from this thread between builds, while the
// earlier contexts' PoCL threads wait idle; it stays set to the last folder.
//
// mde: one minimum distance pass (min_distance.cl) over N agents spread
// uniformly in noise_bench's field-model domain (20 x 20 x 10 m, grid cells
// of 0.1 m, d_min 0.05 m: 0.25 agents a cell); each pass moves the agents,
// the same on both sides.  noise: the curl noise with domain walls sampled at
// N random points (noise_sample_w on CPU devices).  neighbors: every agent
// counts its neighbours within r as in neighbor_grid_bench (see
// make_neighbors).  energy: one step of the FASTSWARM energy model in
// energy_bench's scene (bench/energy_scene.hpp; --agents 100000 for its
// issue 29 row), each side its own swarm stepped as often as the others.
// policy: the policy model's observations in policy_bench's scene (see
// make_policy).
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "energy_scene.hpp"
#include "policy_scene.hpp"
#include "rl/policy_weights.hpp"
#include "device/context.hpp"
#include "fields/noise_field.hpp"
#include "swarm/min_distance.hpp"
#include "swarm/swarm.hpp"

using namespace swarmcl;
using namespace swarmcl::bench;

namespace {

struct Options {
    std::string stage, old_dir, new_dir, json;
    uint32_t widths[2] = {0, 0};  // each side's explicit-width kernels' lanes (0: the device's)
    float cells[2] = {0.2f, 0.2f};  // each side's grid cell in the energy stage (m)
    uint32_t agents = 1000000;
    int reps = 20;
};

[[noreturn]] void usage(const std::string& why) {
    std::fprintf(stderr,
                 "kernel_ab: %s\nusage: kernel_ab --stage mde|noise|neighbors|energy|policy --old DIR --new DIR [--old-width W] [--new-width W] "
                 "[--old-cell M] [--new-cell M] [--agents N] [--reps R] [--json PATH]\n",
                 why.c_str());
    std::exit(2);
}

// One side: the stage built from one kernel directory; run() launches it
// once and waits, result() reads what it wrote back.
struct Side {
    std::shared_ptr<Context> ctx;
    std::function<void()> run;
    std::function<std::vector<uint8_t>()> result;  // what the stage wrote, as bytes
};

template <typename T>
std::vector<uint8_t> as_bytes(const std::vector<T>& v) {
    std::vector<uint8_t> b(v.size() * sizeof(T));
    std::memcpy(b.data(), v.data(), b.size());
    return b;
}

const std::array<float, 3> kLo = {-10.0f, -10.0f, -5.0f}, kHi = {10.0f, 10.0f, 5.0f};

std::vector<cl_float4> uniform_points(uint32_t n) {
    std::vector<cl_float4> p(n);
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (auto& q : p)
        q = {{kLo[0] + (kHi[0] - kLo[0]) * u(rng), kLo[1] + (kHi[1] - kLo[1]) * u(rng),
              kLo[2] + (kHi[2] - kLo[2]) * u(rng), 0.0f}};
    return p;
}

void make_mde(Side& s, const std::vector<cl_float4>& pts) {
    const uint32_t n = uint32_t(pts.size());
    SwarmConfig c;
    c.capacity = n;
    c.domain_min = kLo;
    c.domain_max = kHi;
    c.interaction_radius = 0.1f;
    auto swarm = std::make_shared<Swarm>(s.ctx, c);
    std::vector<float> xyz(3 * size_t(n));
    for (uint32_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) xyz[3 * size_t(i) + a] = pts[i].s[a];
    swarm->write(Attribute::Position, xyz.data(), n);
    auto mde = std::make_shared<MinDistance>(*s.ctx, 0.05f, 99);
    auto moved = std::make_shared<DeviceBuffer<cl_uint>>(*s.ctx, 2, "moved");
    moved->fill(*s.ctx, 0u, 2);
    swarm->ensure_grid();
    auto ctx = s.ctx;
    s.run = [=] {
        mde->apply(*swarm, *moved);
        ctx->queue().finish();
    };
    s.result = [=] {
        std::vector<cl_float4> out(n);
        swarm->positions().download(*ctx, out.data(), n);
        return as_bytes(out);
    };
}

// neighbor_grid_bench's pass: N agents uniform in a cube sized for 30
// neighbours within r = 1 on average, each counting its neighbours
// (Swarm::neighbor_count: the count kernel and the download of the counts).
void make_neighbors(Side& s, uint32_t n) {
    const float r = 1.0f;
    const float edge = float(std::cbrt(n * (4.0 / 3.0 * 3.14159265358979 * r * r * r) / 30.0));
    SwarmConfig c;
    c.capacity = n;
    c.domain_min = {0.0f, 0.0f, 0.0f};
    c.domain_max = {edge, edge, edge};
    c.interaction_radius = r;
    auto swarm = std::make_shared<Swarm>(s.ctx, c);
    std::vector<float> xyz(3 * size_t(n));
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(0.0f, edge);
    for (auto& x : xyz) x = u(rng);
    swarm->write(Attribute::Position, xyz.data(), n);
    auto counts = std::make_shared<std::vector<uint32_t>>(n);
    s.run = [=] { swarm->neighbor_count(r, counts->data(), n); };
    s.result = [=] { return as_bytes(*counts); };
}

void make_noise(Side& s, const std::vector<cl_float4>& pts) {
    const uint32_t n = uint32_t(pts.size());
    NoiseConfig c;
    c.type = NoiseType::Curl;
    c.scale = 0.4f;
    c.gain = 0.25f;
    c.boundary_distance = 0.4f;
    c.region_min = kLo;
    c.region_max = kHi;
    c.domain_walls = true;
    auto field = std::make_shared<NoiseField>(*s.ctx, c);
    auto kernel = std::make_shared<cl::Kernel>(field->sample_kernel());
    auto in = std::make_shared<DeviceBuffer<cl_float4>>(*s.ctx, n, "points");
    auto out = std::make_shared<DeviceBuffer<cl_float4>>(*s.ctx, n, "samples");
    in->upload(*s.ctx, pts.data(), n);
    auto ctx = s.ctx;
    s.run = [=] {
        field->enqueue_sample(*kernel, *in, n, 0.0f, 0, *out);
        ctx->queue().finish();
    };
    s.result = [=] {
        std::vector<cl_float4> r(n);
        out->download(*ctx, r.data(), n);
        return as_bytes(r);
    };
}

// The policy model's observations (policy_observe_w on CPU devices) in
// policy_bench's scene (bench/policy_scene.hpp; --agents 100000 for its
// issue 29 row), each side its own swarm in the same state; the result is
// the observations read back.
void make_policy(Side& s, uint32_t n, const std::shared_ptr<const std::string>& weights) {
    auto swarm = policy_random_swarm(s.ctx, n, kPolicyCell);
    auto model = policy_model_on(*swarm, weights);
    s.run = [=] { model->observe_on_device(*swarm); };  // waits for the device
    s.result = [=] {
        std::vector<float> obs, actions;
        model->observe(*swarm, &obs, &actions);
        return as_bytes(obs);
    };
}

void make_energy(Side& s, uint32_t n, float cell, const std::shared_ptr<const Dataset>& data) {
    auto swarm = energy_ball_swarm(s.ctx, n, cell);
    swarm->set_behavior(std::make_shared<EnergyModel>(*swarm, energy_aggregation_config(false), data));
    auto ctx = s.ctx;
    s.run = [=] {
        swarm->step(1);
        ctx->queue().finish();
    };
    s.result = [=] {
        std::vector<float> p(3 * size_t(n));
        swarm->read(Attribute::Position, p.data(), n);
        return as_bytes(p);
    };
}

std::string cpu_model() {
    std::ifstream f("/proc/cpuinfo");
    std::string line;
    while (std::getline(f, line))
        if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
    return "unknown";
}

}  // namespace

int run(const Options& o);

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc) usage(a + " needs a value");
        const std::string v = argv[++i];
        if (a == "--stage") o.stage = v;
        else if (a == "--old") o.old_dir = v;
        else if (a == "--new") o.new_dir = v;
        else if (a == "--json") o.json = v;
        else if (a == "--old-width") o.widths[0] = uint32_t(std::strtoul(v.c_str(), nullptr, 10));
        else if (a == "--new-width") o.widths[1] = uint32_t(std::strtoul(v.c_str(), nullptr, 10));
        else if (a == "--old-cell") o.cells[0] = std::strtof(v.c_str(), nullptr);
        else if (a == "--new-cell") o.cells[1] = std::strtof(v.c_str(), nullptr);
        else if (a == "--agents") o.agents = uint32_t(std::strtoul(v.c_str(), nullptr, 10));
        else if (a == "--reps") o.reps = std::atoi(v.c_str());
        else usage("unknown option " + a);
    }
    if (o.stage != "mde" && o.stage != "noise" && o.stage != "neighbors" && o.stage != "energy" &&
        o.stage != "policy")
        usage("--stage must be mde, noise, neighbors, energy or policy");
    if (o.old_dir.empty() || o.new_dir.empty()) usage("--old and --new name kernel directories");
    if (o.agents == 0 || o.reps < 2) usage("--agents must be > 0 and --reps >= 2");
    for (const float c : o.cells)
        if (!(c > 0.0f && c < 10.0f)) usage("--old-cell and --new-cell must be in (0, 10) m");
    for (const uint32_t w : o.widths)
        if (w != 0 && w != 1 && w != 8 && w != 16) usage("--old-width and --new-width must be 1, 8 or 16");
    try {
        return run(o);
    } catch (const std::exception& e) {  // a kernel directory without the files, no device, ...
        std::fprintf(stderr, "kernel_ab: %s\n", e.what());
        return 2;
    }
}

int run(const Options& o) {
    const double load_before = load_average();
    const auto pts = o.stage == "mde" || o.stage == "noise" ? uniform_points(o.agents) : std::vector<cl_float4>();
    const auto data = o.stage == "energy" ? std::make_shared<const Dataset>(synthetic_dataset(DatasetOptions()))
                                          : std::shared_ptr<const Dataset>();
    const auto weights = o.stage == "policy" ? std::make_shared<const std::string>(read_policy_file(
                                                   std::string(SWARMCL_SOURCE_DIR) + "/models/policy_roaming.safetensors"))
                                             : std::shared_ptr<const std::string>();
    // Four builds: old, new, new, old.  Which build a context is (its place
    // in memory, the order of creation) moved a null test (old against a
    // copy of old) by up to 4%; with each source in the first and last
    // place alike, the null test reads 1.00.
    Side side[4];
    const std::string dirs[2] = {o.old_dir, o.new_dir};
    const int source[4] = {0, 1, 1, 0};
    for (int k = 0; k < 4; ++k) {
        setenv("SWARMCL_KERNEL_DIR", dirs[source[k]].c_str(), 1);  // read when each program is built
        set_kernel_width_override(o.widths[source[k]]);  // read when each stage is made
        side[k].ctx = std::make_shared<Context>("", "");
        if (o.stage == "mde") make_mde(side[k], pts);
        else if (o.stage == "neighbors") make_neighbors(side[k], o.agents);
        else if (o.stage == "energy") make_energy(side[k], o.agents, o.cells[source[k]], data);
        else if (o.stage == "policy") make_policy(side[k], o.agents, weights);
        else make_noise(side[k], pts);
        side[k].run();  // built and warm
    }
    set_kernel_width_override(0);
    std::vector<double> ratio, ms[2];
    for (int r = 0; r < o.reps; ++r) {
        double t[2] = {0.0, 0.0};
        for (int j = 0; j < 4; ++j) {
            const int k = (r & 1) ? 3 - j : j;  // forwards, then backwards
            const auto t0 = std::chrono::steady_clock::now();
            side[k].run();
            const double dt = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            ms[source[k]].push_back(dt);
            t[source[k]] += dt;
        }
        ratio.push_back(t[1] / t[0]);
    }
    const auto a = side[0].result();
    bool same = true;
    for (int k = 1; k < 4; ++k) {
        const auto b = side[k].result();
        same = same && a == b;
    }
    const std::string device = side[0].ctx->device().device_name;
    std::printf("kernel_ab %s, %u agents, %d alternated rounds on %s (%s), load %.2f\n", o.stage.c_str(), o.agents,
                o.reps, device.c_str(), cpu_model().c_str(), load_before);
    std::printf("  widths (0: the device's) old %u, new %u", o.widths[0], o.widths[1]);
    if (o.stage == "energy") std::printf("; grid cells old %.4g m, new %.4g m", o.cells[0], o.cells[1]);
    std::printf("\n  old %s: median %.3f ms (min %.3f)\n  new %s: median %.3f ms (min %.3f)\n", o.old_dir.c_str(),
                median(ms[0]), minimum(ms[0]), o.new_dir.c_str(), median(ms[1]), minimum(ms[1]));
    std::printf("  new / old, median of the rounds' ratios: %.3f; results %s\n", median(ratio),
                same ? "bitwise the same" : "DIFFER");
    if (!o.json.empty()) {
        std::ofstream j(o.json);
        j << "{\n  \"benchmark\": \"kernel_ab\",\n  \"date\": \"" << utc_now() << "\",\n  \"stage\": \"" << o.stage
          << "\",\n  \"agents\": " << o.agents << ",\n  \"device\": \"" << json_escape(device)
          << "\",\n  \"cpu\": \"" << json_escape(cpu_model()) << "\",\n  \"load_before\": " << load_before
          << ",\n  \"load_after\": " << load_average() << ",\n  \"old\": \"" << json_escape(o.old_dir)
          << "\",\n  \"new\": \"" << json_escape(o.new_dir) << "\",\n  \"old_width\": " << o.widths[0]
          << ",\n  \"new_width\": " << o.widths[1];
        if (o.stage == "energy") j << ",\n  \"old_cell\": " << o.cells[0] << ",\n  \"new_cell\": " << o.cells[1];
        j << ",\n  \"old_ms\": " << json_array(ms[0], 1.0)
          << ",\n  \"new_ms\": " << json_array(ms[1], 1.0) << ",\n  \"round_ratios\": " << json_array(ratio, 1.0)
          << ",\n  \"median_ratio\": " << median(ratio) << ",\n  \"bitwise_same\": " << (same ? "true" : "false")
          << "\n}\n";
        std::printf("wrote %s\n", o.json.c_str());
    }
    return same ? 0 : 1;
}
