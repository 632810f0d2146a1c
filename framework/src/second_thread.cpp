#include "gpl/second_thread.h"

#include <algorithm>
#include <array>
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

// The judge of timed stages (SecondThread::Stage). A trial runs the stage kTrial.size() times, on
// one thread (false) and on two (true) in an order that a steady growth or shrinking of the stage
// from run to run favours neither; each side's time per unit of work is the median of its runs,
// which a run that another program delayed does not move far. Two threads are kept while they take
// at most kKeep of one thread's time, and taken back only when they take at most kTake: where the
// two are about even (a loaded machine, whose times scatter), one thread it is. The choice then
// holds for a stay of runs: kFirstStay after a trial that changed it, twice the last stay after one
// that confirmed it, up to kLongestStay; kSlowRuns runs in a row slower than kSlower times what the
// trial found bring the next trial forward.
constexpr std::array<bool, 8> kTrial{false, true, true, false, true, false, false, true};
constexpr double kKeep = 0.98;
constexpr double kTake = 0.95;
constexpr std::uint64_t kFirstStay = 64;
constexpr std::uint64_t kLongestStay = 1024;
constexpr double kSlower = 1.5;
constexpr int kSlowRuns = 4;

// The median of half a trial's runs.
double median(std::array<double, kTrial.size() / 2> v) {
    std::sort(v.begin(), v.end());
    return 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

std::int64_t nowNs() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

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
    bool timeWork = false;  ///< the work posted is to be timed on the second thread's core
    std::chrono::nanoseconds theirsOnCore{0};  ///< the second thread's last timed work's time on its core
    std::atomic<bool> stop{false};
    std::exception_ptr error;  ///< what the last work threw

    // The caller's account of what the second thread gives now (only the caller reads and writes it).
    using Clock = std::chrono::steady_clock;
    std::uint64_t aloneLeft = 0;     ///< hand-overs the caller is still to run alone
    std::uint64_t nextAlone = kFirstAlone;
    Clock::duration gained{0};       ///< since the last time alone, at most kCredit

    // The judge of timed stages (only the caller reads and writes it).
    bool judged = false;       ///< a stage has been timed: the judge chooses for the other stages
    bool inStage = false;      ///< a timed stage runs now: its hand-overs book nothing
    bool two = true;           ///< the choice
    int trialAt = 0;           ///< the next run's place in kTrial, or -1 between trials
    std::array<double, kTrial.size() / 2> trialOne{}, trialTwo{};  ///< a trial's times per unit of work (ns)
    int ones = 0, twos = 0;
    double found = 0.0;        ///< the choice's time per unit of work in the last trial (ns)
    int slowRuns = 0;
    std::uint64_t stayLeft = 0;
    std::uint64_t lastStay = 0;

    /// Whether the next timed run is on two threads.
    bool nextOnTwo() const { return trialAt >= 0 ? kTrial[static_cast<std::size_t>(trialAt)] : two; }
    /// Takes a timed run's time per unit of work (ns).
    void judge(bool onTwo, double perWork) {
        if (trialAt < 0) {
            slowRuns = perWork > kSlower * found ? slowRuns + 1 : 0;
            if (stayLeft > 0) --stayLeft;
            if (slowRuns >= kSlowRuns) stayLeft = 0;
            if (stayLeft == 0) trialAt = 0, ones = twos = 0, slowRuns = 0;
            return;
        }
        (onTwo ? trialTwo[static_cast<std::size_t>(twos++)] : trialOne[static_cast<std::size_t>(ones++)]) = perWork;
        if (static_cast<std::size_t>(++trialAt) < kTrial.size()) return;
        const double one = median(trialOne), both = median(trialTwo);
        const bool choice = both <= (two ? kKeep : kTake) * one;
        lastStay = choice == two && lastStay > 0 ? std::min(2 * lastStay, kLongestStay) : kFirstStay;
        stayLeft = lastStay;
        two = choice;
        found = two ? both : one;
        trialAt = -1;
    }

    /// True while the caller is to run both halves itself: outside a timed stage while the judge
    /// has chosen one thread, or while the account of the hand-overs says so (counts `hand-overs` of
    /// them).
    bool alone(std::uint64_t handOvers) {
        if (judged && !inStage && !two) return true;
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
    std::uint64_t post(const std::function<void()>* next, bool timed) {
        finish();
        std::uint64_t number = 0;
        {
            const std::lock_guard<std::mutex> lock(mutex);
            work = next;
            timeWork = timed;
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
            bool timed = false;
            {
                const std::lock_guard<std::mutex> lock(mutex);
                next = work;
                timed = timeWork;
                seen = posted.load(std::memory_order_relaxed);
            }
            spin = next == nullptr ? kWokenSpin : kSpin;  // woken: the hand-over comes after the preparations
            if (next != nullptr && claim(seen)) {
                const std::chrono::nanoseconds start = timed ? onCore() : std::chrono::nanoseconds(0);
                try {
                    (*next)();
                } catch (...) {
                    error = std::current_exception();
                }
                if (timed) theirsOnCore = onCore() - start;
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
    if (!shared_->alone(0) && shared_->started()) shared_->post(nullptr, false);
}

void SecondThread::run(bool use, const std::function<void()>& mine, const std::function<void()>& theirs,
                       std::uint64_t handOvers) {
    // In a timed stage the Stage has chosen already (a stage on one thread passes no SecondThread);
    // the account of the hand-overs still sends the caller alone where they lose, as outside.
    if (!use || shared_->alone(handOvers) || !shared_->started()) {
        mine();
        theirs();
        return;
    }
    const auto posted = Shared::Clock::now();
    const std::chrono::nanoseconds callerOnCore = onCore();
    const std::uint64_t number = shared_->post(&theirs, true);
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

SecondThread::Stage::Stage(SecondThread* second, std::size_t work)
    : timed_(second != nullptr && second->shared_->started() ? second : nullptr),
      use_(nullptr),
      work_(work),
      begun_(0) {
    if (timed_ == nullptr) return;
    Shared& shared = *timed_->shared_;
    shared.judged = true;
    shared.inStage = true;
    if (shared.nextOnTwo()) {
        use_ = timed_;
        shared.post(nullptr, false);  // woken to spin through the stage's preparations
    }
    begun_ = nowNs();
}

SecondThread::Stage::~Stage() {
    if (timed_ == nullptr) return;
    const double took = static_cast<double>(nowNs() - begun_);
    Shared& shared = *timed_->shared_;
    shared.inStage = false;
    shared.judge(use_ != nullptr, took / static_cast<double>(std::max<std::size_t>(work_, 1)));
}

}  // namespace gpl
