#include "core/helper_thread.hpp"

#include <chrono>
#include <exception>
#include <system_error>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace swarmcl {
namespace {

inline void cpu_relax() {
#if defined(__SSE2__)
    _mm_pause();
#endif
}

// How long the helper spins for the next job before it sleeps: longer than
// the serial work between two of fast marching's loops (about 0.2 ms at
// 128^3), so that it is awake for the next; a wake from sleep takes tens of
// microseconds.
constexpr std::chrono::microseconds kSpin(500);

}  // namespace

HelperThread::HelperThread() {
    if (std::thread::hardware_concurrency() < 2) return;
    try {
        thread_ = std::thread([this] { loop(); });
    } catch (const std::system_error&) {
        // No helper: every loop runs on the caller's thread.
    }
}

HelperThread::~HelperThread() {
    if (!thread_.joinable()) return;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_.store(true, std::memory_order_release);
    }
    wake_.notify_one();
    thread_.join();
}

void HelperThread::take_chunks() {
    for (;;) {
        const size_t begin = next_.fetch_add(chunk_, std::memory_order_relaxed);
        if (begin >= n_) return;
        fn_(ctx_, begin, begin + chunk_ < n_ ? begin + chunk_ : n_);
    }
}

// A job is open to the helper from its post until one of the two threads
// marks it: the helper kTaken, when it starts on it, or the caller kClosed,
// when it has done every chunk before the helper woke (then it need not
// wait).  The job's fields are written only while no job is open or taken.
void HelperThread::run(size_t n, size_t chunk, Fn fn, void* ctx) {
    if (n == 0) return;
    n_ = n;
    chunk_ = chunk ? chunk : 1;
    fn_ = fn;
    ctx_ = ctx;
    error_ = nullptr;
    next_.store(0, std::memory_order_relaxed);
    if (!thread_.joinable() || n <= chunk_) {
        take_chunks();
        return;
    }
    const uint64_t job = posted_.load(std::memory_order_relaxed) + 1;
    open_.store(job, std::memory_order_release);
    {
        std::lock_guard<std::mutex> lock(mutex_);  // the helper tests posted_ under the lock before it sleeps
        posted_.store(job, std::memory_order_release);
    }
    wake_.notify_one();
    std::exception_ptr mine;
    try {
        take_chunks();
    } catch (...) {
        mine = std::current_exception();
        next_.store(n_, std::memory_order_relaxed);  // no more chunks for the helper either
    }
    uint64_t expected = job;
    if (!open_.compare_exchange_strong(expected, job | kClosed, std::memory_order_acq_rel))
        while (finished_.load(std::memory_order_acquire) != job) cpu_relax();  // the helper is inside its last chunk
    if (mine) std::rethrow_exception(mine);
    if (error_) std::rethrow_exception(error_);
}

void HelperThread::loop() {
    uint64_t seen = 0;
    for (;;) {
        const auto until = std::chrono::steady_clock::now() + kSpin;
        while (posted_.load(std::memory_order_acquire) == seen && !stop_.load(std::memory_order_acquire)) {
            cpu_relax();
            if (std::chrono::steady_clock::now() > until) {
                std::unique_lock<std::mutex> lock(mutex_);
                wake_.wait(lock, [&] {
                    return posted_.load(std::memory_order_acquire) != seen || stop_.load(std::memory_order_acquire);
                });
            }
        }
        if (stop_.load(std::memory_order_acquire)) return;
        seen = posted_.load(std::memory_order_acquire);
        uint64_t expected = seen;
        if (!open_.compare_exchange_strong(expected, seen | kTaken, std::memory_order_acq_rel)) continue;
        try {
            take_chunks();
        } catch (...) {  // the caller rethrows it
            error_ = std::current_exception();
            next_.store(n_, std::memory_order_relaxed);
        }
        finished_.store(seen, std::memory_order_release);
    }
}

}  // namespace swarmcl
