// The thread rule of swarmcl.h (issue 16 item 7): threads each with their own
// context step at once and each gets, bitwise, the single-threaded result;
// swarms of ONE context stepped from several threads at once do too (the
// handle registry, the context's program cache and each swarm are locked).
// scripts/tsan.sh builds this file with -fsanitize=thread and runs it.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "scenario_runs.hpp"

namespace {

using namespace swarmcl::test;

constexpr uint32_t kSteps = 20, kBatch = 5;
constexpr int kThreads = 4;

// The single-threaded result of every model, on a context of its own.
std::vector<State> references() {
    std::vector<State> refs;
    swcl_context_desc d = swcl_context_desc_default();
    swcl_context ctx;
    EXPECT_EQ(swcl_context_create(&d, &ctx), SWCL_OK) << swcl_last_error();
    for (const auto& c : model_cases()) {
        swcl_status st;
        refs.push_back(run_scenario(scenario_text(c, kSteps), ctx, kSteps, kBatch, &st));
        EXPECT_EQ(st, SWCL_OK) << c.model << ": " << swcl_last_error();
    }
    swcl_context_destroy(ctx);
    return refs;
}

TEST(Threads, EachThreadWithItsOwnContextMatchesTheSingleThreadedRun) {
    const auto refs = references();
    const auto& cases = model_cases();
    std::vector<State> got(kThreads);
    std::vector<swcl_status> status(kThreads, SWCL_ERROR_INTERNAL);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            swcl_context_desc d = swcl_context_desc_default();
            swcl_context ctx;
            status[t] = swcl_context_create(&d, &ctx);
            if (status[t] != SWCL_OK) return;
            got[t] = run_scenario(scenario_text(cases[t % cases.size()], kSteps), ctx, kSteps, kBatch, &status[t]);
            swcl_context_destroy(ctx);
        });
    for (auto& th : threads) th.join();
    for (int t = 0; t < kThreads; ++t) {
        ASSERT_EQ(status[t], SWCL_OK) << "thread " << t;
        EXPECT_TRUE(got[t] == refs[t % cases.size()]) << "thread " << t << " (" << cases[t % cases.size()].model << ")";
    }
}

TEST(Threads, SwarmsOfOneContextSteppedFromSeveralThreadsMatchTheSingleThreadedRun) {
    const auto refs = references();
    const auto& cases = model_cases();
    swcl_context_desc d = swcl_context_desc_default();
    swcl_context ctx;
    ASSERT_EQ(swcl_context_create(&d, &ctx), SWCL_OK) << swcl_last_error();
    std::vector<State> got(kThreads);
    std::vector<swcl_status> status(kThreads, SWCL_ERROR_INTERNAL);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            got[t] = run_scenario(scenario_text(cases[t % cases.size()], kSteps), ctx, kSteps, kBatch, &status[t]);
        });
    for (auto& th : threads) th.join();
    for (int t = 0; t < kThreads; ++t) {
        ASSERT_EQ(status[t], SWCL_OK) << "thread " << t;
        EXPECT_TRUE(got[t] == refs[t % cases.size()]) << "thread " << t << " (" << cases[t % cases.size()].model << ")";
    }
    swcl_context_destroy(ctx);
}

TEST(Threads, LastErrorIsPerThread) {
    // Each thread's failure message stays its own while the others fail differently.
    std::atomic<int> wrong{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
        threads.emplace_back([&, t] {
            for (int i = 0; i < 200; ++i) {
                uint32_t n;
                const swcl_status st = t % 2 ? swcl_swarm_agent_count(swcl_swarm{0}, &n)
                                             : swcl_swarm_agent_count(swcl_swarm{1}, nullptr);
                const std::string msg = swcl_last_error();
                if (st == SWCL_OK || msg.empty()) wrong++;
                if (msg.find(t % 2 ? "null swarm handle" : "not a live swarm") == std::string::npos) wrong++;
            }
        });
    for (auto& th : threads) th.join();
    EXPECT_EQ(wrong.load(), 0);
}

TEST(Threads, DestroyingASwarmWhileAnotherThreadStepsItIsNotACrash) {
    // Documented as safe but unordered: each step is OK (before the destroy)
    // or SWCL_ERROR_INVALID_HANDLE (after), never anything else.
    swcl_context_desc d = swcl_context_desc_default();
    swcl_context ctx;
    ASSERT_EQ(swcl_context_create(&d, &ctx), SWCL_OK) << swcl_last_error();
    for (int round = 0; round < 5; ++round) {
        swcl_swarm s;
        ASSERT_EQ(scenario_swarm(scenario_text(model_cases()[0], 10), ctx, &s), SWCL_OK) << swcl_last_error();
        std::atomic<int> other{0};
        std::atomic<bool> started{false};
        std::thread stepper([&] {
            for (int i = 0; i < 200; ++i) {
                const swcl_status st = swcl_swarm_step(s, 1);
                started = true;
                if (st != SWCL_OK && st != SWCL_ERROR_INVALID_HANDLE) other++;
            }
        });
        while (!started) std::this_thread::yield();
        EXPECT_EQ(swcl_swarm_destroy(s), SWCL_OK);
        stepper.join();
        EXPECT_EQ(other.load(), 0);
    }
    swcl_context_destroy(ctx);
}

}  // namespace
