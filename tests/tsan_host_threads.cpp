// The host's own threads under ThreadSanitizer (tests/CMakeLists.txt,
// tsan.host_threads): fast marching's helper thread
// (host/core/helper_thread.cpp, host/fields/fast_marching.cpp), compiled
// with -fsanitize=thread, on tests/fast_march_cases.hpp's 64^3 grid with a
// wall, both orders, against the caller's thread alone; then 2,000 loops posted
// back to back, and 200 whose body throws.  A race makes TSan exit with 66;
// different bits, or an exception lost, exit 1.
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "core/helper_thread.hpp"
#include "fast_march_cases.hpp"
#include "fields/fast_marching.hpp"

using namespace swarmcl;

int main() {
    const test::WalledGrid w = test::walled_grid_64();
    int failed = 0;
    for (const bool second : {false, true}) {
        FastMarchingOptions one, two;
        one.threads = 1;
        one.second_order = two.second_order = second;
        std::vector<double> a = w.known, b = w.known;
        fast_march(w.grid, w.slowness, a, one);
        fast_march(w.grid, w.slowness, b, two);
        if (a != b) {
            std::printf("order %d: one thread and two differ\n", second ? 2 : 1);
            failed = 1;
        }
    }
    HelperThread helper;
    std::vector<int> out(10000);
    for (int round = 0; round < 2000; ++round) {
        const size_t n = out.size() - size_t(round % 7) * 1000;
        auto body = [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) out[i] = round;
        };
        helper.for_chunks(n, 256, body);
        for (size_t i = 0; i < n; ++i) failed |= out[i] != round;
    }
    // A throwing body: rethrown on the caller, the helper stopped cleanly.
    for (int round = 0; round < 200; ++round) {
        auto throwing = [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) out[i] = -round;
            if (begin <= 5000 && 5000 < end) throw std::runtime_error("chunk 5000");
        };
        bool threw = false;
        try {
            helper.for_chunks(out.size(), 64, throwing);
        } catch (const std::runtime_error&) {
            threw = true;
        }
        failed |= !threw;
    }
    std::printf("tsan_host_threads: %s\n", failed ? "FAILED" : "ok");
    return failed;
}
