// One thread beside the caller's for the host's own loops whose iterations
// are independent, such as fast marching's solves of a batch of cells
// (host/fields/fast_marching.cpp): the two threads take chunks of the range
// from a shared counter, so a helper that wakes late takes less of it.  Each
// iteration writes only its own results, so the results do not depend on
// which thread ran it.
#pragma once
#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

namespace swarmcl {

class HelperThread {
public:
    // Starts the thread; where it cannot be started (one processor, or the
    // system refuses a thread), every loop runs on the caller's alone.
    HelperThread();
    ~HelperThread();
    HelperThread(const HelperThread&) = delete;
    HelperThread& operator=(const HelperThread&) = delete;

    bool running() const { return thread_.joinable(); }

    // body(begin, end) over [0, n) in chunks of `chunk`, on both threads;
    // returns when every chunk is done.  Where body throws, the chunks not
    // yet started are dropped and the first exception is rethrown here once
    // both threads have stopped.
    template <class Body>
    void for_chunks(size_t n, size_t chunk, Body& body) {
        run(n, chunk, [](void* b, size_t begin, size_t end) { (*static_cast<Body*>(b))(begin, end); }, &body);
    }

private:
    using Fn = void (*)(void*, size_t, size_t);
    void run(size_t n, size_t chunk, Fn fn, void* ctx);
    void take_chunks();
    void loop();

    std::mutex mutex_;
    std::condition_variable wake_;
    static constexpr uint64_t kTaken = uint64_t(1) << 62, kClosed = uint64_t(1) << 63;
    std::atomic<uint64_t> posted_{0}, finished_{0}, open_{0};
    std::atomic<bool> stop_{false};
    std::atomic<size_t> next_{0};
    // The job: written by the caller before posted_ is raised (release),
    // read by the helper after it sees the raise (acquire).
    size_t n_ = 0, chunk_ = 1;
    Fn fn_ = nullptr;
    void* ctx_ = nullptr;
    std::exception_ptr error_;  // the helper's, read by the caller after finished_
    std::thread thread_;
};

}  // namespace swarmcl
