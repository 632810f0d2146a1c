// The second thread's judge of timed stages (second_thread.h): a stage that takes longer on two
// threads than on one runs on one, and one that takes less on two runs on two; and a stage that
// grows slower on its choice is tried again soon. And its account of the hand-overs: after a
// hand-over that lost, the caller runs both halves itself for a stay counted in hand-overs, of
// which a hand-over may stand for many.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <functional>
#include <thread>

#include "gpl/second_thread.h"

namespace gpl {
namespace {

using std::chrono::milliseconds;

// Runs `runs` timed stages of the same work, each taking `onOne` on one thread and `onTwo` on two;
// returns how many of the last `last` ran on two.
int stagesOnTwo(SecondThread& second, int runs, int last, milliseconds onOne, milliseconds onTwo) {
    int two = 0;
    for (int k = 0; k < runs; ++k) {
        const SecondThread::Stage stage(&second, 1000);
        const bool both = stage.second() != nullptr;
        std::this_thread::sleep_for(both ? onTwo : onOne);
        if (k >= runs - last) two += both ? 1 : 0;
    }
    return two;
}

TEST(SecondThread, TimedStagesRunOnTheThreadCountThatCostsLess) {
    // The first 8 runs are a trial on both; the cheaper is kept for the stay that follows (64 runs).
    SecondThread slowerOnTwo;
    EXPECT_EQ(stagesOnTwo(slowerOnTwo, 20, 12, milliseconds(10), milliseconds(40)), 0);
    EXPECT_FALSE(slowerOnTwo.helps());  // and the other stages take their one-thread paths
    SecondThread fasterOnTwo;
    EXPECT_EQ(stagesOnTwo(fasterOnTwo, 20, 12, milliseconds(40), milliseconds(10)), 12);
    EXPECT_TRUE(fasterOnTwo.helps());
    // Two threads that turn slower (another program takes the second core) lose the choice at a
    // trial that the first slow runs bring forward (early in the stay), and one thread holds
    // for the stay after it.
    EXPECT_EQ(stagesOnTwo(fasterOnTwo, 20, 8, milliseconds(20), milliseconds(50)), 0);
    // A stage on one thread runs on one, untimed.
    const SecondThread::Stage none(nullptr, 1000);
    EXPECT_EQ(none.second(), nullptr);
}

// A hand-over that loses: theirs() sleeps on the second thread while the caller, its own half done
// at once, waits for it. False when the second thread did not begin theirs() within a second (the
// machine gave it no core): the loss is then not the one this test means.
bool loseAHandOver(SecondThread& second) {
    std::atomic<bool> begun{false};
    bool tookIt = true;
    const std::function<void()> mine = [&] {
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(1);
        while (!begun.load() && std::chrono::steady_clock::now() < until) std::this_thread::yield();
        tookIt = begun.load();
    };
    const std::function<void()> theirs = [&] {
        begun.store(true);
        std::this_thread::sleep_for(milliseconds(5));
    };
    second.run(true, mine, theirs);
    return tookIt;
}

// How many more hand-overs the caller runs alone: helps() answers for one hand-over each time.
int handOversLeftAlone(SecondThread& second) {
    int left = 0;
    while (!second.helps() && left < 100000) ++left;
    return left;
}

TEST(SecondThread, AHandOverThatStandsForManyShortensTheStayAlone) {
    // A stay alone counts hand-overs: one that stands for 8 (a step's sweeps at once) takes 8 of
    // them, so that the stay lasts as many sweeps whichever way a stage hands them over.
    SecondThread one, eight;
    if (!loseAHandOver(one) || !loseAHandOver(eight)) GTEST_SKIP() << "the second thread found no core within a second";
    const std::function<void()> nothing = [] {};
    one.run(true, nothing, nothing, 1);
    eight.run(true, nothing, nothing, 8);
    const int leftAfterOne = handOversLeftAlone(one);
    const int leftAfterEight = handOversLeftAlone(eight);
    EXPECT_GE(leftAfterOne, 8) << "a lost hand-over sends the caller alone for a while";
    EXPECT_EQ(leftAfterOne - leftAfterEight, 7) << "the hand-over standing for 8 took 8 of the stay";
}

}  // namespace
}  // namespace gpl
