#include "frame_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "cli_support.hpp"

namespace swarmcl_cli {

FrameStats frame_stats(swcl_swarm swarm, uint32_t n, float min_distance) {
    FrameStats f;
    if (n == 0) return f;
    std::vector<float> vel(size_t(n) * 3), nn(n);
    check(swcl_swarm_read(swarm, SWCL_ATTRIBUTE_VELOCITY, vel.data(), n), "reading velocities");
    for (uint32_t i = 0; i < n; ++i)
        f.mean_speed += std::sqrt(double(vel[3 * i]) * vel[3 * i] + double(vel[3 * i + 1]) * vel[3 * i + 1] +
                                  double(vel[3 * i + 2]) * vel[3 * i + 2]) / n;
    if (n > 1) {
        check(swcl_swarm_nearest_neighbor(swarm, nn.data(), nullptr, n), "nearest neighbours");
        std::sort(nn.begin(), nn.end());
        auto pct = [&](double q) { return double(nn[size_t(q * (n - 1) + 0.5)]); };
        f.nn_p5 = pct(0.05), f.nn_p50 = pct(0.5), f.nn_p95 = pct(0.95);
        if (min_distance > 0) {
            std::vector<uint32_t> close(n);
            // Just below the threshold: pairs MDE left at exactly d do not count.
            check(swcl_swarm_neighbor_count(swarm, min_distance * 0.999f, close.data(), n), "counting close pairs");
            double pairs = 0;
            for (uint32_t c : close) pairs += c;
            f.close_pair_fraction = pairs / 2.0 / (0.5 * double(n) * (n - 1.0));
        }
    }
    swcl_step_stats st;
    st.struct_size = sizeof(st);
    check(swcl_swarm_take_step_stats(swarm, &st), "reading statistics");
    if (st.steps) f.mde_moved = double(st.mde_moved_total) / (double(st.steps) * n);
    return f;
}

void print_stats_header() {
    std::printf("%8s %8s %9s %9s %9s %10s %9s\n", "step", "speed", "nn p5", "nn p50", "nn p95", "pairs<mde",
                "MDE moved");
}

void print_stats(uint32_t step, const FrameStats& f) {
    std::printf("%8u %8.3f %9.4f %9.4f %9.4f %10.2e %8.3f%%\n", step, f.mean_speed, f.nn_p5, f.nn_p50, f.nn_p95,
                f.close_pair_fraction, 100.0 * f.mde_moved);
}

}  // namespace swarmcl_cli
