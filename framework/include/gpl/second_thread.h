// A second thread for stages that split their work into two halves that touch different data: the
// caller runs one half, the second thread the other, and both return before the caller goes on.
//
// A stage hands over work many times a step (the friction stage: once per sweep), so the thread is
// made once and kept. After a hand-over it spins for half a millisecond (the next hand-over then
// costs well under a microsecond, and a step's stages come about that close after each other), and
// then sleeps until the next one. A stage wakes it as it begins, and it then spins through the
// stage's preparations (up to 20 ms), so that the first hand-over finds it awake: waking a thread
// that sleeps takes tens of microseconds. Without a second thread (one was not asked for, or the
// system would not make one) the caller runs both halves itself, its own first: a stage whose
// halves touch different data gets the same result either way. The caller does the same when its
// own half is done before the second thread has begun the other: on a machine whose other core is
// busy with another program, a stage then takes the time of one thread, not the wait for a core.
//
// Whether two threads pay is judged by what a whole stage costs, not by the hand-overs: two halves
// beside each other on two cores can take longer than one after the other on one (their bodies pass
// between the cores' caches, the cores share the machine with other programs), which no hand-over
// sees. A stage that runs alike on one thread or two times itself with a Stage: now and then it runs
// a few times on one thread and on two in turn (a trial), and keeps two threads only where their
// median time per unit of work is clearly below one thread's, one thread where the two are about
// even (second_thread.cpp says by how much). After a trial that confirms the choice the next comes
// twice as late, in stages, after one that changes it soon; a stage that grows clearly slower than
// its trial found brings the next trial forward. While one thread is the choice the second thread
// sleeps, and the other stages of the step (the broad phase, collision detection) take their
// one-thread paths too (helps()). And hand-over by hand-over, in a timed stage or not, the caller
// keeps account of what the second thread gained (the other half's time on the second thread's
// core, less the caller's wait for it), and runs both halves itself for a while once the second
// thread has cost more than it gained: the brake for a second core that another program takes
// between two trials, and the whole judge of a stage that does not time itself.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

namespace gpl {

class SecondThread {
public:
    SecondThread();
    ~SecondThread();
    /// Each engine has its own: a copy starts without a thread.
    SecondThread(const SecondThread&);
    SecondThread& operator=(const SecondThread&);

    /// Runs mine() here and theirs() on the second thread (made on first use), and returns when
    /// both have. With `use` false, when no thread can be made, or while the machine gives the
    /// second thread no core, runs mine() and then theirs() here. An exception from theirs() is
    /// thrown here once mine() has ended. `handOvers`: how many hand-overs this one stands for in
    /// the account's stays alone, which count hand-overs (a step's sweeps handed over at once count
    /// as that many sweeps, so that a stay alone lasts as many steps as a stage's that hands over
    /// once a sweep).
    void run(bool use, const std::function<void()>& mine, const std::function<void()>& theirs,
             std::uint64_t handOvers = 1);
    /// Whether run() hands theirs() to the second thread now; false without a thread, while the
    /// timed stages find one thread cheaper, and while the machine gives it no core. A stage may then
    /// take its one-thread path, whose result is the same.
    bool helps();
    /// Makes the thread (on first use) and wakes it, so that it is spinning, not asleep, when the
    /// next run() comes: for a stage to call when it begins its preparations.
    void wake();

    /// One run of a stage that runs alike on one thread or two, timed from its making to its end
    /// (the stage's scope). `work` measures the run's size (a friction stage's contact points), so
    /// that runs of different sizes compare by their time per unit of work.
    class Stage {
    public:
        /// `second` null: one thread, untimed.
        Stage(SecondThread* second, std::size_t work);
        ~Stage();
        Stage(const Stage&) = delete;
        Stage& operator=(const Stage&) = delete;
        /// The second thread, or nullptr where this run is on one thread: what the stage hands its
        /// halves to.
        SecondThread* second() const { return use_; }

    private:
        SecondThread* timed_;
        SecondThread* use_;
        std::size_t work_;
        std::int64_t begun_;  ///< ns, steady clock
    };

private:
    /// The thread and what it shares with the caller, owned (second_thread.cpp). Hidden, and held by
    /// a plain pointer, so that every file that includes the engine stays free of <thread>, <mutex>
    /// and <memory>, which would add to what every hook file and test compiles.
    struct Shared;
    Shared* shared_;
};

/// each(i) for every i in [0, count), for a loop whose steps touch different data: with `second`
/// (and it helps()), [0, count / 2) here and the rest on the second thread at once; otherwise one
/// plain loop here. The same result either way.
template <class Each>
void inHalves(SecondThread* second, std::size_t count, const Each& each) {
    const auto range = [&each](std::size_t from, std::size_t to) {
        for (std::size_t i = from; i < to; ++i) each(i);
    };
    if (second == nullptr || count < 2 || !second->helps()) {
        range(0, count);
        return;
    }
    const std::size_t half = count / 2;
    // Each captures one reference, which fits in std::function's own storage: nothing is allocated.
    const auto halves = [&range, half, count](bool first) { first ? range(0, half) : range(half, count); };
    const std::function<void()> mine = [&halves] { halves(true); };
    const std::function<void()> theirs = [&halves] { halves(false); };
    second->run(true, mine, theirs);
}

}  // namespace gpl
