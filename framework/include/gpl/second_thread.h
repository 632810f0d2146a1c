// A second thread for stages that split their work into two halves that touch different data: the
// caller runs one half, the second thread the other, and both return before the caller goes on.
//
// A stage hands over work many times a step (the friction stage: once per sweep), so the thread is
// made once and kept. After a hand-over it spins for a hundred microseconds (the next hand-over then
// costs well under a microsecond), and then sleeps until the next one; a stage wakes it as it
// begins, so that its first hand-over finds it awake. Without a second thread
// (one was not asked for, or the system would not make one) the caller runs both halves itself,
// its own first: a stage whose halves touch different data gets the same result either way.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace gpl {

class SecondThread {
public:
    SecondThread() = default;
    ~SecondThread();
    /// Each engine has its own: a copy starts without a thread.
    SecondThread(const SecondThread&) {}
    SecondThread& operator=(const SecondThread&) { return *this; }

    /// Runs mine() here and theirs() on the second thread (made on first use), and returns when
    /// both have. With `use` false, or when no thread can be made, runs mine() and then theirs()
    /// here. An exception from theirs() is thrown here once mine() has ended.
    void run(bool use, const std::function<void()>& mine, const std::function<void()>& theirs);
    /// Makes the thread (on first use) and wakes it, so that it is spinning, not asleep, when the
    /// next run() comes: for a stage to call when it begins its preparations.
    void wake();

private:
    std::thread thread_;
    bool failed_ = false;  ///< the system would not make a thread: run everything here
    std::mutex mutex_;
    std::condition_variable wake_;
    const std::function<void()>* work_ = nullptr;
    std::atomic<std::uint64_t> posted_{0};  ///< hand-overs so far
    std::atomic<std::uint64_t> done_{0};    ///< hand-overs the thread has finished
    std::atomic<bool> stop_{false};
    std::exception_ptr error_;

    /// True once the thread runs (made now if need be).
    bool started();
    /// Hands work (nullptr: nothing, only wake) to the thread, once it has done the last.
    void post(const std::function<void()>* work);
    /// Returns once the thread has done everything posted.
    void finish();
    void loop();
};

}  // namespace gpl
