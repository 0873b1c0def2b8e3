// Fast marching benchmark (curl-noise paper §5.2, Eq. 7): swarmcl's
// fast_march / solve_cost on an N^3 grid (distance from a small sphere, |grad
// u| = 1) beside scikit-fmm's skfmm.distance on the same grid in the same run
// (bench/fmm_skfmm.py through /usr/bin/python3, Debian's python3-scikit-fmm),
// first and second order, with both max errors against the exact distance.
//
//   fmm_bench [--n 128] [--repeats 3] [--threads 0] [--python /usr/bin/python3] [--json PATH]
//
// --threads: FastMarchingOptions::threads (0: a second thread on large
// grids, 1: the caller's alone); the run with the other setting is timed as
// well, first order, and printed beside it.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.hpp"
#include "fields/cost_field.hpp"
#include "roofline.hpp"

#ifndef SWARMCL_BENCH_RESULTS_DIR
#define SWARMCL_BENCH_RESULTS_DIR "bench/results"
#endif
#ifndef SWARMCL_BENCH_DIR
#define SWARMCL_BENCH_DIR "bench"
#endif

using namespace swarmcl;
using namespace swarmcl::bench;
using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
    uint32_t n = 128;
    int repeats = 3;
    unsigned threads = 0;
    std::string python = "/usr/bin/python3", json = std::string(SWARMCL_BENCH_RESULTS_DIR) + "/fmm.json";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--n") n = uint32_t(std::atoi(next().c_str()));
        else if (a == "--repeats") repeats = std::atoi(next().c_str());
        else if (a == "--threads") threads = unsigned(std::atoi(next().c_str()));
        else if (a == "--python") python = next();
        else if (a == "--json") json = next();
        else { std::fprintf(stderr, "usage: fmm_bench [--n 128] [--repeats 3] [--threads 0] [--python PATH] [--json PATH]\n"); return 2; }
    }
    Grid3 g;
    g.h = 1.0 / n;
    g.dims = {n, n, n};
    const double R = 2.0 * g.h;
    const float C[3] = {0.31f, 0.47f, 0.52f};
    Goal goal;
    goal.kind = Goal::Kind::Sphere;
    goal.center = {C[0], C[1], C[2]};
    goal.radius = float(R);
    CostWeights w;
    w.A = 1.0;
    w.B = 0.0;
    const auto slowness = cost_slowness(g, {}, w);
    std::printf("fmm_bench: %u^3 cells, distance from a sphere of radius %.4f (2 cells), load %.2f\n", n, R,
                load_average());
    double secs[2], err[2];
    std::vector<double> runs[2], first_order;
    for (int order = 0; order < 2; ++order) {
        std::vector<double> u;
        for (int r = 0; r < repeats; ++r) {
            const auto t0 = Clock::now();
            u = solve_cost(g, slowness, {goal}, order == 1, threads);
            runs[order].push_back(std::chrono::duration<double>(Clock::now() - t0).count());
        }
        secs[order] = median(runs[order]);
        if (order == 0) first_order = u;
        err[order] = 0;
        for (uint32_t k = 0; k < n; ++k)
            for (uint32_t j = 0; j < n; ++j)
                for (uint32_t i = 0; i < n; ++i) {
                    const auto p = g.center(i, j, k);
                    const double exact = std::hypot(p[0] - C[0], p[1] - C[1], p[2] - C[2]) - R;
                    if (exact > 0) err[order] = std::max(err[order], std::fabs(u[g.index(i, j, k)] - exact));
                }
    }
    // The roofline (issue 29): the solver runs on the host, one thread; at
    // the least it reads each cell's slowness and writes its cost (two
    // doubles) and keeps a state byte, beside std::copy's bandwidth on this
    // host in this run.
    const double cells = double(n) * n * n, host_gbs = host_copy_bandwidth_gbs(size_t(cells));
    const std::vector<RooflineRow> roof = {roofline_row("fast marching, first order", 17, cells, 1e3 * secs[0], host_gbs),
                                           roofline_row("fast marching, second order", 17, cells, 1e3 * secs[1],
                                                        host_gbs)};
    std::printf("  (rows per cell; the copy is the host's std::copy, one thread)\n");
    print_roofline(roof, host_gbs);
    // The peer, same grid, same run.
    char cmd[1024];
    std::snprintf(cmd, sizeof cmd, "%s %s/fmm_skfmm.py %u %.17g %.17g %.9g %.9g %.9g %d", python.c_str(),
                  SWARMCL_BENCH_DIR, n, g.h, R, C[0], C[1], C[2], repeats);
    std::string peer;
    if (FILE* f = popen(cmd, "r")) {
        char buf[4096];
        while (fgets(buf, sizeof buf, f)) peer += buf;
        pclose(f);
    }
    while (!peer.empty() && (peer.back() == '\n' || peer.back() == '\r')) peer.pop_back();
    auto field = [&](const std::string& order, const std::string& key) {
        const auto o = peer.find("\"" + order + "\"");
        if (o == std::string::npos) return -1.0;
        const auto k = peer.find("\"" + key + "\": ", o);
        return k == std::string::npos ? -1.0 : std::atof(peer.c_str() + k + key.size() + 4);
    };
    const double s1 = field("order1", "seconds"), e1 = field("order1", "max_error");
    const double s2 = field("order2", "seconds"), e2 = field("order2", "max_error");
    std::printf("  swarmcl first order   %7.3f s   max error %.2f cells\n", secs[0], err[0] / g.h);
    std::printf("  swarmcl second order  %7.3f s   max error %.2f cells\n", secs[1], err[1] / g.h);
    // The first order once more with the other threads setting: its time,
    // and whether its result is the same bits.
    const unsigned other = threads == 1 ? 0 : 1;
    std::vector<double> other_runs;
    bool same_bits = true;
    for (int r = 0; r < repeats; ++r) {
        const auto t0 = Clock::now();
        const auto u = solve_cost(g, slowness, {goal}, false, other);
        other_runs.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
        same_bits &= u == first_order;
    }
    const double other_secs = median(other_runs);
    std::printf("  first order, threads %u %7.3f s   (threads %u: %.3f s, %.2fx; the same bits: %s)\n", other, other_secs,
                threads, secs[0], other_secs / secs[0], same_bits ? "yes" : "NO");
    if (s1 > 0) {
        std::printf("  scikit-fmm order 1    %7.3f s   max error %.2f cells   (scikit-fmm / swarmcl: %.2f)\n", s1,
                    e1 / g.h, s1 / secs[0]);
        std::printf("  scikit-fmm order 2    %7.3f s   max error %.2f cells   (scikit-fmm / swarmcl: %.2f)\n", s2,
                    e2 / g.h, s2 / secs[1]);
    } else {
        std::printf("  scikit-fmm: not run (%s)\n", cmd);
    }
    std::ofstream out(json);
    out << "{\n  \"benchmark\": \"fmm_bench\",\n  \"date\": \"" << utc_now() << "\",\n  \"load_average\": "
        << load_average() << ",\n  \"cells\": " << n << ",\n  \"swarmcl_order1_seconds\": " << secs[0]
        << ",\n  \"swarmcl_order1_runs\": " << json_array(runs[0], 1.0) << ",\n  \"swarmcl_order1_max_error_cells\": "
        << err[0] / g.h << ",\n  \"swarmcl_order2_seconds\": " << secs[1] << ",\n  \"swarmcl_order2_max_error_cells\": "
        << err[1] / g.h << ",\n  \"threads\": " << threads << ",\n  \"order1_other_threads\": {\"threads\": " << other
        << ", \"seconds\": " << other_secs << ", \"runs\": " << json_array(other_runs, 1.0)
        << ", \"same_bits\": " << (same_bits ? "true" : "false") << "},\n  \"roofline_host_copy\": " << roofline_json(roof, host_gbs) << ",\n  \"skfmm\": " << (peer.empty() ? "null" : peer) << "\n}\n";
    std::printf("  wrote %s\n", json.c_str());
    return 0;
}
