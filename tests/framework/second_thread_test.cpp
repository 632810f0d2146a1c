// The second thread's judge of timed stages (second_thread.h): a stage that takes longer on two
// threads than on one runs on one, and one that takes less on two runs on two; and a stage that
// grows slower on its choice is tried again soon.
#include <gtest/gtest.h>

#include <chrono>
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

}  // namespace
}  // namespace gpl
