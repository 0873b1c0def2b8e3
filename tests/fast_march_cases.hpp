// Grids for fast marching's tests (tests/test_path_field.cpp and the
// ThreadSanitizer build, tests/tsan_host_threads.cpp): random slowness, and
// a 64^3 grid with a wall, over the 2 MB from which fast_march starts its
// helper thread.
#pragma once
#include <cstdint>
#include <random>
#include <vector>

#include "fields/fast_marching.hpp"

namespace swarmcl::test {

inline std::vector<double> random_slowness(size_t count, unsigned seed, double lo, double hi) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> slow(lo, hi);
    std::vector<double> f(count);
    for (auto& x : f) x = slow(rng);
    return f;
}

// [0, 1]^3 in 64^3 cells, slowness in [1, 2], a wall x = 32 (y >= 10, z <
// 50) and two sources on either side of it.
struct WalledGrid {
    Grid3 grid;
    std::vector<double> slowness, known;  // known: the sources' 0, +inf elsewhere
};
inline WalledGrid walled_grid_64() {
    WalledGrid w;
    const uint32_t N = 64;
    w.grid.h = 1.0 / N;
    w.grid.dims = {N, N, N};
    w.slowness = random_slowness(w.grid.count(), 11, 1.0, 2.0);
    for (uint32_t k = 0; k < 50; ++k)
        for (uint32_t j = 10; j < N; ++j) w.slowness[w.grid.index(32, j, k)] = kInf;
    w.known.assign(w.grid.count(), kInf);
    w.known[w.grid.index(50, 40, 3)] = 0.0;
    w.known[w.grid.index(7, 60, 60)] = 0.0;
    return w;
}

}  // namespace swarmcl::test
