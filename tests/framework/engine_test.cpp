#include "gpl/engine.h"
#include "gpl/runner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

namespace gpl {
namespace {

TEST(Engine, DefaultsAreDocumented) {
    PhysicsEngine e;
    EXPECT_EQ(e.timeStep(), kDefaultTimeStep);
    EXPECT_EQ(e.gravity(), Vec3(0.0, -9.81, 0.0));
    EXPECT_TRUE(e.stageActive(Stage::ConstantAcceleration));
    EXPECT_TRUE(e.stageActive(Stage::Integration));
}

TEST(Engine, RejectsBadSettings) {
    PhysicsEngine e;
    EXPECT_THROW(e.setTimeStep(0.0), std::invalid_argument);
    EXPECT_THROW(e.setTimeStep(-0.01), std::invalid_argument);
    EXPECT_THROW(e.setTimeStep(std::numeric_limits<double>::quiet_NaN()), std::invalid_argument);
    EXPECT_THROW(e.setTimeStep(std::numeric_limits<double>::infinity()), std::invalid_argument);
    EXPECT_THROW(e.setGravity(Vec3(0.0, std::numeric_limits<double>::quiet_NaN(), 0.0)), std::invalid_argument);
    EXPECT_EQ(e.timeStep(), kDefaultTimeStep);
}

TEST(Engine, RejectsBadBodiesAndDuplicateNames) {
    PhysicsEngine e;
    e.add(sphere("ball", 0.5, 1.0));
    EXPECT_THROW(e.add(sphere("ball", 0.5, 1.0)), std::invalid_argument);
    Body bad = sphere("bad", 0.5, 1.0);
    bad.position.y() = std::numeric_limits<double>::infinity();
    EXPECT_THROW(e.add(bad), std::invalid_argument);
    EXPECT_EQ(e.bodies().size(), 1u);
    EXPECT_THROW(e.body("nobody"), std::out_of_range);
}

TEST(Engine, ConstantAccelerationIsSetNotSummedAndSkipsStatic) {
    PhysicsEngine e;
    e.add(sphere("light", 0.5, 0.1));
    e.add(box("heavy", {1.0, 1.0, 1.0}, 1000.0));
    e.add(box("wall", {1.0, 1.0, 1.0}, 1.0).makeStatic());
    for (int i = 0; i < 3; ++i) e.updateConstantAcceleration();
    EXPECT_EQ(e.body("light").acceleration, e.gravity());
    EXPECT_EQ(e.body("heavy").acceleration, e.gravity());
    EXPECT_EQ(e.body("wall").acceleration, Vec3::Zero());
    e.setGravity(Vec3(0.0, -1.62, 0.0));
    e.updateConstantAcceleration();
    EXPECT_EQ(e.body("light").acceleration, Vec3(0.0, -1.62, 0.0));
}

TEST(Engine, StagesAreRequiredAndEnabled) {
    PhysicsEngine e;
    e.setRequiredStages({Stage::Integration});
    EXPECT_FALSE(e.stageActive(Stage::ConstantAcceleration));
    e.setRequiredStages({Stage::Integration, Stage::ConstantAcceleration});
    e.setStageEnabled(Stage::ConstantAcceleration, false);
    EXPECT_FALSE(e.stageActive(Stage::ConstantAcceleration));
    e.setStageEnabled(Stage::ConstantAcceleration, true);
    EXPECT_TRUE(e.stageActive(Stage::ConstantAcceleration));
    EXPECT_EQ(e.requiredStages().names(), "gravity, integrate");
}

TEST(Engine, WorldDiagnosticsSumTheBodies) {
    PhysicsEngine e;
    e.add(sphere("a", 0.5, 2.0).at({0.0, 1.0, 0.0}).moving({3.0, 0.0, 0.0}));
    e.add(sphere("b", 0.5, 1.0).at({0.0, 2.0, 0.0}).moving({0.0, -4.0, 0.0}));
    e.add(plane("floor", Vec3::UnitY()));
    EXPECT_DOUBLE_EQ(e.kineticEnergy(), 0.5 * 2.0 * 9.0 + 0.5 * 1.0 * 16.0);
    EXPECT_DOUBLE_EQ(e.potentialEnergy(), 2.0 * 9.81 * 1.0 + 1.0 * 9.81 * 2.0);
    EXPECT_DOUBLE_EQ(e.totalEnergy(), e.kineticEnergy() + e.potentialEnergy());
    EXPECT_TRUE(e.linearMomentum().isApprox(Vec3(6.0, -4.0, 0.0)));
}

TEST(Engine, StepAdvancesTimeAndCatchesNonFiniteState) {
    PhysicsEngine e;
    e.setTimeStep(0.05);
    e.add(sphere("ball", 0.5, 1.0));
    e.step();
    e.step();
    EXPECT_EQ(e.stepCount(), 2u);
    EXPECT_NEAR(e.time(), 0.1, 1e-15);
    // No stages, so that the reference integrator's own assertions (Debug builds) stay out of it.
    e.setRequiredStages({});
    e.bodies()[0].velocity.x() = std::numeric_limits<double>::quiet_NaN();
    try {
        e.step();
        FAIL() << "no SimulationError";
    } catch (const SimulationError& error) {
        EXPECT_NE(std::string(error.what()).find("ball"), std::string::npos) << error.what();
    }
}

TEST(Runner, AStoppedRunSaysWhyFirstAndSummarisesOnlyFiniteSteps) {
    PhysicsEngine e;
    e.setRequiredStages({});  // no hooks run: the NaN below survives into the step's check
    e.add(sphere("ball", 0.5, 1.0).at({0.0, 5.0, 0.0}));
    e.bodies()[0].velocity.x() = std::numeric_limits<double>::quiet_NaN();
    const RunSummary none = run(e, 10, nullptr);
    EXPECT_EQ(none.steps, 0u);
    const std::string text = describe(none, e);
    EXPECT_EQ(text.rfind("stopped early: body 'ball' is no longer finite after step 1", 0), 0u) << text;
    EXPECT_EQ(text.find("nan"), std::string::npos) << text;
    EXPECT_EQ(text.find("steps:"), std::string::npos) << "no finite step to summarise:\n" << text;

    RunSummary some;
    some.steps = 3;
    some.simulatedTime = 0.03;
    some.initialEnergy = some.finalEnergy = 49.05;
    some.error = "body 'ball' is no longer finite after step 4 (t = 0.04 s): check integrator()";
    const std::string three = describe(some, e);
    EXPECT_EQ(three.rfind("stopped early: body 'ball' is no longer finite after step 4", 0), 0u) << three;
    EXPECT_NE(three.find("the 3 finite steps:\nsteps: 3 of h"), std::string::npos) << three;
}

TEST(Engine, FiniteBodiesWhoseSumOverflowsAreFinite) {
    // allFinite() adds every position and velocity up first; numbers near the largest double add
    // up to infinity although each is finite, and that must not stop the simulation.
    PhysicsEngine e;
    e.setRequiredStages({});
    const double huge = 0.9 * std::numeric_limits<double>::max();
    e.add(sphere("far", 0.5, 1.0).at(Vec3(huge, 0.0, 0.0)));
    e.add(sphere("farther", 0.5, 1.0).at(Vec3(huge, 0.0, 0.0)).moving(Vec3(huge, 0.0, 0.0)));
    EXPECT_TRUE(e.allFinite());
    EXPECT_NO_THROW(e.step());
    e.bodies()[1].position.y() = std::numeric_limits<double>::infinity();
    EXPECT_FALSE(e.allFinite());
    e.bodies()[1].position.y() = 0.0;
    e.bodies()[0].velocity.z() = -std::numeric_limits<double>::infinity();
    EXPECT_FALSE(e.allFinite());
}

TEST(Engine, RemovingABodyTakesItsSpringsAndConstraintsAlong) {
    PhysicsEngine e;
    e.add(box("anchor", {0.1, 0.1, 0.1}, 1.0).makeStatic());
    e.add(sphere("a", 0.2, 1.0).at({1.0, 0.0, 0.0}));
    e.add(sphere("b", 0.2, 1.0).at({2.0, 0.0, 0.0}));
    e.addSpring("anchor", "a", 10.0);
    e.addSpring("a", "b", 10.0);
    e.addDistanceConstraint("anchor", "b");
    e.remove(1);  // "a"
    ASSERT_EQ(e.springs().size(), 0u);
    ASSERT_EQ(e.distanceConstraints().size(), 1u);
    EXPECT_EQ(e.bodies()[e.distanceConstraints()[0].b].name, "b") << "renumbered";
    EXPECT_NO_THROW(e.step());
}

TEST(Engine, NotImplementedIsRecordedOncePerHook) {
    PhysicsEngine e;
    e.notImplemented("integrator()");
    e.notImplemented("integrator()");
    e.notImplemented("simulationTimestep()");
    EXPECT_EQ(e.missingHooks().size(), 2u);
    EXPECT_EQ(e.missingHooks().count("integrator()"), 1u);
}

}  // namespace
}  // namespace gpl
