// The helper thread of the host's parallel loops (host/core/helper_thread.hpp):
// every index of a loop runs exactly once, whichever thread takes it, over
// many jobs posted back to back (so that the helper is sometimes late for a
// job the caller has finished alone, and sometimes inside one).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <thread>
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

// A body that throws, on whichever thread runs that chunk: for_chunks
// rethrows it once both threads have stopped, and the next job runs whole.
TEST(HelperThread, AThrowingBodyIsRethrownAndTheHelperGoesOn) {
    HelperThread helper;
    for (int round = 0; round < 200; ++round) {
        std::atomic<size_t> ran{0};
        auto failing = [&](size_t begin, size_t end) {
            ran += end - begin;
            if (begin <= 700 && 700 < end) throw std::runtime_error("chunk 700");
        };
        EXPECT_THROW(helper.for_chunks(1000, 10, failing), std::runtime_error);
        EXPECT_LE(ran.load(), 1000u);
        std::atomic<size_t> sum{0};
        auto counting = [&](size_t begin, size_t end) { sum += end - begin; };
        helper.for_chunks(1000, 10, counting);
        ASSERT_EQ(sum.load(), 1000u) << round;
    }
}

// The helper's own exception reaches the caller: a body that throws only on
// the helper thread, and on the caller's waits (up to 10 s) until the helper
// has taken a chunk.
TEST(HelperThread, TheHelpersExceptionReachesTheCaller) {
    HelperThread helper;
    if (!helper.running()) GTEST_SKIP() << "one processor: no helper thread";
    const auto caller = std::this_thread::get_id();
    for (int round = 0; round < 20; ++round) {
        std::atomic<bool> helper_ran{false};
        auto on_helper_only = [&](size_t, size_t) {
            if (std::this_thread::get_id() != caller) {
                helper_ran = true;
                throw std::runtime_error("helper");
            }
            const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(10);
            while (!helper_ran && std::chrono::steady_clock::now() < until) std::this_thread::yield();
        };
        EXPECT_THROW(helper.for_chunks(100, 1, on_helper_only), std::runtime_error) << round;
        EXPECT_TRUE(helper_ran.load());
    }
}
