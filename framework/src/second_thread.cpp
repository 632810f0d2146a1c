#include "gpl/second_thread.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <mutex>
#include <system_error>
#include <thread>
#include <utility>

#include <time.h>
#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace gpl {
namespace {

// How long a waiting thread spins before it sleeps (the second thread) or yields (the caller): a
// sweep's hand-overs are a few tens of microseconds apart.
constexpr std::chrono::microseconds kSpin{500};         // after a hand-over
constexpr std::chrono::microseconds kWokenSpin{20000};  // after wake(): a stage's preparations

// What the second thread gains, hand-over by hand-over: what its half would have added on one thread
// less the time the caller waited for it once its own half was done. What the half would have added
// is the time it took the second thread on its core (time without a core not counted), but no more
// than the caller's own half took on its core: the halves are cut to equal work, and a half that
// takes the second thread longer (its core's caches shared with another program) gains no more.
// When the caller found the other half not begun and ran it itself, the hand-over gains
// -kClaimCost instead (the second thread had no core; its spinning and the hand-over were for
// nothing). Less, either way, the time the caller itself was without a core during the hand-over:
// the machine then has fewer free cores than this program's threads, and the second thread's
// spinning takes a core's time from the caller or from another program.
//
// The gains add up, at most to kCredit; once they fall below -kTolerance the second thread has
// cost more than it gained, and the caller runs both halves itself, the second thread asleep, for
// the next kFirstAlone hand-overs. Then it tries two threads again; each try that fails doubles the
// hand-overs alone, up to kLongestAlone, and a try whose gains reach kCredit brings them back to
// kFirstAlone. Hand-overs, not seconds: the time between an engine's steps (its program doing
// something else) does not end a stretch alone.
constexpr std::chrono::microseconds kClaimCost{50};
constexpr std::chrono::microseconds kCredit{2000};
constexpr std::chrono::microseconds kTolerance{200};
constexpr std::uint64_t kFirstAlone = 32;
constexpr std::uint64_t kLongestAlone = 4096;

// The time this thread has run on a core.
std::chrono::nanoseconds onCore() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return std::chrono::seconds(t.tv_sec) + std::chrono::nanoseconds(t.tv_nsec);
}

// Lets the other hardware thread of a shared core run while this one spins.
inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
    _mm_pause();
#endif
}

// Spins until done() or `spin` has passed; true when done. Every few microseconds it offers the
// core to any other thread that is waiting for it (another program, or a test run beside this one):
// alone on its core, that returns at once.
template <class Done>
bool spinUntil(Done done, std::chrono::microseconds spin) {
    const auto until = std::chrono::steady_clock::now() + spin;
    for (int k = 0;; ++k) {
        if (done()) return true;
        pause();
        if ((k & 63) == 63) {
            if (std::chrono::steady_clock::now() > until) return false;
            std::this_thread::yield();
        }
    }
}

}  // namespace

struct SecondThread::Shared {
    std::thread thread;
    bool failed = false;  ///< the system would not make a thread: the caller does it all
    std::mutex mutex;
    std::condition_variable wake;
    const std::function<void()>* work = nullptr;
    std::atomic<std::uint64_t> posted{0};   ///< hand-overs so far
    /// The last hand-over that either thread has taken to run: the second thread, or the caller
    /// once its own half is done and the second thread has not begun (it may have no core now).
    std::atomic<std::uint64_t> claimed{0};
    std::atomic<std::uint64_t> done{0};     ///< the last hand-over that has been run to its end
    std::chrono::nanoseconds theirsOnCore{0};  ///< the second thread's last work's time on its core
    std::atomic<bool> stop{false};
    std::exception_ptr error;  ///< what the last work threw

    // The caller's account of what the second thread gives now (only the caller reads and writes it).
    using Clock = std::chrono::steady_clock;
    std::uint64_t aloneLeft = 0;     ///< hand-overs the caller is still to run alone
    std::uint64_t nextAlone = kFirstAlone;
    Clock::duration gained{0};       ///< since the last time alone, at most kCredit

    /// True while the caller is to run both halves itself; counts `hand-overs` of them.
    bool alone(std::uint64_t handOvers) {
        if (aloneLeft == 0) return false;
        aloneLeft -= std::min(aloneLeft, handOvers);
        return true;
    }
    /// Books one hand-over's gain; the caller goes alone once the second thread has cost more than it
    /// gained.
    void book(Clock::duration gain) {
        gained = std::min<Clock::duration>(gained + gain, kCredit);
        if (gained == Clock::duration(kCredit)) nextAlone = kFirstAlone;
        if (gained >= -Clock::duration(kTolerance)) return;
        gained = Clock::duration(0);
        aloneLeft = nextAlone;
        nextAlone = std::min(2 * nextAlone, kLongestAlone);
    }

    ~Shared() {
        if (!thread.joinable()) return;
        {
            const std::lock_guard<std::mutex> lock(mutex);
            stop = true;
        }
        wake.notify_one();
        thread.join();
    }

    /// True once the thread runs (made now if need be).
    bool started() {
        if (!thread.joinable() && !failed) {
            try {
                thread = std::thread([this] { loop(); });
            } catch (const std::system_error&) {
                failed = true;  // e.g. a sandbox's limit on processes
            }
        }
        return thread.joinable();
    }

    /// Hands `next` (nullptr: nothing, only wake) to the thread, once the last is done; returns its
    /// number.
    std::uint64_t post(const std::function<void()>* next) {
        finish();
        std::uint64_t number = 0;
        {
            const std::lock_guard<std::mutex> lock(mutex);
            work = next;
            number = posted.load(std::memory_order_relaxed) + 1;
            if (next == nullptr) {  // nothing to run: taken and done as it is posted
                claimed.store(number, std::memory_order_relaxed);
                done.store(number, std::memory_order_relaxed);
            }
            posted.store(number, std::memory_order_release);
        }
        wake.notify_one();
        return number;
    }

    /// Takes hand-over `number` to run, unless the other thread has taken it.
    bool claim(std::uint64_t number) {
        std::uint64_t before = number - 1;
        return claimed.compare_exchange_strong(before, number, std::memory_order_acq_rel);
    }

    /// Returns once everything posted has been run.
    void finish() {
        const std::uint64_t all = posted.load(std::memory_order_relaxed);
        const auto finished = [this, all] { return done.load(std::memory_order_acquire) == all; };
        while (!spinUntil(finished, kSpin)) std::this_thread::yield();
    }

    void loop() {
        std::uint64_t seen = 0;
        std::chrono::microseconds spin = kSpin;
        const auto newWork = [this, &seen] { return posted.load(std::memory_order_acquire) != seen || stop; };
        for (;;) {
            if (!spinUntil(newWork, spin)) {
                std::unique_lock<std::mutex> lock(mutex);
                wake.wait(lock, newWork);
            }
            if (stop) return;
            const std::function<void()>* next = nullptr;
            {
                const std::lock_guard<std::mutex> lock(mutex);
                next = work;
                seen = posted.load(std::memory_order_relaxed);
            }
            spin = next == nullptr ? kWokenSpin : kSpin;  // woken: the hand-over comes after the preparations
            if (next != nullptr && claim(seen)) {
                const std::chrono::nanoseconds start = onCore();
                try {
                    (*next)();
                } catch (...) {
                    error = std::current_exception();
                }
                theirsOnCore = onCore() - start;
                done.store(seen, std::memory_order_release);
            }
        }
    }
};

SecondThread::SecondThread() : shared_(new Shared) {}
SecondThread::~SecondThread() { delete shared_; }
SecondThread::SecondThread(const SecondThread&) : shared_(new Shared) {}
SecondThread& SecondThread::operator=(const SecondThread&) { return *this; }

bool SecondThread::helps() { return !shared_->alone(1) && shared_->started(); }

void SecondThread::wake() {
    if (!shared_->alone(0) && shared_->started()) shared_->post(nullptr);
}

void SecondThread::run(bool use, const std::function<void()>& mine, const std::function<void()>& theirs) {
    if (!use || shared_->alone(1) || !shared_->started()) {
        mine();
        theirs();
        return;
    }
    const auto posted = Shared::Clock::now();
    const std::chrono::nanoseconds callerOnCore = onCore();
    const std::uint64_t number = shared_->post(&theirs);
    std::exception_ptr mineFailed, theirsFailed;
    try {
        mine();
    } catch (...) {
        mineFailed = std::current_exception();
    }
    const auto mineDone = Shared::Clock::now();
    const std::chrono::nanoseconds mineOnCore = onCore() - callerOnCore;
    // Their half not begun yet (the second thread may be waiting for a core that another program
    // holds): this thread runs it, and never waits for a core that is not free.
    const bool claimed = shared_->claim(number);
    if (claimed) {
        try {
            theirs();
        } catch (...) {
            theirsFailed = std::current_exception();
        }
        shared_->done.store(number, std::memory_order_release);
    }
    shared_->finish();
    const auto allDone = Shared::Clock::now();
    const Shared::Clock::duration offCore = (allDone - posted) - (onCore() - callerOnCore);
    const Shared::Clock::duration gain =
        (claimed ? -Shared::Clock::duration(kClaimCost)
                 : std::min(shared_->theirsOnCore, mineOnCore) - (allDone - mineDone)) -
        std::max(offCore, Shared::Clock::duration(0));
    shared_->book(gain);
    if (mineFailed) std::rethrow_exception(mineFailed);
    if (theirsFailed) std::rethrow_exception(theirsFailed);
    if (shared_->error) std::rethrow_exception(std::exchange(shared_->error, nullptr));
}

}  // namespace gpl
