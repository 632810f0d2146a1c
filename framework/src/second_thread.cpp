#include "gpl/second_thread.h"

#include <chrono>
#include <system_error>
#include <utility>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace gpl {
namespace {

// How long a waiting thread spins before it sleeps (the second thread) or yields (the caller): a
// sweep's hand-overs are a few tens of microseconds apart.
constexpr std::chrono::microseconds kSpin{100};

// Lets the other hardware thread of a shared core run while this one spins.
inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
}

// Spins until done() or kSpin has passed; true when done.
template <class Done>
bool spinUntil(Done done) {
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (int k = 0;; ++k) {
        if (done()) return true;
        pause();
        if ((k & 63) == 63 && std::chrono::steady_clock::now() > until) return false;
    }
}

}  // namespace

SecondThread::~SecondThread() {
    if (!thread_.joinable()) return;
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    wake_.notify_one();
    thread_.join();
}

bool SecondThread::started() {
    if (!thread_.joinable() && !failed_) {
        try {
            thread_ = std::thread([this] { loop(); });
        } catch (const std::system_error&) {
            failed_ = true;  // e.g. a sandbox's limit on processes: the caller does it all
        }
    }
    return thread_.joinable();
}

void SecondThread::post(const std::function<void()>* work) {
    finish();
    {
        const std::lock_guard<std::mutex> lock(mutex_);
        work_ = work;
        posted_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_one();
}

void SecondThread::finish() {
    const std::uint64_t posted = posted_.load(std::memory_order_relaxed);
    const auto finished = [this, posted] { return done_.load(std::memory_order_acquire) == posted; };
    while (!spinUntil(finished)) std::this_thread::yield();
}

void SecondThread::wake() {
    if (started()) post(nullptr);
}

void SecondThread::run(bool use, const std::function<void()>& mine, const std::function<void()>& theirs) {
    if (!use || !started()) {
        mine();
        theirs();
        return;
    }
    post(&theirs);
    std::exception_ptr mineFailed;
    try {
        mine();
    } catch (...) {
        mineFailed = std::current_exception();
    }
    finish();
    if (mineFailed) std::rethrow_exception(mineFailed);
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void SecondThread::loop() {
    std::uint64_t seen = 0;
    const auto posted = [this, &seen] { return posted_.load(std::memory_order_acquire) != seen || stop_; };
    for (;;) {
        if (!spinUntil(posted)) {
            std::unique_lock<std::mutex> lock(mutex_);
            wake_.wait(lock, posted);
        }
        if (stop_) return;
        const std::function<void()>* work = nullptr;
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            work = work_;
            seen = posted_.load(std::memory_order_relaxed);
        }
        if (work != nullptr) {
            try {
                (*work)();
            } catch (...) {
                error_ = std::current_exception();
            }
        }
        done_.store(seen, std::memory_order_release);
    }
}

}  // namespace gpl
