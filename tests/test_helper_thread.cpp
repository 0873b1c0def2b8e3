// The helper thread of the host's parallel loops (host/core/helper_thread.hpp):
// every index of a loop runs exactly once, whichever thread takes it, over
// many jobs posted back to back (so that the helper is sometimes late for a
// job the caller has finished alone, and sometimes inside one).
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <vector>

#include "core/helper_thread.hpp"

using swarmcl::HelperThread;

TEST(HelperThread, EveryIndexRunsOnceInEveryJob) {
    HelperThread helper;
    std::vector<std::atomic<int>> hits(5000);
    size_t jobs = 0;
    for (int round = 0; round < 300; ++round)
        for (const size_t n : {size_t(0), size_t(1), size_t(7), size_t(256), size_t(257), size_t(5000)})
            for (const size_t chunk : {size_t(1), size_t(16), size_t(256)}) {
                for (auto& h : hits) h.store(0, std::memory_order_relaxed);
                auto body = [&](size_t begin, size_t end) {
                    ASSERT_LT(begin, end);
                    ASSERT_LE(end, n);
                    ASSERT_LE(end - begin, chunk);
                    for (size_t i = begin; i < end; ++i) hits[i].fetch_add(1, std::memory_order_relaxed);
                };
                helper.for_chunks(n, chunk, body);
                ++jobs;
                for (size_t i = 0; i < hits.size(); ++i)
                    ASSERT_EQ(hits[i].load(), i < n ? 1 : 0) << "n " << n << " chunk " << chunk << " index " << i;
            }
    EXPECT_EQ(jobs, 300u * 18u);
}

// Results written by the helper's chunks are seen by the caller once
// for_chunks returns (plain writes, no atomics).
TEST(HelperThread, TheCallerSeesTheHelpersWrites) {
    HelperThread helper;
    std::vector<double> out(100000);
    for (int round = 0; round < 50; ++round) {
        auto body = [&](size_t begin, size_t end) {
            for (size_t i = begin; i < end; ++i) out[i] = double(i) * round;
        };
        helper.for_chunks(out.size(), 512, body);
        for (size_t i = 0; i < out.size(); ++i) ASSERT_EQ(out[i], double(i) * round) << i;
    }
}

// Started and stopped at once, or after a job, or a thousand times: no hang.
TEST(HelperThread, StopsWhenIdleOrAfterWork) {
    for (int i = 0; i < 1000; ++i) {
        auto helper = std::make_unique<HelperThread>();
        if (i % 2) {
            std::atomic<size_t> sum{0};
            auto body = [&](size_t begin, size_t end) { sum += end - begin; };
            helper->for_chunks(1000, 10, body);
            ASSERT_EQ(sum.load(), 1000u);
        }
    }
}
