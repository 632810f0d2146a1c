// Worksheet 2 autograder, the earlier hooks inside the whole step: simulationTimestep() and
// integrator() (worksheet 1) graded again where springs and switched-off stages are in play, so a
// hook that only works under gravity alone loses points here.
#include <cmath>
#include <sstream>
#include <string>

#include "gpl/engine.h"
#include "graded.h"

namespace gpl {
namespace {

class Worksheet2WholeStep : public ::testing::Test {
protected:
    PhysicsEngine engine;

    void TearDown() override {
        if (HasFailure() && !engine.missingHooks().empty()) {
            std::string hooks;
            for (const auto& h : engine.missingHooks()) hooks += " " + h;
            ADD_FAILURE() << "hooks still not implemented:" << hooks;
        }
    }
};

std::string str(const Vec3& v) {
    std::ostringstream out;
    out.precision(12);
    out << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
    return out.str();
}

GRADED_TEST(Worksheet2WholeStep, SpringOscillatesWithItsPeriod, 3,
            "integrator() must use each body's acceleration accumulator, which holds gravity AND the "
            "springs' accelerations, never gravity() itself.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall")) {
    // A 1 kg ball on a spring of k = 40 N/m under gravity, stepped with semi-implicit Euler (the
    // worksheet-1 integrator()). For x'' = -w^2 x this method turns the state by exactly
    // theta = acos(1 - h^2 w^2 / 2) per step, so the period is 2 pi h / theta (1.0002 s here).
    const double k = 40.0, m = 1.0, h = 0.01, w = std::sqrt(k / m);
    engine.setTimeStep(h);
    engine.setRequiredStages({Stage::ConstantAcceleration, Stage::Springs, Stage::Integration});
    engine.add(sphere("anchor", 0.05, 1.0).at({0.0, 8.0, 0.0}).makeStatic());
    const double rest = 8.0 - 1.0 - m * 9.81 / k;  // equilibrium height (m)
    const double amplitude = 0.5;                  // m
    engine.add(sphere("ball", 0.25, m).at({0.0, rest - amplitude, 0.0}));
    engine.addSpring("anchor", "ball", k, 0.0, 1.0);
    double previous = -amplitude, firstCrossing = -1.0, lastCrossing = -1.0, largest = 0.0;
    int crossings = 0;
    grading::steps(engine, 1000, [&](int i) {
        const double y = engine.body("ball").position.y() - rest;
        largest = std::max(largest, std::abs(y));
        if (previous < 0.0 && y >= 0.0) {  // upward through equilibrium, time by linear interpolation
            const double t = h * (i - 1 + previous / (previous - y));
            if (crossings == 0) firstCrossing = t;
            lastCrossing = t;
            ++crossings;
        }
        previous = y;
    });
    if (HasFailure()) return;
    ASSERT_GE(crossings, 5) << "the ball does not oscillate about y = " << rest << " m (it is at "
                            << str(engine.body("ball").position) << " after 10 s)";
    const double period = (lastCrossing - firstCrossing) / (crossings - 1);
    const double expected = 2.0 * M_PI * h / std::acos(1.0 - h * h * w * w / 2.0);
    // Interpolating crossings errs by O(h^2 w^2) of a step; a missing spring is off by 100 %.
    EXPECT_NEAR(period, expected, 1e-3 * expected) << "period of the spring oscillator (s)";
    // Semi-implicit Euler keeps the amplitude to within about h w / 2 (3 %) of its start.
    EXPECT_NEAR(largest, amplitude, 0.5 * h * w * amplitude + 1e-9) << "largest displacement (m)";
}

GRADED_TEST(Worksheet2WholeStep, SpringPairKeepsItsMomentum, 2,
            "With gravity switched off only the spring acts; its two forces are equal and opposite, so "
            "integrator() must leave the total momentum exactly as it was.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall")) {
    // Two free bodies (1 kg and 3 kg) on a stretched spring, drifting; no gravity stage.
    engine.setRequiredStages({Stage::Springs, Stage::Integration});
    engine.add(sphere("light", 0.2, 1.0).at({0.0, 5.0, 0.0}).moving({1.0, 0.5, 0.0}));
    engine.add(box("heavy", {0.3, 0.3, 0.3}, 3.0).at({2.0, 5.0, 0.0}).moving({-0.2, 0.0, 0.3}));
    engine.addSpring("light", "heavy", 25.0, 0.0, 1.0);
    const Vec3 momentum = engine.linearMomentum();
    const double startDistance = 2.0;
    double shortest = startDistance;
    grading::steps(engine, 300, [&](int step) {
        const int i = step - 1;
        // Each step adds h F to one body and -h F to the other: momentum changes only by rounding.
        const Vec3 now = engine.linearMomentum();
        ASSERT_LE((now - momentum).norm(), 1e-12 * (momentum.norm() + 10.0))
            << "step " << i + 1 << ": momentum " << str(now) << ", at the start " << str(momentum);
        shortest = std::min(shortest, (engine.body("light").position - engine.body("heavy").position).norm());
    });
    if (HasFailure()) return;
    // The spring pulls the bodies from 2 m towards its rest length of 1 m and beyond.
    EXPECT_LT(shortest, 1.0) << "the spring never pulled the bodies together: is the integrator moving them?";
}

GRADED_TEST(Worksheet2WholeStep, PendulumSwingsWithItsSmallAnglePeriod, 2,
            "positionVerlet() inside the whole step: gravity through the accumulator, the rod as a "
            "distance constraint projected after it; the period must be 2 pi sqrt(L / g) (1 + theta^2 / 16).",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall"),
            grading::dependsOn("Worksheet2.PositionVerletSecondOrder")) {
    // A bob on a 2 m rod released at 5 degrees, stepped by position Verlet with h = 0.01 s for 30 s.
    const double length = 2.0, angle = 5.0 * M_PI / 180.0, h = 0.01;
    engine.setTimeStep(h);
    engine.setIntegratorKind(Integrator::PositionVerlet);
    engine.setRequiredStages({Stage::ConstantAcceleration, Stage::Integration, Stage::Constraints});
    const Vec3 pivot(0.0, 5.0, 0.0);
    engine.add(sphere("pivot", 0.05, 1.0).at(pivot).makeStatic());
    engine.add(sphere("bob", 0.1, 1.0).at(pivot + length * Vec3(std::sin(angle), -std::cos(angle), 0.0)));
    engine.addDistanceConstraint("pivot", "bob");
    double previous = engine.body("bob").position.x(), first = -1.0, last = -1.0;
    int crossings = 0;
    grading::steps(engine, 3000, [&](int i) {
        const double x = engine.body("bob").position.x();
        if (previous < 0.0 && x >= 0.0) {
            const double t = h * (i - 1 + previous / (previous - x));
            if (crossings == 0) first = t;
            last = t;
            ++crossings;
        }
        previous = x;
    });
    if (HasFailure()) return;
    ASSERT_GE(crossings, 5) << "the pendulum does not swing through the vertical (bob at "
                            << str(engine.body("bob").position) << " after 30 s)";
    const double period = (last - first) / (crossings - 1);
    const double expected = 2.0 * M_PI * std::sqrt(length / 9.81) * (1.0 + angle * angle / 16.0);
    // The reference lands within 1e-4 of this (the step, the projection, the theta^4 term); an
    // integrator with the wrong force or a first-order step is off by more than 1e-3.
    EXPECT_NEAR(period, expected, 1e-3 * expected) << "period of the pendulum (s)";
}

GRADED_TEST(Worksheet2WholeStep, StagesSwitchedOffDoNothing, 2,
            "simulationTimestep() runs each stage only when stageActive(stage) says so: with gravity "
            "switched off a thrown ball flies straight on, with integration switched off nothing moves.",
            grading::dependsOn("Worksheet1.MatchesDiscreteFreeFall")) {
    const Vec3 x0(0.0, 3.0, 0.0), v0(2.0, 1.0, -1.0);
    engine.add(sphere("ball", 0.3, 2.0).at(x0).moving(v0));
    engine.setStageEnabled(Stage::ConstantAcceleration, false);
    const int n = 100;
    grading::steps(engine, n, [](int) {});
    const double h = engine.timeStep();
    const Vec3 straight = x0 + n * h * v0;
    // n additions of h v round to ~1e-14 of the distance; gravity would be off by n^2 h^2 g / 2 = 4.9 m.
    EXPECT_LE((engine.body("ball").position - straight).norm(), 1e-10 * straight.norm())
        << "with gravity off the ball is at " << str(engine.body("ball").position) << ", expected "
        << str(straight) << " (a straight line at constant velocity)";
    EXPECT_LE((engine.body("ball").velocity - v0).norm(), 1e-12 * v0.norm()) << "velocity with gravity off";

    engine.setStageEnabled(Stage::ConstantAcceleration, true);
    engine.setStageEnabled(Stage::Integration, false);
    const Vec3 before = engine.body("ball").position;
    grading::steps(engine, 10, [](int) {});
    EXPECT_EQ(engine.body("ball").position, before) << "with integration off nothing may move";
}

}  // namespace
}  // namespace gpl
